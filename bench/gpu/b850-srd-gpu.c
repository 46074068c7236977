/* b850-srd-gpu.c - GSRD on the GPU: particle-steps per second for 3-D, n0 = 10, 64^3 .. 512^3 cells
 * (float and double storage), bytes moved per particle-step (model: pass 1 reads and writes x, v;
 * pass 2 reads x, v and writes v; cell arrays not counted), and the fraction of the device-to-device
 * memcpy bandwidth measured in the same run. Also the device memory a 512^3 x 10 run needs and
 * whether it fits the free memory; S(k) of the cell counts at 128^3 and 512^3 by cuFFT on the device
 * (gran_cuda_srd_sk_power: counts, FFT, power; the half spectrum copied back) against copying the
 * counts to the host and FFTW (r2c, FFTW_ESTIMATE, one thread) there. BENCH_QUICK=1: 64^3 and 128^3
 * only. */
#include "bench_util.h" /* first: feature macros */

#include <fftw3.h>

#include "srd_cuda.h"

static gran_cuda_srd_params params(int64_t L, int precision) {
  gran_cuda_srd_params p;
  memset(&p, 0, sizeof p);
  p.geom.dim = 3;
  p.geom.wall_axis = -1;
  p.geom.a = p.geom.inv_a = 1.0;
  for (int k = 0; k < 3; ++k) {
    p.geom.L[k] = p.geom.nc[k] = L;
    p.geom.box[k] = (double)L;
  }
  p.n = L * L * L * 10;
  p.precision = precision;
  p.fx = 0;
  p.dt = 0.1;
  p.alpha = 130.0 * 3.14159265358979323846 / 180.0;
  return p;
}

int main(void) {
  for (int prec = 1; prec >= 0; --prec) {
    for (int64_t L = 512; L >= 64; L /= 2) {
      gran_cuda_srd_params p = params(L, prec);
      size_t need = 0;
      const int e = gran_cuda_srd_bytes(&p, &need);
      if (e) {
        printf("bench-gpu: %s\n", gran_last_error_message());
        return e == GRAN_ERR_UNSUPPORTED ? 0 : 1;
      }
      printf("%-6s %3lld^3 n0=10: %.3g particles, device memory %.1f GB (%.0f B/particle)\n",
             prec ? "float" : "double", (long long)L, (double)p.n, 1e-9 * (double)need, (double)need / (double)p.n);
    }
  }
  double bw = 0.0;
  int rc = gran_cuda_copy_bandwidth((size_t)1 << 30, 20, &bw);
  if (rc) {
    printf("bench-gpu: %s\n", gran_last_error_message());
    return rc == GRAN_ERR_UNSUPPORTED ? 0 : 1;
  }
  printf("device-to-device memcpy: %.1f GB/s (read + write, 1 GiB x 20)\n", 1e-9 * bw);
  const int64_t Lmax = bench_quick() ? 128 : 512;
  printf("\n%-6s %6s %12s %14s %10s %10s %8s\n", "prec", "cells", "particles", "p-steps/s", "B/p-step", "GB/s", "of copy");
  for (int prec = 1; prec >= 0; --prec) {
    const size_t real = prec ? 4 : 8;
    const double bytes_ps = (double)(12 * real + 9 * real); /* pass 1: x, v read + written; pass 2: x, v read, v written */
    for (int64_t L = 64; L <= Lmax; L *= 2) {
      gran_cuda_srd_params p = params(L, prec);
      gran_rng shift;
      gran_rng_stream(1, 0, &shift);
      gran_cuda_srd *h = NULL;
      rc = gran_cuda_srd_create(&p, NULL, NULL, NULL, &h); /* random state made on the device */
      if (rc) {
        printf("%-6s %4lld^3: %s\n", prec ? "float" : "double", (long long)L, gran_last_error_message());
        continue;
      }
      double t = 0.0;
      if (gran_cuda_srd_sort(h) || gran_cuda_srd_time_steps(h, 2, &shift, &t)) return 1; /* warm-up */
      const int nsteps = L >= 256 ? 10 : 50;
      if (gran_cuda_srd_time_steps(h, nsteps, &shift, &t)) return 1;
      const double ps = (double)p.n * nsteps / t;
      double ts = 0.0, t0 = bench_now();
      if (gran_cuda_srd_sort(h)) return 1;
      double mom[3], ek;
      gran_cuda_srd_moments(h, mom, &ek); /* synchronises */
      ts = bench_now() - t0;
      printf("%-6s %4lld^3 %12.4g %14.4g %10.0f %10.1f %7.1f%%   (sort %.3g s = %.2g steps)\n", prec ? "float" : "double",
             (long long)L, (double)p.n, ps, bytes_ps, 1e-9 * ps * bytes_ps, 100.0 * ps * bytes_ps / bw, ts,
             ts / (t / nsteps));
      /* the same with warp-aggregated cell sums, right after a sort and 5 steps later (sorted as the
         engine keeps it with sort_every) */
      if (gran_cuda_srd_set_sums(h, 1) || gran_cuda_srd_sort(h) || gran_cuda_srd_time_steps(h, nsteps, &shift, &t))
        return 1;
      const double ps_agg = (double)p.n * nsteps / t;
      printf("%-6s %4lld^3 %12s %14.4g %10.0f %10.1f %7.1f%%   (warp-aggregated cell sums, %d steps after a sort)\n",
             prec ? "float" : "double", (long long)L, "", ps_agg, bytes_ps, 1e-9 * ps_agg * bytes_ps,
             100.0 * ps_agg * bytes_ps / bw, nsteps);
      gran_cuda_srd_destroy(&h);
    }
  }
  /* S(k): cuFFT on the device against counts copied to FFTW on the host (float storage) */
  printf("\nS(k) of the cell counts (3-D, n0 = 10):\n%6s %14s %20s %8s\n", "cells", "cuFFT (s)", "copy + FFTW (s)",
         "ratio");
  for (int64_t L = 128; L <= (bench_quick() ? 128 : 512); L *= 4) {
    gran_cuda_srd_params p = params(L, 1);
    gran_cuda_srd *h = NULL;
    if (gran_cuda_srd_create(&p, NULL, NULL, NULL, &h)) {
      printf("%4lld^3: %s\n", (long long)L, gran_last_error_message());
      continue;
    }
    const int64_t nc = L * L * L, nh = L / 2 + 1, ncplx = L * L * nh;
    double *pw = malloc(sizeof(double) * (size_t)ncplx), *cnt = fftw_alloc_real((size_t)nc);
    fftw_complex *z = fftw_alloc_complex((size_t)ncplx);
    if (!pw || !cnt || !z) return 1;
    fftw_plan plan = fftw_plan_dft_r2c_3d((int)L, (int)L, (int)L, cnt, z, FFTW_ESTIMATE);
    if (gran_cuda_srd_sk_power(h, pw)) return 1; /* warm-up (cuFFT plan cache, module load) */
    double t0 = bench_now();
    if (gran_cuda_srd_sk_power(h, pw)) {
      printf("sk_power: %s\n", gran_last_error_message());
      return 1;
    }
    const double t_cufft = bench_now() - t0;
    t0 = bench_now();
    if (gran_cuda_srd_counts(h, cnt)) return 1;
    const double mean = (double)p.n / (double)nc;
    for (int64_t c = 0; c < nc; ++c) cnt[c] -= mean;
    fftw_execute(plan);
    double maxdiff = 0.0;
    for (int64_t q = 0; q < ncplx; ++q) {
      const double pf = (z[q][0] * z[q][0] + z[q][1] * z[q][1]) / (double)p.n, d = fabs(pf - pw[q]);
      maxdiff = d > maxdiff ? d : maxdiff;
    }
    const double t_fftw = bench_now() - t0;
    printf("%4lld^3 %14.3g %20.3g %7.1fx   (largest |S_cuFFT - S_FFTW| per mode %.2g)\n", (long long)L, t_cufft, t_fftw,
           t_fftw / t_cufft, maxdiff);
    fftw_destroy_plan(plan);
    fftw_free(cnt);
    fftw_free(z);
    free(pw);
    gran_cuda_srd_destroy(&h);
  }
  return 0;
}
