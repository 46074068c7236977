! Fig. 2 of Bodrova & Osinsky from Fortran: HCS temperatures, tau0 and the MSD (Eq. 22).
program example
  use granary
  use, intrinsic :: iso_c_binding
  implicit none
  type(c_ptr) :: mix
  real(c_double) :: T0(2), tau0, t(3) = [1d0, 10d0, 100d0], msd(2, 3)
  integer :: i
  call gran_mixture_create(mix, density=[0.1d0, 0.001d0], mass=[1d0, 100d0], &
                           sigma=[1d0, 100d0**(1d0/3)])
  call gran_mixture_set_restitution(mix, 0.5d0)
  call gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1d0, T0, tau0)
  print '(a, f8.3, a, 2f10.5)', 'tau0 =', tau0, '   T(0) =', T0
  call gran_theory_msd_hcs(mix, T0, tau0, t, msd)
  do i = 1, 3
    print '(a, f6.1, a, 2es14.6)', 't =', t(i), '   MSD_k =', msd(:, i)
  end do
  call gran_mixture_destroy(mix)
end program example
