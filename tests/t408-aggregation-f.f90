! t408-aggregation-f.f90 - Fortran bindings of the aggregation kinetics (gran_theory_agg_fractions,
! gran_theory_aggregation, gran_theory_smoluchowski_constant) against closed forms: stick and
! shatter fractions, the constant-kernel solution, the E_agg = 0 limit (the mixture theory), mass
! conservation with truncation. error stop 1 on failure.
program t408_aggregation_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix
  real(c_double) :: fs, ff, q, n0(60), n(60, 2), ov(3, 2), t(2), tau, dens(3), t0(3), nn(3, 2), tt(3, 2), tm(3, 2)
  real(c_double) :: mass
  integer :: ierr, k

  call gran_theory_agg_fractions(1.0_c_double, 1.0_c_double, 2.0_c_double, 2.0_c_double, 1.0_c_double, &
                                 3.0_c_double, fs, ff)
  q = 0.5_c_double
  call expect(abs(fs - (1 - (1 + q) * exp(-q))) < 1e-14_c_double, 'stick fraction 1 - (1+q) e^-q')
  call expect(abs(ff - exp(-1.5_c_double)) < 1e-14_c_double, 'shatter fraction e^-w')
  call gran_theory_agg_fractions(-1.0_c_double, 1.0_c_double, 2.0_c_double, 2.0_c_double, 1.0_c_double, &
                                 3.0_c_double, fs, ff, ierr)
  call expect(ierr == GRAN_ERR_ARG, 'negative mass -> GRAN_ERR_ARG')

  n0 = 0
  n0(1) = 1
  t = [1.0_c_double, 4.0_c_double]
  call gran_theory_smoluchowski_constant(1.0_c_double, n0, t, 1e-11_c_double, n, ov)
  do k = 1, 2
    tau = t(k) / 2
    call expect(abs(n(5, k) / (tau**4 / (1 + tau)**6) - 1) < 1e-7_c_double, 'constant kernel n_5 (1e-7)')
    mass = sum([(real(k, c_double), k = 1, 60)] * n(:, k)) + ov(2, k)
    call expect(abs(mass - 1) < 1e-12_c_double, 'constant kernel mass closes (1e-12)')
  end do

  dens = [0.1_c_double, 0.03_c_double, 0.01_c_double]
  call gran_mixture_create(mix, dens)
  call gran_mixture_set_restitution(mix, 0.8_c_double)
  t0 = [1.0_c_double, 3.0_c_double, 0.5_c_double]
  call gran_theory_aggregation(mix, t0, 0.0_c_double, huge(1.0_c_double), 0.5_c_double, t, 1e-10_c_double, nn, tt)
  call gran_theory_temperatures(mix, t0, t, 1e-10_c_double, tm)
  call expect(maxval(abs(tt / tm - 1)) < 1e-7_c_double, 'E_agg = 0, E_frag = huge: mixture temperatures (1e-7)')
  call gran_theory_aggregation(mix, t0, 2.0_c_double, 3.0_c_double, 0.5_c_double, t, 1e-9_c_double, nn, tt, ov)
  do k = 1, 2
    mass = nn(1, k) + 2 * nn(2, k) + 3 * nn(3, k) + ov(2, k)
    call expect(abs(mass / 0.19_c_double - 1) < 1e-12_c_double, 'ballistic aggregation mass closes (1e-12)')
  end do
  call gran_theory_aggregation(mix, t0, 2.0_c_double, 3.0_c_double, 1.5_c_double, t, 1e-9_c_double, nn, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'eps_f = 1.5 -> GRAN_ERR_ARG')
  call gran_mixture_destroy(mix)

  call test_finish('t408-aggregation-f')
end program t408_aggregation_f
