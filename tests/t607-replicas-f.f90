! t607-replicas-f.f90 - replicas and threads from Fortran: set and read back the replicas of a
! scene, set and read the thread count, run three replicas and get the mean beside its standard
! error (resumed from a checkpoint with another thread count: the same result), and exact error
! codes for bad arguments.
program t607_replicas_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
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
  call require(r == 2 .and. .not. keep, 'the scene has 2 replicas, not kept')
  call gran_scene_set_replicas(scene, 3, .true.)
  call gran_scene_replicas(scene, r, keep)
  call require(r == 3 .and. keep, 'set_replicas: 3 replicas, kept')
  call gran_set_threads(2)
  call gran_get_threads(nth)
  call require(nth == 2, 'set_threads(2) reads back 2')

  ctl%stop_after_checkpoints = 1
  call gran_scene_run(scene, checkpoint=trim(ckp), ctl=ctl, result=res)
  call require(res%finished == 0, 'the run stops after its first checkpoint')
  call gran_set_threads(1)
  call gran_scene_resume(trim(ckp), result=res)
  call require(res%finished == 1 .and. res%time == 4.0d0, 'the resumed run (1 thread) finishes at t_end')
  open(unit=10, file=trim(outp), status='old', iostat=ierr)
  call require(ierr == 0, 'the output file exists')
  close(10, status='delete')

  ! exact error codes
  call gran_scene_set_replicas(scene, 0, .false., ierr)
  call require(ierr == GRAN_ERR_ARG, '0 replicas: GRAN_ERR_ARG')
  call require(index(gran_last_error_message(), 'replicas') > 0, 'the message names replicas')
  call gran_set_threads(-3, ierr)
  call require(ierr == GRAN_ERR_ARG, '-3 threads: GRAN_ERR_ARG')
  call gran_set_threads(0)
  call gran_scene_destroy(scene)
  deallocate(text)
  call test_finish('t607-replicas-f')
end program t607_replicas_f
