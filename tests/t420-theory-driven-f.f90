! t420-theory-driven-f.f90 - the Fortran binding of gran_theory_temperatures_driven
! (bindings/granary.f90): an elastic gas heats linearly, an elastic gas in a bath of its own
! particles ends at the bath's temperature, the optional heating, shape and argument errors.
! Prints what it checks (tests/granary_test_f.f90); error stop 1 on failure.
program t420_theory_driven_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(c_ptr) :: mix
  real(c_double) :: t(3), temp(1, 3), bad(2, 3), free(1, 3)
  integer :: ierr

  call gran_mixture_create(mix, [0.1_c_double], mass=[2.0_c_double], sigma=[1.0_c_double])
  t = [0.0_c_double, 1.0_c_double, 100.0_c_double]
  call gran_theory_temperatures_driven(mix, [0.5_c_double], 0.0_c_double, 1.0_c_double, 1.0_c_double, &
                                       1.0_c_double, t, 1e-10_c_double, temp, heating=[0.3_c_double])
  call expect(all(abs(temp(1, :) / (0.5_c_double + 0.3_c_double * t) - 1) < 1e-9_c_double), &
              'elastic gas, heating 0.3: T = T0 + 0.3 t')
  t(3) = 1e4_c_double
  call gran_theory_temperatures_driven(mix, [0.5_c_double], 0.02_c_double, 2.0_c_double, 2.0_c_double, &
                                       1.0_c_double, t, 1e-10_c_double, temp)
  call expect(abs(temp(1, 3) / 2 - 1) < 1e-8_c_double .and. temp(1, 2) > 0.5_c_double, &
              'elastic gas in a bath of its own particles at T_b = 2: T -> 2')
  call gran_mixture_set_restitution(mix, 0.8_c_double)
  call gran_theory_temperatures_driven(mix, [0.5_c_double], 0.0_c_double, 1.0_c_double, 1.0_c_double, &
                                       1.0_c_double, t, 1e-10_c_double, temp)
  call gran_theory_temperatures(mix, [0.5_c_double], t, 1e-10_c_double, free)
  call expect(all(abs(temp / free - 1) < 1e-8_c_double), 'no heating, no bath: the free-cooling temperatures')
  call gran_theory_temperatures_driven(mix, [0.5_c_double], 0.0_c_double, 1.0_c_double, 1.0_c_double, &
                                       1.0_c_double, t, 1e-10_c_double, bad, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'temp of the wrong shape: GRAN_ERR_ARG')
  call gran_theory_temperatures_driven(mix, [0.5_c_double], -1.0_c_double, 1.0_c_double, 1.0_c_double, &
                                       1.0_c_double, t, 1e-10_c_double, temp, ierr=ierr)
  call expect(ierr == GRAN_ERR_ARG, 'negative bath density: GRAN_ERR_ARG')
  call expect(index(gran_last_error_message(), 'bath_density') > 0, 'the message names bath_density')
  call gran_mixture_destroy(mix)
  call test_finish('t420-theory-driven-f')
end program t420_theory_driven_f
