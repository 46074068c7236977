! t201-segtree-f.f90 - Fortran twin of t201-segtree: 1-based leaves, totals, sampling frequencies
! (chi-square), zero-weight leaves never sampled at the boundaries, updates, error codes.
program t201_segtree_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(gran_segtree) :: t
  type(gran_rng) :: g
  real(c_double) :: w(7), total, wi, e, chi2, u(1)
  integer :: counts(7), i, k, idx, ierr, df
  integer, parameter :: n = 200000

  w = [0d0, 1d0, 2d0, 0d0, 3.5d0, 0.25d0, 0d0]
  call gran_segtree_init(t, w)
  call require(t%m == 7 .and. t%base == 8, 'm = 7, base = 8')
  call gran_segtree_total(t, total)
  call require(total == 6.75d0, 'total = 6.75')
  ! boundaries: u = 0 gives the first positive leaf (2), u -> 1- the last positive leaf (6)
  call gran_segtree_sample(t, 0d0, idx)
  call require(idx == 2, 'u = 0 samples leaf 2')
  call gran_segtree_sample(t, nearest(1d0, -1d0), idx)
  call require(idx == 6, 'u = nextafter(1, 0) samples leaf 6')

  ! frequencies: chi-square over the 4 positive leaves (df 3) below 16.27 (significance 1e-3)
  call gran_rng_seed(g, 2_c_int64_t)
  counts = 0
  do i = 1, n
    call gran_rng_uniform(g, u)
    call gran_segtree_sample(t, u(1), idx)
    counts(idx) = counts(idx) + 1
  end do
  call require(all(counts(1:7:3) == 0) .and. counts(7) == 0, 'zero-weight leaves never sampled')
  chi2 = 0
  df = -1
  do k = 1, 7
    if (w(k) > 0) then
      e = n * w(k) / total
      chi2 = chi2 + (counts(k) - e)**2 / e
      df = df + 1
    end if
  end do
  print '(a, i0, a, f8.3)', 'chi2 (df ', df, ') = ', chi2
  call require(chi2 < 16.27d0, 'sampling frequencies')

  ! updates
  call gran_segtree_set(t, 1, 10d0)
  call gran_segtree_get(t, 1, wi)
  call require(wi == 10d0, 'set then get leaf 1')
  call gran_segtree_set_batch(t, [2, 5, 2], [0d0, 1d0, 4d0])   ! repeated index: the last value wins
  call gran_segtree_get(t, 2, wi)
  call require(wi == 4d0, 'set_batch: repeated index keeps the last value')
  call gran_segtree_total(t, total)
  call require(total == 10d0 + 4d0 + 2d0 + 1d0 + 0.25d0, 'total after updates')
  call gran_segtree_rebuild(t)
  call require(t%nupdate == 0, 'rebuild resets nupdate')

  ! errors
  call gran_segtree_sample(t, 1d0, idx, ierr)
  call require(ierr == GRAN_ERR_ARG, 'u = 1 gives GRAN_ERR_ARG')
  call gran_segtree_set(t, 0, 1d0, ierr)
  call require(ierr == GRAN_ERR_RANGE, 'leaf 0 gives GRAN_ERR_RANGE (1-based)')
  call gran_segtree_set(t, 8, 1d0, ierr)
  call require(ierr == GRAN_ERR_RANGE, 'leaf 8 of 7 gives GRAN_ERR_RANGE')
  call gran_segtree_set(t, 1, -1d0, ierr)
  call require(ierr == GRAN_ERR_ARG, 'negative weight gives GRAN_ERR_ARG')
  call gran_segtree_set_batch(t, [1, 2], [1d0], ierr)
  call require(ierr == GRAN_ERR_ARG, 'set_batch with sizes 2 and 1 gives GRAN_ERR_ARG')
  call gran_segtree_set_batch(t, [1, 2, 3, 4, 5, 6, 7], [0d0, 0d0, 0d0, 0d0, 0d0, 0d0, 0d0])
  call gran_segtree_sample(t, 0.5d0, idx, ierr)
  call require(ierr == GRAN_ERR_EMPTY, 'all zero gives GRAN_ERR_EMPTY')
  call gran_segtree_free(t)
  call require(.not. c_associated(t%node) .and. t%m == 0, 'free zeroes the tree')
  call gran_segtree_free(t)
  call gran_segtree_total(t, total, ierr)
  call require(ierr == GRAN_ERR_STATE, 'a freed tree gives GRAN_ERR_STATE')
  call test_finish('t201-segtree-f')
end program t201_segtree_f
