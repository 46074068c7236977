! t410-sonine-f.f90 - the Fortran bindings of the first Sonine approximation (bindings/granary.f90):
! gran_theory_hcs_approx (one species: van Noije & Ernst's a2; binary: an HCS of the Sonine rates),
! gran_theory_sonine_rates, gran_theory_temperatures_approx (reaches the HCS) and a refusal.
! Prints what it checks; error stop 1 on failure.
program t410_sonine_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix
  real(c_double) :: one(1), t1(1), a1(1), tau0, e, vne, dens(2), mass(2), sig(2)
  real(c_double) :: t0(2), a2(2), zeta(2), da(2), tt(1), temp(2, 1), a2t(2, 1)
  integer :: ierr

  e = 0.5_c_double
  vne = 16 * (1 - e) * (1 - 2 * e * e) / (81 - 17 * e + 30 * e * e * (1 - e))
  one = 1
  call gran_mixture_create(mix, one, mass=one, sigma=one)
  call gran_mixture_set_restitution(mix, e)
  call gran_theory_hcs_approx(mix, int(GRAN_THEORY_SONINE), int(GRAN_HCS_NORM_MEAN), 1.0_c_double, t1, a1, tau0)
  call expect(abs(a1(1) - vne) < 1e-12_c_double, 'one species: a2 = van Noije & Ernst')
  call gran_theory_hcs_approx(mix, int(GRAN_THEORY_MAXWELLIAN), int(GRAN_HCS_NORM_MEAN), 1.0_c_double, t1, a1, tau0)
  call expect(a1(1) == 0, 'Maxwellian level: a2 = 0')
  call gran_mixture_destroy(mix)

  dens = [1.0_c_double, 0.5_c_double]
  mass = [1.0_c_double, 10.0_c_double]
  sig = [1.0_c_double, 2.0_c_double]
  call gran_mixture_create(mix, dens, mass=mass, sigma=sig)
  call gran_mixture_set_restitution(mix, 0.7_c_double)
  call gran_theory_hcs_approx(mix, int(GRAN_THEORY_SONINE), int(GRAN_HCS_NORM_T1), 1.0_c_double, t0, a2, tau0)
  call expect(abs(t0(2) / t0(1) / 1.806332989_c_double - 1) < 1e-8_c_double, 'binary: T2/T1 = 1.806332989')
  call gran_theory_sonine_rates(mix, t0, a2, zeta, da)
  call expect(all(abs(0.5_c_double * zeta * tau0 - 1) < 1e-11_c_double), 'binary: zeta_k tau0/2 = 1')
  call expect(all(abs(da * tau0) < 1e-10_c_double), 'binary: da2/dt = 0')
  tt = 1e4_c_double * tau0
  call gran_theory_temperatures_approx(mix, int(GRAN_THEORY_SONINE), [1.0_c_double, 5.0_c_double], &
                                       [0.0_c_double, 0.0_c_double], tt, 1e-10_c_double, temp, a2t)
  call expect(abs(temp(2, 1) / temp(1, 1) / (t0(2) / t0(1)) - 1) < 1e-6_c_double, 'trajectory reaches the HCS ratio')
  call expect(all(abs(a2t(:, 1) - a2) < 1e-6_c_double), 'trajectory reaches the HCS a2')
  call gran_theory_hcs_approx(mix, 5, int(GRAN_HCS_NORM_T1), 1.0_c_double, t0, a2, tau0, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'approximation = 5 refused (GRAN_ERR_ARG)')
  call gran_mixture_destroy(mix)

  call test_finish('t410-sonine-f')
end program t410_sonine_f
