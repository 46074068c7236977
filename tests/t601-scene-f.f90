! t601-scene-f.f90 - the io bindings from Fortran: parse a scene, read its sizes, times, lags,
! text and output path, build its mixture and initial temperatures and engine options, run it
! with a progress callback, stop after a checkpoint and resume it, and get exact error codes.
module t601_progress
  use, intrinsic :: iso_c_binding
  use granary
  implicit none
  integer :: ncalls = 0
contains
  integer(c_int) function on_progress(p, params) bind(C)
    type(gran_run_progress), intent(in) :: p
    type(c_ptr), value :: params
    ncalls = ncalls + 1
    if (p%output_index /= ncalls .or. p%noutputs /= 4) then
      write(*, *) 'progress: bad indices', p%output_index, p%noutputs
      error stop 1
    end if
    if (c_associated(params)) continue
    on_progress = 0
  end function on_progress
end module t601_progress

program t601_scene_f
  use, intrinsic :: iso_c_binding
  use granary
  use t601_progress
  use granary_test_f
  implicit none
  type(c_ptr) :: scene, mix, sim
  integer :: ierr, m, nt, nl, have
  real(c_double) :: t0, t1, times(4), lags(2), T(2), tau0
  integer(c_int64_t) :: counts(2)
  character(len=:), allocatable :: text, path, msg
  character(len=64) :: tag
  character(len=1), parameter :: nl_ = achar(10)
  character(len=256) :: outp, ckp, line
  type(gran_run_control) :: ctl
  type(gran_run_result) :: res
  real :: r
  interface
    ! the theory and engine handles are released through their C functions
    function c_mixture_destroy(p) bind(C, name='gran_mixture_destroy') result(e)
      import :: c_ptr, c_int
      type(c_ptr), intent(inout) :: p
      integer(c_int) :: e
    end function c_mixture_destroy
    function c_dsmc_destroy(p) bind(C, name='gran_dsmc_destroy') result(e)
      import :: c_ptr, c_int
      type(c_ptr), intent(inout) :: p
      integer(c_int) :: e
    end function c_dsmc_destroy
  end interface
  ! a private output name (several builds may run this test at once)
  call random_seed()
  call random_number(r)
  write(tag, '(i0)') int(r * 1.0e9)
  outp = '/tmp/granary-t601f-' // trim(tag) // '.h5'
  ckp = '/tmp/granary-t601f-' // trim(tag) // '.ckpt'

  text = '[mixture]' // nl_ // 'nspecies = 2' // nl_ // 'mass = [1.0, 2.0]' // nl_ // &
         'density = [0.1, 0.05]' // nl_ // '[restitution]' // nl_ // 'eps = 0.7' // nl_ // &
         '[initial]' // nl_ // 'temperatures = [1.0, 1.5]' // nl_ // '[engine]' // nl_ // &
         'counts = [500, 250]' // nl_ // 'seed = 5' // nl_ // 't_end = 4.0' // nl_ // &
         '[observables]' // nl_ // 'times = [0.5, 1.0, 2.0, 4.0]' // nl_ // &
         'tamsd = { tracers = 3, dt = 0.25, samples = 13, lags = [0.25, 1.0] }' // nl_ // &
         '[output]' // nl_ // 'path = "' // trim(outp) // '"' // nl_ // 'checkpoint_every = 2' // nl_
  call gran_scene_parse(text, 'f.toml', scene)
  call gran_scene_sizes(scene, m, nt, nl, t0, t1)
  write(line, *) m, nt, nl, t0, t1
  call require(m == 2 .and. nt == 4 .and. nl == 2 .and. t0 == 0.0d0 .and. t1 == 4.0d0, &
               'sizes: 2 species, 4 times, 2 lags, t from 0 to 4:' // trim(line))
  call gran_scene_times(scene, times)
  call require(all(times == [0.5d0, 1.0d0, 2.0d0, 4.0d0]), 'output times')
  call gran_scene_lags(scene, lags)
  call require(all(lags == [0.25d0, 1.0d0]), 'TAMSD lags')
  call gran_scene_text(scene, msg)
  call require(msg == text, 'the scene text')
  call gran_scene_output_path(scene, path)
  call require(path == trim(outp), 'the output path')

  call gran_scene_mixture(scene, mix)
  call gran_scene_initial_temperatures(scene, mix, T, tau0)
  call require(all(T == [1.0d0, 1.5d0]), 'initial temperatures')
  block
    ! the engine options land in C memory laid out as gran_dsmc_options; only counts are read here
    integer(c_int64_t), target :: optbuf(16)
    call gran_scene_dsmc_options(scene, c_loc(optbuf), counts, have)
  end block
  call require(have == 1 .and. all(counts == [500_c_int64_t, 250_c_int64_t]), 'engine options: the counts')
  call gran_scene_dsmc(scene, mix, sim)
  call require(c_associated(sim), 'gran_scene_dsmc makes an engine')
  ierr = c_dsmc_destroy(sim)
  call require(ierr == 0, 'engine destroyed')
  ierr = c_mixture_destroy(mix)
  call require(ierr == 0, 'mixture destroyed')

  ! run with a progress callback, stop after the first checkpoint, then resume
  ctl%progress = c_funloc(on_progress)
  ctl%stop_after_checkpoints = 1
  call gran_scene_run(scene, checkpoint=trim(ckp), ctl=ctl, result=res)
  write(line, *) res%finished, res%checkpoints, ncalls
  call require(res%finished == 0 .and. res%checkpoints == 1 .and. ncalls == 2, &
               'stopped run: not finished, 1 checkpoint, 2 progress calls:' // trim(line))
  ctl%stop_after_checkpoints = 0
  call gran_scene_resume(trim(ckp), ctl=ctl, result=res)
  write(line, *) res%finished, ncalls, res%time
  call require(res%finished == 1 .and. ncalls == 4 .and. res%time == 4.0d0, &
               'resumed run: finished, 4 progress calls, t = 4:' // trim(line))
  open(unit=10, file=trim(outp), status='old', iostat=ierr)
  call require(ierr == 0, 'the output file exists')
  close(10, status='delete')

  call gran_scene_destroy(scene)

  ! exact error codes
  call gran_scene_parse('[mixture]' // nl_ // 'density = [0.1]' // nl_ // '[engine]' // nl_ // &
                        'counts = [10]' // nl_ // 't_end = -1.0' // nl_, 'bad.toml', scene, ierr)
  call require(ierr == GRAN_ERR_PARSE, 't_end = -1: GRAN_ERR_PARSE')
  msg = gran_last_error_message()
  call require(index(msg, 'engine.t_end') > 0 .and. index(msg, 'bad.toml:5') > 0, &
               'the message names the key and its line: ' // msg)
  call gran_scene_load('/nonexistent/x.toml', scene, ierr)
  call require(ierr == GRAN_ERR_IO, 'missing scene file: GRAN_ERR_IO')
  call gran_scene_resume('/nonexistent/x.ckpt', ierr=ierr)
  call require(ierr == GRAN_ERR_IO, 'missing checkpoint: GRAN_ERR_IO')
  call gran_scene_destroy(scene)
  call gran_scene_parse(text, 'f.toml', scene)
  call gran_scene_run(scene, output='/dev/null/o.h5', checkpoint='', ierr=ierr)
  call require(ierr == GRAN_ERR_IO, 'unwritable output: GRAN_ERR_IO')
  call gran_scene_destroy(scene)
  call require(.not. c_associated(scene), 'destroy nulls the handle')
  call gran_scene_destroy(scene) ! safe twice
  deallocate(text, path, msg)
  call test_finish('t601-scene-f')
end program t601_scene_f
