! t501-dsmc-f.f90 - the DSMC engine from Fortran: a small binary mixture through every wrapper of
! the dsmc section (options, create, advance, observables, particle view, trajectories,
! checkpoint), with physics checks: zero total momentum, the energy ledger, collision counts that
! sum to the collisions, a restart that continues bit for bit; struct sizes and enum values against
! the C library (gran_abi_query); bad input returns its code through ierr.
program t501_dsmc_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix, sim, sim2
  type(gran_dsmc_options) :: opt
  type(gran_dsmc_stats) :: st, st2
  type(gran_particles), pointer :: p, p2
  real(c_double) :: temp(2), msd(2), msd_total, a2(2), P3(3), ek, e0, ed, tnow, pscale
  real(c_double), pointer :: xyz(:, :, :), v(:), v2(:), r(:), r2(:)
  real(c_double), allocatable :: vs1(:, :), vs2(:, :), vbad(:, :)
  integer(c_int32_t), pointer :: tsp(:)
  integer(c_int64_t) :: counts(2), offs(3), cc(2, 2), value, nbad(2)
  integer :: ierr
  character(len=*), parameter :: ckpt = '/tmp/granary-t501-f.h5'


  ! ABI: struct sizes and enum values as the C library sees them
  call gran_abi_query('sizeof(gran_dsmc_options)', value)
  call expect(value == c_sizeof(opt), 'sizeof(gran_dsmc_options)')
  call gran_abi_query('sizeof(gran_dsmc_stats)', value)
  call expect(value == c_sizeof(st), 'sizeof(gran_dsmc_stats)')
  call gran_abi_query('GRAN_SELECTOR_BIRD_PAPER', value)
  call expect(value == GRAN_SELECTOR_BIRD_PAPER, 'GRAN_SELECTOR_BIRD_PAPER')
  call gran_abi_query('GRAN_OBSERVE_TRAJECTORIES', value)
  call expect(value == GRAN_OBSERVE_TRAJECTORIES, 'GRAN_OBSERVE_TRAJECTORIES')

  call gran_mixture_create(mix, [0.08_c_double, 0.02_c_double], mass=[1.0_c_double, 4.0_c_double], &
                           sigma=[1.0_c_double, 1.5_c_double])
  call gran_mixture_set_restitution(mix, 0.8_c_double)

  call gran_dsmc_options_default(opt)
  call expect(opt%selector == GRAN_SELECTOR_LOWRANK .and. opt%observe == 0, 'options_default')
  opt%volume = 4.0e4_c_double
  opt%seed = 12345_c_int64_t
  opt%observe = ior(ior(GRAN_OBSERVE_DISPLACEMENT, GRAN_OBSERVE_COLLISION_COUNTS), GRAN_OBSERVE_TRAJECTORIES)
  opt%traj_per_species = 3
  opt%traj_dt = 0.5_c_double
  opt%traj_samples = 21
  opt%bound_refresh = 1000
  opt%speed_classes = GRAN_SPEED_CLASSES_OFF ! the live particle view (p is compared after an advance)

  ! bad input through ierr: unknown selector, negative counts, wrong array size
  opt%selector = 9
  call gran_dsmc_create(sim, mix, opt, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG .and. .not. c_associated(sim), 'unknown selector rejected')
  opt%selector = GRAN_SELECTOR_LOWRANK
  nbad = [-1_c_int64_t, 10_c_int64_t]
  call gran_dsmc_create(sim, mix, opt, counts=nbad, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'negative count rejected')
  call gran_dsmc_create(sim, mix, opt, T0=[1.0_c_double], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'wrong size of T0 rejected')

  call gran_dsmc_create(sim, mix, opt, T0=[1.0_c_double, 1.0_c_double])
  call gran_dsmc_counts(sim, counts)
  call expect(all(counts == [3200_c_int64_t, 800_c_int64_t]), 'counts = round(n_k V)')
  call gran_dsmc_species_offsets(sim, offs)
  call expect(all(offs == [0_c_int64_t, 3200_c_int64_t, 4000_c_int64_t]), 'species offsets')

  call gran_dsmc_advance(sim, 5.0_c_double)
  call gran_dsmc_get_stats(sim, st)
  call gran_dsmc_time(sim, tnow)
  call expect(tnow == 5.0_c_double .and. st%time == tnow, 'time after advance')
  call expect(st%nparticles == 4000 .and. st%nspecies == 2 .and. st%collisions > 5000, 'stats')
  call expect(st%acceptance > 0.05_c_double .and. st%acceptance <= 1.0_c_double, 'acceptance')

  call gran_dsmc_advance_collisions(sim, 2500_c_int64_t)
  call gran_dsmc_get_stats(sim, st2)
  call expect(st2%collisions == st%collisions + 2500, 'advance_collisions')

  ! ledger and momentum
  call gran_dsmc_energy(sim, ek, e0, ed)
  call expect(abs(e0 - ed - ek) <= 1.0e-12_c_double * e0 .and. ek < e0, 'energy ledger closes')
  call gran_dsmc_momentum(sim, P3)
  pscale = sqrt(2.0_c_double * e0 * (3200.0_c_double + 4.0_c_double * 800.0_c_double))
  call expect(all(abs(P3) <= 1.0e-12_c_double * pscale), 'zero total momentum')

  call gran_dsmc_temperatures(sim, temp)
  call gran_dsmc_sonine_a2(sim, a2)
  call gran_dsmc_msd(sim, msd, msd_total)
  call expect(all(temp > 0.0_c_double) .and. all(temp < 1.0_c_double), 'temperatures cooled')
  call expect(all(abs(a2) < 0.5_c_double), 'sonine a2')
  call expect(all(msd > 0.0_c_double) .and. &
              abs(msd_total - (3200 * msd(1) + 800 * msd(2)) / 4000) <= 1.0e-12_c_double * msd_total, 'msd')
  call gran_dsmc_collision_counts(sim, cc)
  call expect(cc(1, 2) == cc(2, 1) .and. cc(1, 1) + cc(1, 2) + cc(2, 2) == st2%collisions, 'collision counts')

  call gran_dsmc_particles(sim, p)
  call expect(p%n == 4000 .and. c_associated(p%r) .and. c_associated(p%t_last), 'particle view')

  ! one species' velocities copied out: the view's block of species 2, and with species 1 the
  ! total momentum; bad k and shape through ierr
  allocate(vs1(3, 3200), vs2(3, 800), vbad(3, 10))
  call gran_dsmc_species_velocities(sim, 1_c_int64_t, vs1)
  call gran_dsmc_species_velocities(sim, 2_c_int64_t, vs2)
  call c_f_pointer(p%v, v, [3 * p%n])
  call expect(all(reshape(vs2, [3 * 800]) == v(3 * 3200 + 1:)), 'species velocities: the view''s block')
  call expect(all(abs(sum(vs1, dim=2) + 4.0_c_double * sum(vs2, dim=2) - P3) <= 1.0e-12_c_double * pscale), &
              'species velocities: the momentum')
  call gran_dsmc_species_velocities(sim, 3_c_int64_t, vs2, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'species velocities: k out of range')
  call gran_dsmc_species_velocities(sim, 1_c_int64_t, vbad, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'species velocities: wrong shape')
  deallocate(vs1, vs2, vbad) ! a main program's allocatables are never freed by themselves (LeakSanitizer)

  call gran_dsmc_trajectories(sim, xyz, tsp)
  call expect(size(xyz, 1) == 3 .and. size(xyz, 2) == 21 .and. size(xyz, 3) == 6, 'trajectory shape')
  call expect(all(tsp == [0, 0, 0, 1, 1, 1]), 'tracer species')
  call expect(all(xyz(:, 1, :) == 0.0_c_double), 'first sample is the start')

  ! checkpoint, read back, continue both: bit for bit
  call gran_dsmc_checkpoint_write(sim, ckpt, '/engine')
  call gran_dsmc_checkpoint_read(sim2, ckpt, '/engine', mix)
  call gran_dsmc_advance(sim, 9.0_c_double)
  call gran_dsmc_advance(sim2, 9.0_c_double)
  call gran_dsmc_particles(sim2, p2)
  call c_f_pointer(p%v, v, [3 * p%n])
  call c_f_pointer(p2%v, v2, [3 * p2%n])
  call c_f_pointer(p%r, r, [3 * p%n])
  call c_f_pointer(p2%r, r2, [3 * p2%n])
  call expect(all(v == v2) .and. all(r == r2), 'restart continues bit for bit')
  call gran_dsmc_get_stats(sim, st)
  call gran_dsmc_get_stats(sim2, st2)
  call expect(st%collisions == st2%collisions .and. st%trials == st2%trials, 'restart counters')
  call gran_dsmc_destroy(sim2)
  call gran_dsmc_checkpoint_read(sim2, '/nonexistent/none.h5', '/engine', mix, ierr=ierr)
  call expect(ierr == GRAN_ERR_IO .and. .not. c_associated(sim2), 'missing checkpoint file')
  open(unit=10, file=ckpt, status='old')
  close(10, status='delete')

  call gran_dsmc_destroy(sim)
  call gran_dsmc_destroy(sim2)
  call expect(.not. c_associated(sim), 'destroy nulls the handle')
  call gran_mixture_destroy(mix)

  call test_finish('t501-dsmc-f')
end program t501_dsmc_f
