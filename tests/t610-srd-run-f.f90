! t610-srd-run-f.f90 - GSRD from Fortran through the run driver and the cell fields:
! gran_srd_fields on a 3-D engine (particles per cell sum to N, count x velocity sums to the total
! momentum, count x (d theta + |V|^2) / 2 to the kinetic energy, to 1e-12), a shape error through
! ierr, and an `[engine] type = "srd"` scene parsed and run with gran_scene_parse / gran_scene_run
! (its output times on the step grid, t_end = steps dt), and a bad scene (alpha = 0) refused with
! GRAN_ERR_PARSE naming the key.
program t610_srd_run_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: srd, scene
  type(gran_srd_options) :: opt
  type(gran_srd_obs) :: ob
  real(c_double), allocatable :: cnt(:), vel(:, :), th(:), short(:)
  real(c_double) :: p(3), e2, t0, t1, times(5)
  integer(c_int64_t) :: nc
  integer :: ierr, m, nt, nl, c
  character(len=*), parameter :: out = '/tmp/granary-t610-f.h5'
  character(len=1), parameter :: nl_ = achar(10)
  character(len=:), allocatable :: msg

  call gran_srd_options_default(opt)
  opt%cells = [5, 4, 3]
  opt%n0 = 6.0_c_double
  opt%eps = 0.9_c_double
  opt%sigma = 0.2_c_double
  opt%seed = 610_c_int64_t
  call gran_srd_create(opt, srd)
  call gran_srd_advance(srd, 12_c_int64_t)
  call gran_srd_observe(srd, ob)
  nc = 60
  allocate(cnt(nc), vel(3, nc), th(nc), short(nc - 1))
  call gran_srd_fields(srd, nc, cnt, vel, th)
  call expect(sum(cnt) == real(ob%n, c_double), 'fields: count sums to N')
  do c = 1, 3
    p(c) = sum(cnt * vel(c, :))
  end do
  call expect(maxval(abs(p - ob%momentum)) < 1e-12_c_double * ob%n, 'fields: momentum')
  e2 = 0
  do c = 1, int(nc)
    e2 = e2 + cnt(c) * (3 * th(c) + sum(vel(:, c)**2))
  end do
  call expect(abs(0.5_c_double * e2 - ob%energy) < 1e-12_c_double * ob%energy, 'fields: kinetic energy')
  call gran_srd_fields(srd, nc, count=short, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'fields: short array refused')
  call gran_srd_fields(srd, nc, temperature=th, ierr=ierr)
  call expect(ierr == GRAN_SUCCESS, 'fields: only the temperature')
  call gran_srd_destroy(srd)
  deallocate(cnt, vel, th, short)

  call gran_scene_parse('[engine]' // nl_ // 'type = "srd"' // nl_ // 'dimension = 2' // nl_ // 'cells = 8' // nl_ // &
                        'dt = 0.5' // nl_ // 'steps = 20' // nl_ // '[observables]' // nl_ // 'every = 5' // nl_ // &
                        '[output]' // nl_ // 'path = "' // out // '"' // nl_, 'f.toml', scene)
  call gran_scene_sizes(scene, m, nt, nl, t0, t1)
  call expect(nt == 5 .and. t0 == 0 .and. t1 == 10, 'scene sizes: 5 output times, t_end = steps dt')
  call gran_scene_times(scene, times)
  call expect(all(times == [0.0_c_double, 2.5_c_double, 5.0_c_double, 7.5_c_double, 10.0_c_double]), 'output times')
  call gran_scene_run(scene, checkpoint='', ierr=ierr)
  call expect(ierr == GRAN_SUCCESS, 'scene run')
  call gran_scene_destroy(scene)
  open(unit=11, file=out, status='old', iostat=ierr)
  call expect(ierr == 0, 'output written')
  if (ierr == 0) close(11, status='delete')

  call gran_scene_parse('[engine]' // nl_ // 'type = "srd"' // nl_ // 'cells = 4' // nl_ // 'alpha = 0' // nl_, &
                        'bad.toml', scene, ierr)
  msg = gran_last_error_message()
  call expect(ierr == GRAN_ERR_PARSE, 'bad scene: GRAN_ERR_PARSE')
  call expect(index(msg, "bad.toml:4: key 'engine.alpha'") > 0, 'bad scene: alpha named with its line')

  deallocate(msg)
  call test_finish('t610-srd-run-f')
end program t610_srd_run_f
