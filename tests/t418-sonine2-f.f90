! t418-sonine2-f.f90 - the Fortran bindings of the second Sonine approximation (bindings/granary.f90):
! gran_theory_hcs_sonine2, gran_theory_hcs_sonine_n (one species: a2, a3 of the linear second Sonine equations; binary: an HCS of the
! rates) and gran_theory_sonine2_rates, gran_theory_temperatures_sonine2 (stays at the HCS, reaches it from a Maxwellian
! start), gran_theory_msd_sonine2 (the late slope from the HCS), and refusals. Prints what it checks; error stop 1 on failure.
program t418_sonine2_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix
  real(c_double) :: one(1), t1(1), a1(1), b1(1), tau0, dens(2), mass(2), sig(2)
  real(c_double) :: t0(2), a2(2), a3(2), zeta(2), d2(2), d3(2), tn(2), an(4), taun
  real(c_double) :: tt(2), temp(2, 2), a2t(2, 2), a3t(2, 2), msd(2, 2), mtot(2), dk(2), dl
  integer :: ierr

  one = 1
  call gran_mixture_create(mix, one, mass=one, sigma=one)
  call gran_mixture_set_restitution(mix, 0.5_c_double)
  call gran_theory_hcs_sonine2(mix, int(GRAN_HCS_NORM_MEAN), 1.0_c_double, t1, a1, b1, tau0)
  call expect(abs(a1(1) - 0.044993978002290_c_double) < 1e-12_c_double, 'one species eps 0.5: a2 = 0.044994')
  call expect(abs(b1(1) + 0.017684168615936_c_double) < 1e-12_c_double, 'one species eps 0.5: a3 = -0.017684')
  call gran_mixture_destroy(mix)

  dens = [1.0_c_double, 0.5_c_double]
  mass = [1.0_c_double, 10.0_c_double]
  sig = [1.0_c_double, 2.0_c_double]
  call gran_mixture_create(mix, dens, mass=mass, sigma=sig)
  call gran_mixture_set_restitution(mix, 0.7_c_double)
  call gran_theory_hcs_sonine2(mix, int(GRAN_HCS_NORM_T1), 1.0_c_double, t0, a2, a3, tau0)
  call expect(abs(t0(2) / t0(1) / 1.799810119285_c_double - 1) < 1e-10_c_double, 'binary: T2/T1 = 1.799810119')
  call gran_theory_sonine2_rates(mix, t0, a2, a3, zeta, d2, d3)
  call expect(all(abs(0.5_c_double * zeta * tau0 - 1) < 1e-11_c_double), 'binary: zeta_k tau0/2 = 1')
  call expect(all(abs(d2 * tau0) < 1e-10_c_double) .and. all(abs(d3 * tau0) < 1e-10_c_double), &
              'binary: da2/dt = da3/dt = 0')
  tt = [10.0_c_double, 100.0_c_double] * tau0
  call gran_theory_temperatures_sonine2(mix, t0, tt, 1e-10_c_double, temp, a20=a2, a30=a3, a2=a2t, a3=a3t)
  call expect(all(abs(temp(:, 2) / (t0 / (1 + 100.0_c_double)**2) - 1) < 1e-8_c_double) .and. &
              all(abs(a2t(:, 2) - a2) < 1e-10_c_double) .and. all(abs(a3t(:, 2) - a3) < 1e-10_c_double), &
              'trajectory from the second Sonine HCS: Haff''s law, a2 and a3 constant')
  tt = [3e3_c_double, 1e4_c_double] * tau0
  call gran_theory_temperatures_sonine2(mix, [1.0_c_double, 5.0_c_double], tt, 1e-10_c_double, temp, a2=a2t, a3=a3t)
  call expect(abs(temp(2, 2) / temp(1, 2) / 1.799810119285_c_double - 1) < 1e-7_c_double .and. &
              all(abs(a2t(:, 2) - a2) < 1e-7_c_double) .and. all(abs(a3t(:, 2) - a3) < 1e-7_c_double), &
              'trajectory from a Maxwellian start reaches the second Sonine HCS')
  call gran_theory_temperatures_sonine2(mix, t0, tt, 1e-10_c_double, temp, a30=[0.0_c_double, 1.0_c_double], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'a30 = 1 refused (GRAN_ERR_ARG)')
  call gran_theory_temperatures_sonine2(mix, t0, tt, 1e-10_c_double, temp(:, 1:1), ierr=ierr)
  call expect(ierr /= 0, 'temp of the wrong shape refused')
  tt = [50.0_c_double, 500.0_c_double] * tau0
  call gran_theory_msd_sonine2(mix, t0, tt, 1e-9_c_double, msd, a20=a2, a30=a3, correlation_a2=.true., msd_total=mtot)
  call gran_theory_diffusion_approx(mix, int(GRAN_THEORY_SONINE), t0, a2, [2.0_c_double, 2.0_c_double] / tau0, dk)
  dl = tau0 * (log(501.0_c_double) - log(51.0_c_double))
  call expect(all(abs((msd(:, 2) - msd(:, 1)) / (6 * dl) / dk - 1) < 1e-6_c_double), &
              'gran_theory_msd_sonine2 from the second Sonine HCS: late slope 6 D_k(0) tau0')
  call expect(abs(mtot(2) / ((msd(1, 2) + 0.5_c_double * msd(2, 2)) / 1.5_c_double) - 1) < 1e-13_c_double, &
              'gran_theory_msd_sonine2: msd_total')
  call gran_theory_msd_sonine2(mix, t0, tt, 1e-9_c_double, msd, a30=[0.0_c_double, 1.0_c_double], ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'gran_theory_msd_sonine2: a30 = 1 refused (GRAN_ERR_ARG)')
  call gran_theory_msd_sonine2(mix, t0, tt, 1e-9_c_double, msd(:, 1:1), ierr=ierr)
  call expect(ierr /= 0, 'gran_theory_msd_sonine2: msd of the wrong shape refused')
  call gran_theory_hcs_sonine_n(mix, 3, int(GRAN_HCS_NORM_T1), 1.0_c_double, tn, an, taun)
  call expect(abs(tn(2) / tn(1) / 1.799810119285_c_double - 1) < 1e-10_c_double .and. &
              abs(an(1) - a2(1)) < 1e-10_c_double .and. abs(an(4) - a3(2)) < 1e-10_c_double, &
              'gran_theory_hcs_sonine_n(nmax = 3) = gran_theory_hcs_sonine2')
  call gran_theory_hcs_sonine_n(mix, 7, int(GRAN_HCS_NORM_T1), 1.0_c_double, tn, an, taun, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'nmax = 7 refused (GRAN_ERR_ARG)')
  call gran_theory_hcs_sonine2(mix, 9, 1.0_c_double, t0, a2, a3, tau0, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'norm = 9 refused (GRAN_ERR_ARG)')
  call gran_mixture_destroy(mix)

  call test_finish('t418-sonine2-f')
end program t418_sonine2_f
