! t414-sonine-diffusion-f.f90 - the Fortran bindings of the two-moment velocity correlation
! (bindings/granary.f90): gran_theory_diffusion_approx (elastic hard spheres: D2/D1 = 59/58),
! gran_theory_msd_hcs_approx and gran_theory_msd_approx (the closed form equals Eq. 4 from the HCS;
! the Maxwellian level equals gran_theory_msd_hcs), gran_theory_tamsd_approx (lag -> t_meas gives
! the MSD; Maxwellian = gran_theory_tamsd) and a refusal.
! Prints what it checks (tests/granary_test_f.f90); error stop 1 on failure.
program t414_sonine_diffusion_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix
  real(c_double) :: one(1), dm(1), ds(1), z(1), t0(2), a2(2), tau0, t(2), ma(2, 2), mb(2, 2), mc(2, 2), md(2, 2)
  real(c_double) :: ta(2, 1), tb(2, 1), lag(1)
  integer :: ierr

  one = 1
  z = 0
  call gran_mixture_create(mix, one, mass=one, sigma=one)
  call gran_theory_diffusion_approx(mix, int(GRAN_THEORY_MAXWELLIAN), [1.0_c_double], [0.0_c_double], z, dm)
  call gran_theory_diffusion_approx(mix, int(GRAN_THEORY_SONINE), [1.0_c_double], [0.0_c_double], z, ds)
  call expect(abs(ds(1) / dm(1) - 59.0_c_double / 58) < 1e-12_c_double, 'elastic: D2/D1 = 59/58')
  call gran_mixture_destroy(mix)

  call gran_mixture_create(mix, [1.0_c_double, 0.5_c_double], mass=[1.0_c_double, 10.0_c_double], &
                           sigma=[1.0_c_double, 2.0_c_double])
  call gran_mixture_set_restitution(mix, 0.7_c_double)
  call gran_theory_hcs_approx(mix, int(GRAN_THEORY_MAXWELLIAN), int(GRAN_HCS_NORM_MEAN), 1.0_c_double, t0, a2, tau0)
  t = [10.0_c_double, 1000.0_c_double]
  call gran_theory_msd_hcs(mix, t0, tau0, t, ma)
  call gran_theory_msd_hcs_approx(mix, int(GRAN_THEORY_MAXWELLIAN), t0, a2, tau0, t, mb)
  call expect(all(ma == mb), 'Maxwellian level = gran_theory_msd_hcs')
  call gran_theory_msd_hcs_approx(mix, int(GRAN_THEORY_SONINE), t0, a2, tau0, t, mc)
  call gran_theory_msd_approx(mix, int(GRAN_THEORY_SONINE), t0, t, 1e-9_c_double, md)
  call expect(all(abs(md / mc - 1) < 1e-6_c_double), 'Sonine: HCS closed form = Eq. 4')
  call expect(all(abs(mc / ma - 1) > 1e-3_c_double), 'Sonine MSD differs from the Maxwellian')
  lag = 0.999999999_c_double * t(2)
  call gran_theory_tamsd_approx(mix, int(GRAN_THEORY_SONINE), t0, a2, tau0, t(2), lag, 1e-10_c_double, ta)
  call expect(all(abs(ta(:, 1) / mc(:, 2) - 1) < 1e-6_c_double), 'Sonine TAMSD at lag -> t_meas = the Sonine MSD')
  call gran_theory_tamsd(mix, t0, tau0, t(2), [10.0_c_double], 1e-10_c_double, ta)
  call gran_theory_tamsd_approx(mix, int(GRAN_THEORY_MAXWELLIAN), t0, a2, tau0, t(2), [10.0_c_double], &
                                1e-10_c_double, tb)
  call expect(all(ta == tb), 'TAMSD: Maxwellian level = gran_theory_tamsd')
  call gran_theory_msd_hcs_approx(mix, 4, t0, a2, tau0, t, mc, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'approximation = 4 refused (GRAN_ERR_ARG)')
  call gran_mixture_destroy(mix)

  call test_finish('t414-sonine-diffusion-f')

end program t414_sonine_diffusion_f
