! t101-rng-f.f90 - Fortran twin of t101-rng: the same known-answer values (uint64 bits shown as
! signed int64), jump / long_jump / stream consistency, a frequency check, shape errors.
program t101_rng_f
  use, intrinsic :: iso_c_binding
  use granary
  use granary_test_f
  implicit none
  type(gran_rng) :: g, h, st(3)
  integer(c_int64_t) :: out(4)
  real(c_double), allocatable :: u(:), e(:,:), x2(:,:)
  integer :: i, k, ierr, counts(10)
  real(c_double) :: chi2, m, v
  integer, parameter :: n = 100000
  logical :: ok

  ! state {1,2,3,4}: published first outputs of xoshiro256**
  g%s = [1_c_int64_t, 2_c_int64_t, 3_c_int64_t, 4_c_int64_t]
  call gran_rng_u64(g, out)
  call require(all(out == [11520_c_int64_t, 0_c_int64_t, 1509978240_c_int64_t, 1215971899390074240_c_int64_t]), &
               'xoshiro256** outputs from {1,2,3,4}')
  ! after jump / long_jump (the same values as t101-rng.c)
  g%s = [1_c_int64_t, 2_c_int64_t, 3_c_int64_t, 4_c_int64_t]
  call gran_rng_jump(g)
  call gran_rng_u64(g, out(1:2))
  call require(out(1) == -4912596984176294952_c_int64_t .and. out(2) == 7126240192422241655_c_int64_t, &
               'outputs after jump')
  g%s = [1_c_int64_t, 2_c_int64_t, 3_c_int64_t, 4_c_int64_t]
  call gran_rng_long_jump(g)
  call gran_rng_u64(g, out(1:2))
  call require(out(1) == 5942309088398569549_c_int64_t .and. out(2) == -2821296343772193180_c_int64_t, &
               'outputs after long_jump')
  ! seeding is splitmix64: seed 0 gives its published first outputs
  call gran_rng_seed(g, 0_c_int64_t)
  call require(g%s(1) == -2152535657050944081_c_int64_t .and. g%s(2) == 7960286522194355700_c_int64_t .and. &
               g%s(3) == 487617019471545679_c_int64_t, 'splitmix64 seeding')
  ! stream k = seed + k jumps
  call gran_rng_seed(h, 2024_c_int64_t)
  do k = 0, 40
    call gran_rng_stream(2024_c_int64_t, int(k, c_int64_t), g)
    call require(all(g%s == h%s), 'stream equals repeated jumps')
    call gran_rng_jump(h)
  end do

  ! frequency check: 10 equal bins of [0,1), chi-square (df 9) below 27.88 (significance 1e-3)
  allocate(u(n))
  call gran_rng_seed(g, 101_c_int64_t)
  call gran_rng_uniform(g, u)
  call require(all(u >= 0d0 .and. u < 1d0), 'uniform in [0,1)')
  counts = 0
  do i = 1, n
    k = min(int(u(i) * 10) + 1, 10)
    counts(k) = counts(k) + 1
  end do
  chi2 = sum((counts - n / 10d0)**2 / (n / 10d0))
  print '(a, f8.3)', 'uniform chi2 (df 9) = ', chi2
  call require(chi2 < 27.88d0, 'uniform chi-square')
  call gran_rng_uniform_pos(g, u)
  call require(all(u > 0d0 .and. u <= 1d0), 'uniform_pos in (0,1]')
  ! normal: mean 0 (se 1/sqrt(n)), variance 1 (se sqrt(2/n)), 4 standard errors
  call gran_rng_normal(g, u)
  m = sum(u) / n
  v = sum(u**2) / n
  print '(a, 2f10.6)', 'normal mean, <x^2> = ', m, v
  call require(abs(m) < 4 / sqrt(real(n, c_double)) .and. abs(v - 1) < 4 * sqrt(2d0 / n), 'normal moments')
  ! exponential: mean 1 (se 1/sqrt(n))
  call gran_rng_exponential(g, u)
  call require(abs(sum(u) / n - 1) < 4 / sqrt(real(n, c_double)), 'exponential mean')
  ! unit vectors: |e| = 1
  allocate(e(3, 1000), x2(2, 1000))
  call gran_rng_unit_vector3(g, e)
  call require(all(abs(sqrt(sum(e**2, dim=1)) - 1) < 1d-15), '|e| = 1 in 3-D')
  call gran_rng_unit_vector2(g, x2)
  call require(all(abs(sqrt(sum(x2**2, dim=1)) - 1) < 1d-15), '|e| = 1 in 2-D')

  ! errors: wrong shape caught by the wrapper, ierr returned
  call gran_rng_unit_vector3(g, x2, ierr)
  call require(ierr == GRAN_ERR_ARG, 'unit_vector3 with e(2, n) gives GRAN_ERR_ARG')
  call gran_rng_unit_vector2(g, e, ierr)
  call require(ierr == GRAN_ERR_ARG, 'unit_vector2 with e(3, n) gives GRAN_ERR_ARG')

  ! GPU: unsupported without a GPU, else bit-identical to the CPU
  do k = 1, 3
    call gran_rng_stream(8_c_int64_t, int(k, c_int64_t), st(k))
  end do
  deallocate(x2)
  allocate(x2(4, 3))
  call gran_cuda_rng_uniform(st, x2, ierr)
  ok = ierr == GRAN_ERR_UNSUPPORTED
  if (ierr == GRAN_SUCCESS) then
    ok = .true.
    do k = 1, 3
      g = st(k)
      call gran_rng_uniform(g, u(1:4))
      ok = ok .and. all(u(1:4) == x2(:, k))
    end do
  end if
  print '(a, i0)', 'gran_cuda_rng_uniform status ', ierr
  call require(ok, 'CUDA uniform: unsupported or identical to the CPU')
  deallocate(u, e, x2)
  call test_finish('t101-rng-f')
end program t101_rng_f
