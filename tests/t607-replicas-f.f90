! t607-replicas-f.f90 - replicas and threads from Fortran: set and read back the replicas of a
! scene, set and read the thread count, run three replicas and get the mean beside its standard
! error (resumed from a checkpoint with another thread count: the same result), and exact error
! codes for bad arguments.
program t607_replicas_f
  use, intrinsic :: iso_c_binding
  use granary
  implicit none
  type(c_ptr) :: scene
  integer :: ierr, r, nth
  logical :: keep
  real :: x
  character(len=64) :: tag
  character(len=256) :: outp, ckp
  character(len=:), allocatable :: text
  character(len=1), parameter :: nl_ = achar(10)
  type(gran_run_control) :: ctl
  type(gran_run_result) :: res

  call random_seed()
  call random_number(x)
  write(tag, '(i0)') int(x * 1.0e9)
  outp = '/tmp/granary-t607f-' // trim(tag) // '.h5'
  ckp = '/tmp/granary-t607f-' // trim(tag) // '.ckpt'
  text = '[mixture]' // nl_ // 'nspecies = 2' // nl_ // 'mass = [1.0, 2.0]' // nl_ // &
         'density = [0.1, 0.05]' // nl_ // '[restitution]' // nl_ // 'eps = 0.7' // nl_ // &
         '[initial]' // nl_ // 'temperatures = [1.0, 1.5]' // nl_ // '[engine]' // nl_ // &
         'counts = [400, 200]' // nl_ // 'seed = 5' // nl_ // 't_end = 4.0' // nl_ // 'replicas = 2' // nl_ // &
         '[observables]' // nl_ // 'times = [0.5, 1.0, 2.0, 4.0]' // nl_ // &
         '[output]' // nl_ // 'path = "' // trim(outp) // '"' // nl_ // 'checkpoint_every = 2' // nl_
  call gran_scene_parse(text, 'f.toml', scene)
  call gran_scene_replicas(scene, r, keep)
  if (r /= 2 .or. keep) error stop 1
  call gran_scene_set_replicas(scene, 3, .true.)
  call gran_scene_replicas(scene, r, keep)
  if (r /= 3 .or. .not. keep) error stop 1
  call gran_set_threads(2)
  call gran_get_threads(nth)
  if (nth /= 2) error stop 1

  ctl%stop_after_checkpoints = 1
  call gran_scene_run(scene, checkpoint=trim(ckp), ctl=ctl, result=res)
  if (res%finished /= 0) error stop 1
  call gran_set_threads(1)
  call gran_scene_resume(trim(ckp), result=res)
  if (res%finished /= 1 .or. res%time /= 4.0d0) error stop 1
  open(unit=10, file=trim(outp), status='old', iostat=ierr)
  if (ierr /= 0) error stop 1
  close(10, status='delete')

  ! exact error codes
  call gran_scene_set_replicas(scene, 0, .false., ierr)
  if (ierr /= GRAN_ERR_ARG) error stop 1
  if (index(gran_last_error_message(), 'replicas') == 0) error stop 1
  call gran_set_threads(-3, ierr)
  if (ierr /= GRAN_ERR_ARG) error stop 1
  call gran_set_threads(0)
  call gran_scene_destroy(scene)
  deallocate(text)
  write(*, '(a)') 't607-replicas-f: ok'
end program t607_replicas_f
