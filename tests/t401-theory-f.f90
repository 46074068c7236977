! t401-theory-f.f90 - every Fortran binding of the theory section (bindings/granary.f90), with the
! values of Bodrova & Osinsky Fig. 2 and Fig. 5 and the C-side oracles. Prints what it checks; error stop 1
! on failure.
program t401_theory_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix, mix1, pl
  real(c_double) :: dens(2), mass(2), sig(2), t0(2), tau0, xi(2), tv(2), dd(2), itc, eps, beta, g2
  real(c_double) :: mm(2), ss(2), nn(2), e2(2, 2), temp(2, 3), times(3), msd(2, 3), tot(3), msd4(2, 3)
  real(c_double) :: tsam(2, 3)
  real(c_double) :: lag(4), tam(2, 4), d0(2, 4), xip(2, 4), msd1(3), tau31, red(2, 3), gam, hat
  real(c_double) :: g(2, 2), rates(2, 2), counts(2, 2, 3), x
  integer(c_int64_t) :: m
  integer :: ierr, model, k, j

  ! ---- mixture ---------------------------------------------------------------------------------
  dens = [0.1_c_double, 0.001_c_double]
  mass = [1.0_c_double, 100.0_c_double]
  sig = [1.0_c_double, 100.0_c_double**(1.0_c_double / 3)]
  call gran_mixture_create(mix, dens, mass=mass, sigma=sig)
  call gran_mixture_nspecies(mix, m)
  call expect(m == 2, 'nspecies = 2')
  call gran_mixture_get(mix, mm, ss, nn)
  call expect(all(mm == mass) .and. all(ss == sig) .and. all(nn == dens), 'get returns mass, sigma, density')
  call gran_mixture_set_restitution(mix, 0.5_c_double)
  call gran_mixture_restitution_model(mix, model)
  call expect(model == GRAN_RESTITUTION_CONSTANT, 'model constant')
  call gran_mixture_pair(mix, 1_c_int64_t, 2_c_int64_t, eps=eps, beta=beta, g2=g2)
  call expect(eps == 0.5_c_double .and. beta == 0 .and. g2 == 1, 'pair(1,2): eps 0.5, beta 0, g2 1')

  ! ---- Fig. 2: T_1(0) = 0.554, T_2(0) = 45.58755, tau0 = 19.258 (see t402 for the last digits) -----
  call gran_theory_hcs(mix, int(GRAN_HCS_NORM_MEAN), 1.0_c_double, t0, tau0)
  print '(a, 2f12.6, a, f10.5)', ' Fig. 2 HCS T =', t0, '  tau0 =', tau0
  call expect(abs(t0(1) - 0.554_c_double) < 5e-4_c_double, 'Fig. 2: T_1 rounds to 0.554')
  call expect(abs((0.1_c_double * t0(1) + 0.001_c_double * t0(2)) / 0.101_c_double - 1) &
              < 1e-14_c_double, 'Fig. 2: mean temperature 1')
  call gran_theory_hcs(mix, int(GRAN_HCS_NORM_T1), 0.554_c_double, t0, tau0)
  call expect(abs(t0(2) / 45.58755_c_double - 1) < 1e-5_c_double, 'Fig. 2: T_2 = 45.58755 (1e-5) with T_1 = 0.554')
  call expect(abs(tau0 / 19.258_c_double - 1) < 5e-5_c_double, 'Fig. 2: tau0 = 19.258 (5e-5)')
  call gran_theory_cooling_rates(mix, t0, xi)
  call expect(all(abs(xi * tau0 / 2 - 1) < 1e-12_c_double), 'equal cooling rates 2/tau0 (1e-12)')
  call gran_theory_tau_v(mix, t0, tv)
  call gran_theory_diffusion(mix, t0, dd)
  call expect(all(abs(dd / (t0 * tv / mass) - 1) < 1e-14_c_double), 'D = T tau_v/m (1e-14)')
  call gran_theory_collision_rate1(mix, t0, itc)
  call expect(abs(itc / (4 * 0.1_c_double * sqrt(acos(-1.0_c_double) * t0(1))) - 1) < 1e-14_c_double, 'Eq. 7 (1e-14)')

  ! ---- temperatures, MSD ------------------------------------------------------------------------
  times = [0.5_c_double, 10.0_c_double, 1e6_c_double]
  call gran_theory_temperatures(mix, t0, times, 1e-10_c_double, temp)
  do j = 1, 3
    do k = 1, 2
      call expect(abs(temp(k, j) * (1 + times(j) / tau0)**2 / t0(k) - 1) < 1e-9_c_double, 'Haff from the HCS (1e-9)')
    end do
  end do
  call gran_theory_msd_hcs(mix, t0, tau0, times, msd, tot)
  call gran_theory_msd(mix, t0, times, 1e-10_c_double, msd4)
  call expect(all(abs(msd4 / msd - 1) < 1e-8_c_double), 'Eq. 22 == Eq. 4 (1e-8)')
  call expect(all(abs(tot - (0.1_c_double * msd(1, :) + 0.001_c_double * msd(2, :)) / 0.101_c_double) &
              < 1e-14_c_double * tot), 'Eq. 3 total')
  call gran_theory_reduced_time(mix, t0, times, 1e-10_c_double, red)
  call expect(all(abs(red(1, :) / (tau0 * itc * log(1 + times / tau0)) - 1) < 1e-9_c_double), 'Eq. 18 (1e-9)')

  ! ---- TAMSD -------------------------------------------------------------------------------------
  lag = [1e-3_c_double, 1.0_c_double, 100.0_c_double, 999.0_c_double]
  call gran_theory_tamsd(mix, t0, tau0, 1000.0_c_double, lag, 1e-10_c_double, tam)
  call gran_theory_tamsd_parts(mix, t0, tau0, 1000.0_c_double, lag, 1e-10_c_double, delta0=d0, xi=xip)
  call expect(all(tam > 0) .and. all(tam(:, 2:) > tam(:, :3)), 'TAMSD positive, increasing')
  ! the same TAMSD on a sample grid (dt = 1e-3: 1e6+1 samples, the Euler-Maclaurin branch) is Eq. 27
  ! to about dt/tau0
  call gran_theory_tamsd_sampled(mix, t0, tau0, 1e-3_c_double, 1000001_c_int64_t, &
                                 [1_c_int64_t, 1000_c_int64_t, 100000_c_int64_t], 1e-10_c_double, tsam)
  call expect(all(abs(tsam / tam(:, 1:3) - 1) < 1e-3_c_double), 'sampled TAMSD -> Eq. 27 as dt -> 0')
  call expect(all(abs((d0(:, 3:) + xip(:, 3:)) / tam(:, 3:) - 1) &
              < 1e-8_c_double), 'delta0 + Xi = TAMSD at lag >> tau_v (1e-8)')

  ! ---- Eq. 31, tracer, collisions ---------------------------------------------------------------
  dens = [0.1_c_double, 0.0_c_double]
  call gran_mixture_create(mix1, dens, mass=mass, sigma=sig)
  call gran_mixture_set_restitution(mix1, 0.5_c_double)
  call gran_theory_hcs(mix1, int(GRAN_HCS_NORM_T1), 1.0_c_double, t0, tau0)
  print '(a, 2f12.5, a, f8.4)', ' Fig. 5 HCS T =', t0, '  tau0 =', tau0
  call expect(abs(t0(2) - 412.93_c_double) < 5e-3_c_double .and. &
              abs(tau0 - 11.3_c_double) < 5e-2_c_double, 'Fig. 5: T_2 = 412.93, tau0 = 11.3')
  call gran_theory_tau_v(mix1, t0, tv)
  call expect(abs(tv(2) - 1212) < 0.5_c_double, 'Fig. 5: tau_v2 = 1212')
  call gran_theory_msd_mono(mix1, 1.0_c_double, times, msd1, tau31)
  call gran_theory_msd_hcs(mix1, t0, tau0, times, msd)
  call expect(all(abs(msd1 / msd(1, :) - 1) < 1e-13_c_double) .and. &
              abs(tau31 / tau0 - 1) < 1e-13_c_double, 'Eq. 31 == Eq. 22 (1e-13)')
  call gran_theory_collision_rate1(mix1, t0, itc)
  call gran_theory_tracer_tau_v_hat(mix1, 2_c_int64_t, t0(2) / t0(1), hat)
  call expect(abs(hat / itc / tv(2) - 1) < 1e-13_c_double, 'Eq. 33 == tau_v2/tau_c (1e-13)')
  call gran_theory_tracer_gamma_approx(mix1, 2_c_int64_t, gam, ierr)
  call expect(ierr == GRAN_ERR_DOMAIN, 'Eqs. 34-35 outside validity: GRAN_ERR_DOMAIN')
  call gran_theory_mean_relative_speed(mix1, t0, g)
  call expect(abs(g(1, 2) / sqrt(8 / acos(-1.0_c_double) * (t0(1) + t0(2) / 100)) - 1) < 1e-15_c_double, 'Eq. 60')
  call gran_theory_collision_rates(mix1, t0, rates)
  call expect(rates(2, 2) == 0 .and. rates(1, 2) == rates(2, 1), 'collision rates: tracer-tracer 0, symmetric')
  call gran_theory_collision_counts(mix1, t0, 1e3_c_double, times, 1e-10_c_double, counts)
  call expect(all(abs(counts(1, 1, :) / (1e3_c_double * rates(1, 1) * tau0 * log(1 + times / tau0)) - 1) < 1e-9_c_double), &
               'counts = V rate tau0 log(1+t/tau0) (1e-9)')

  ! ---- setters, viscoelastic, powerlaw ----------------------------------------------------------
  e2 = reshape([0.9_c_double, 0.8_c_double, 0.8_c_double, 0.7_c_double], [2, 2])
  call gran_mixture_set_restitution_matrix(mix, e2)
  call gran_mixture_pair(mix, 2_c_int64_t, 2_c_int64_t, eps=eps)
  call expect(eps == 0.7_c_double, 'eps matrix (2,2) = 0.7')
  call gran_mixture_restitution_model(mix, model)
  call expect(model == GRAN_RESTITUTION_MATRIX, 'model matrix')
  call gran_mixture_set_g2_matrix(mix, e2 + 1)
  call gran_mixture_set_g2(mix, 1.2_c_double)
  call gran_mixture_pair(mix, 1_c_int64_t, 2_c_int64_t, g2=g2)
  call expect(g2 == 1.2_c_double, 'g2 = 1.2')
  call gran_mixture_set_viscoelastic(mix, 0.09_c_double)
  call gran_mixture_set_viscoelastic_matrix(mix, e2 / 10)
  call gran_mixture_pair(mix, 1_c_int64_t, 1_c_int64_t, beta=beta)
  call expect(abs(beta - 0.09_c_double) < 1e-17_c_double, 'beta matrix (1,1) = 0.09')
  call gran_mixture_set_viscoelastic_material(mix, 1e-3_c_double, 1e4_c_double, 0.3_c_double)
  call gran_mixture_restitution_model(mix, model)
  call expect(model == GRAN_RESTITUTION_VISCOELASTIC, 'model viscoelastic')
  call gran_viscoelastic_eps(0.3_c_double, x)
  call expect(abs(x - 0.902851771188985_c_double) < 1e-12_c_double, 'eps(0.3) = 0.902851771188985 (1e-12)')
  call gran_viscoelastic_eps_vn(0.09_c_double, -1.0_c_double, eps)
  call expect(eps == x, 'eps_vn(0.09, -1) = eps(0.3)')
  call gran_mixture_create_powerlaw(pl, 1000_c_int64_t, 1.0_c_double, 1.0_c_double, 0.1_c_double, 3.0_c_double)
  call gran_mixture_nspecies(pl, m)
  call expect(m == 1000, 'powerlaw M = 1000')
  call gran_mixture_destroy(pl)

  ! ---- errors: codes come back through ierr -----------------------------------------------------
  call gran_mixture_set_restitution(mix, 1.5_c_double, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'eps = 1.5 -> GRAN_ERR_ARG')
  call expect(index(gran_last_error_message(), 'eps') > 0, 'message names eps')
  call gran_theory_cooling_rates(mix, [1.0_c_double], xi, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'short T array -> GRAN_ERR_ARG')
  call gran_theory_hcs(mix, int(GRAN_HCS_NORM_MEAN), 1.0_c_double, t0, tau0, ierr)
  call expect(ierr == GRAN_ERR_DOMAIN, 'viscoelastic HCS -> GRAN_ERR_DOMAIN')
  call gran_mixture_pair(mix, 3_c_int64_t, 1_c_int64_t, eps=eps, ierr=ierr)
  call expect(ierr == GRAN_ERR_RANGE, 'pair index 3 -> GRAN_ERR_RANGE')
  call gran_mixture_create(pl, [real(c_double) ::], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'empty mixture -> GRAN_ERR_ARG')

  call gran_mixture_destroy(mix)
  call gran_mixture_destroy(mix1)
  call gran_mixture_destroy(pl)
  call expect(.not. c_associated(mix), 'destroy nulls the handle')
  call gran_mixture_destroy(mix)

  call test_finish('t401-theory-f')
end program t401_theory_f
