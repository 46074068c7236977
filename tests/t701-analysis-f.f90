! t701-analysis-f.f90 - Fortran twin of t701-analysis (brief): TAMSD plan and one-shot against the
! direct sum and the ballistic exact result, Sonine a2 with and without masses, speed histogram
! normalisation, shape errors.
program t701_analysis_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  integer, parameter :: nt = 300, ntraj = 4
  real(c_double) :: xyz(3, nt, ntraj), a(nt), b(nt), step(3), a2, hist(20), axes(3, 6), vel(3, 2)
  type(gran_tamsd_plan) :: plan
  type(gran_rng) :: g
  integer :: i, j, l, ierr, nb

  ! ballistic trajectory R = R0 + v i dt: delta^2(L) = |v|^2 (L dt)^2
  do i = 1, nt
    xyz(:, i, 1) = [1d0, 2d0, 3d0] + [0.5d0, -1d0, 2d0] * (i - 1) * 0.1d0
  end do
  call gran_tamsd(xyz(:, :, 1:1), a)
  call require(a(1) == 0d0, 'lag 0 is 0')
  call require(all([(abs(a(l + 1) - 5.25d0 * (l * 0.1d0)**2) <= 1d-10 * 5.25d0 * (l * 0.1d0)**2, l = 1, nt - 1)]), &
               'ballistic TAMSD = |v|^2 (L dt)^2 to 1e-10')

  ! random walks: FFT plan (executed twice) equals the direct sum to 1e-10 relative
  call gran_rng_seed(g, 7_c_int64_t)
  do j = 1, ntraj
    xyz(:, 1, j) = 50d0
    do i = 2, nt
      call gran_rng_normal(g, step)
      xyz(:, i, j) = xyz(:, i - 1, j) + step
    end do
  end do
  call gran_tamsd_plan_create(nt, plan)
  call gran_tamsd_plan_execute(plan, xyz, a)
  call gran_tamsd_plan_execute(plan, xyz, a)
  call gran_tamsd_direct(xyz, b)
  call require(all(abs(a(2:) - b(2:)) <= 1d-10 * b(2:)), 'FFT TAMSD equals the direct sum')
  print '(a, es10.3)', 'largest relative difference: ', maxval(abs(a(2:) - b(2:)) / b(2:))
  call gran_tamsd_plan_execute(plan, xyz(:, 1:nt - 1, :), a, ierr)
  call require(ierr == GRAN_ERR_ARG, 'positions of another length than the plan give GRAN_ERR_ARG')
  call gran_tamsd_plan_destroy(plan)
  call require(.not. c_associated(plan%ptr), 'destroy nulls the handle')
  call gran_tamsd_plan_destroy(plan)

  ! Sonine a2: the six axis directions have one speed: a2 = 3/5 - 1
  axes = 0
  do i = 1, 3
    axes(i, 2 * i - 1) = 1
    axes(i, 2 * i) = -1
  end do
  call gran_sonine_a2(axes, a2)
  call require(abs(a2 + 0.4d0) < 1d-15, 'a2 = -0.4 for one speed')
  ! masses 1 and 4, v1 = (2, 0, 0), v2 = (0, -1, 0): mass-weighted flow u = (2/5, -4/5, 0),
  ! c1 = (8/5, 4/5, 0), c2 = (-2/5, -1/5, 0), E1 = 3.2, E2 = 4 * 0.2 = 0.8,
  ! a2 = (3/5) ((3.2^2 + 0.8^2)/2) / 2^2 - 1 = -0.184
  vel(:, 1) = [2d0, 0d0, 0d0]
  vel(:, 2) = [0d0, -1d0, 0d0]
  call gran_sonine_a2(vel, a2, mass=[1d0, 4d0])
  call require(abs(a2 + 0.184d0) < 1d-14, 'a2 with masses (hand computed -0.184)')
  call gran_sonine_a2(vel, a2, mass=[1d0], ierr=ierr)
  call require(ierr == GRAN_ERR_ARG, 'mass of the wrong size gives GRAN_ERR_ARG')
  call gran_sonine_a2(reshape([1d0, 1d0, 1d0, 1d0, 1d0, 1d0], [3, 2]), a2, ierr=ierr)
  call require(ierr == GRAN_ERR_DOMAIN, 'no spread gives GRAN_ERR_DOMAIN')

  ! histogram: sum hist dc + beyond / n = 1
  call gran_speed_histogram(reshape(xyz, [3, nt * ntraj]), 30d0, 2d0, hist, nb)
  call require(abs(sum(hist) * 0.1d0 + real(nb, c_double) / (nt * ntraj) - 1) < 1d-12, 'histogram normalisation')
  call gran_speed_histogram(axes(1:2, :), 1d0, 2d0, hist, nb, ierr)
  call require(ierr == GRAN_ERR_ARG, 'v(2, n) gives GRAN_ERR_ARG')
  call gran_speed_histogram(axes, -1d0, 2d0, hist, nb, ierr)
  call require(ierr == GRAN_ERR_ARG, 'negative scale gives GRAN_ERR_ARG')
  call test_finish('t701-analysis-f')
end program t701_analysis_f
