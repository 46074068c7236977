! t803-srd-f.f90 - the GSRD engine from Fortran: every wrapper of the GSRD section (options,
! create, advance, observe, stress reset, particle views, S(k), velocity profile, checkpoint
! write/read, destroy),
! with physics checks: particle number exact, momentum conserved to 1e-12, the energy ledger closed
! to 1e-12 for eps < 1, a restart that continues bit for bit; struct sizes against the C library;
! bad input (alpha = 0) returns GRAN_ERR_ARG through ierr.
program t803_srd_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: srd, srd2
  type(gran_srd_options) :: opt
  type(gran_srd_obs) :: ob, ob2
  real(c_double), pointer :: x(:), y(:), z(:), vx(:), vy(:), vz(:)
  real(c_double), pointer :: x2(:), y2(:), z2(:), vx2(:), vy2(:), vz2(:)
  real(c_double) :: p0(3), k(4), s(4)
  integer(c_int64_t) :: cnt(4), value, pc(6)
  real(c_double) :: pm(6)
  integer :: ierr
  character(len=*), parameter :: ckpt = '/tmp/granary-t803-f.ckp'

  call gran_abi_query('sizeof(gran_srd_options)', value)
  call expect(value == c_sizeof(opt), 'sizeof(gran_srd_options)')
  call gran_abi_query('sizeof(gran_srd_obs)', value)
  call expect(value == c_sizeof(ob), 'sizeof(gran_srd_obs)')

  call gran_srd_options_default(opt)
  call expect(opt%dim == 3 .and. opt%wall_axis == -1 .and. opt%cells(1) == 16, 'options_default')
  opt%cells = 6
  opt%eps = 0.8_c_double
  opt%sigma = 0.3_c_double
  opt%seed = 4242_c_int64_t
  call gran_srd_create(opt, srd)
  call gran_srd_particles(srd, x, y, z, vx, vy, vz)
  call expect(size(x) == 2160 .and. associated(vz), 'particle views')
  p0 = [sum(vx), sum(vy), sum(vz)]
  call gran_srd_advance(srd, 10_c_int64_t)
  call gran_srd_stress_reset(srd)
  call gran_srd_observe(srd, ob)
  call expect(ob%n == 2160 .and. ob%steps == 10, 'observe: n and steps')
  call expect(maxval(abs(ob%momentum - p0)) < 1e-12_c_double * sum(abs(vx) + abs(vy) + abs(vz)), 'momentum')
  call expect(abs(ob%ledger_error) < 1e-12_c_double, 'energy ledger')
  call expect(ob%e_collisions < 0, 'dissipation recorded')
  call gran_srd_structure_factor(srd, k, s, cnt)
  call expect(all(cnt > 0) .and. all(s > 0), 'structure factor')

  ! velocity profile: counts add up to N, count-weighted means to the total momentum
  call gran_srd_velocity_profile(srd, 2, 0, pm, pc)
  call expect(sum(pc) == ob%n, 'velocity profile: counts')
  call gran_srd_particles(srd, x, y, z, vx, vy, vz)
  call expect(abs(sum(pm * real(pc, c_double)) - sum(vx)) < 1e-12_c_double * sum(abs(vx)), 'velocity profile: momentum')
  call gran_srd_velocity_profile(srd, 3, 0, pm, pc, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'velocity profile: bad axis')

  call gran_srd_checkpoint_write(srd, ckpt, '/srd')
  call gran_srd_checkpoint_read(ckpt, '/srd', srd2)
  call gran_srd_advance(srd, 7_c_int64_t)
  call gran_srd_advance(srd2, 7_c_int64_t)
  call gran_srd_particles(srd, x, y, z, vx, vy, vz)
  call gran_srd_particles(srd2, x2, y2, z2, vx2, vy2, vz2)
  call expect(all(x == x2) .and. all(vz == vz2) .and. all(vy == vy2), 'restart bit for bit')
  call gran_srd_observe(srd, ob)
  call gran_srd_observe(srd2, ob2)
  call expect(ob%energy == ob2%energy, 'restart energy')
  call gran_srd_destroy(srd2)
  call gran_srd_checkpoint_read(ckpt, '/other', srd2, ierr)
  call expect(ierr == GRAN_ERR_IO .and. .not. c_associated(srd2), 'checkpoint: a missing group is refused')
  call gran_srd_checkpoint_write(srd, ckpt, '/', ierr)
  call expect(ierr == GRAN_ERR_ARG, 'checkpoint: the root is no group for a state')
  call gran_srd_destroy(srd)
  call expect(.not. c_associated(srd), 'destroy nulls')
  open(unit=11, file=ckpt, status='old')
  close(11, status='delete')

  opt%creation = GRAN_SRD_CREATE_CELLS
  call gran_srd_create(opt, srd)
  call gran_srd_particles(srd, x, y, z, vx, vy, vz)
  call expect(size(x) == 2160 .and. abs(sum(vx)) < 1e-12_c_double * sum(abs(vx)), 'creation by cells: N and momentum')
  call expect(all(int(x(2:)) + 6 * int(y(2:)) + 36 * int(z(2:)) >= &
                  int(x(:size(x) - 1)) + 6 * int(y(:size(x) - 1)) + 36 * int(z(:size(x) - 1))), &
              'creation by cells: in cell order')
  call gran_srd_advance(srd, 5_c_int64_t)
  call gran_srd_observe(srd, ob)
  call expect(ob%n == 2160 .and. abs(ob%ledger_error) < 1e-12_c_double, 'creation by cells: runs')
  call gran_srd_destroy(srd)
  opt%creation = 2
  call gran_srd_create(opt, srd, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'creation = 2 rejected')
  opt%creation = GRAN_SRD_CREATE_SERIAL

  opt%alpha_deg = 0
  call gran_srd_create(opt, srd, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'alpha = 0 rejected')
  call gran_srd_checkpoint_read('/nonexistent/x.ckp', '/srd', srd, ierr)
  call expect(ierr == GRAN_ERR_IO, 'missing checkpoint')

  call test_finish('t803-srd-f')
end program t803_srd_f
