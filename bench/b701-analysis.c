/* b701-analysis.c - TAMSD of one random-walk trajectory for every lag (nlag = nt): FFT (FFTW,
 * O(nt log nt)) against the direct sum (O(nt nlag)), the time each takes, the speedup and the
 * largest relative difference between them over all lags (what the FFT's speed costs in
 * accuracy). "plan" = plan creation once; "execute" = one more trajectory with the same plan. */
#include "bench_util.h"

#include <math.h>
#include <stdint.h>

int main(void) {
  const int64_t nts[] = {1000, 10000, 100000};
  const int ncase = bench_quick() ? 2 : 3;
  printf("b701-analysis: TAMSD of one trajectory, all lags (nlag = nt)\n");
  printf("%8s %12s %12s %12s %12s %10s %14s\n", "nt", "plan s", "execute s", "one-shot s", "direct s", "speedup",
         "max rel diff");
  gran_rng g;
  BENCH_CHECK(gran_rng_seed(&g, 701));
  for (int c = 0; c < ncase; c++) {
    const int64_t nt = nts[c];
    double *r = malloc(sizeof(double) * 3 * (size_t)nt), *a = malloc(sizeof(double) * (size_t)nt),
           *b = malloc(sizeof(double) * (size_t)nt);
    if (!r || !a || !b) return 1;
    BENCH_CHECK(gran_rng_normal(&g, 3 * nt, r));
    for (int64_t i = 3; i < 3 * nt; i++) r[i] += r[i - 3]; /* random walk */

    double t0 = bench_now();
    gran_tamsd_plan *plan = NULL;
    BENCH_CHECK(gran_tamsd_plan_create(nt, &plan));
    const double t_plan = bench_now() - t0;
    const int reps = nt <= 10000 ? 20 : 3;
    t0 = bench_now();
    for (int k = 0; k < reps; k++) BENCH_CHECK(gran_tamsd_plan_execute(plan, 1, r, nt, a));
    const double t_exec = (bench_now() - t0) / reps;
    BENCH_CHECK(gran_tamsd_plan_destroy(&plan));
    t0 = bench_now();
    BENCH_CHECK(gran_tamsd(1, nt, r, nt, a));
    const double t_one = bench_now() - t0;
    t0 = bench_now();
    BENCH_CHECK(gran_tamsd_direct(1, nt, r, nt, b));
    const double t_direct = bench_now() - t0;
    double worst = 0;
    for (int64_t l = 1; l < nt; l++) {
      const double d = fabs(a[l] - b[l]) / b[l];
      if (d > worst) worst = d;
    }
    printf("%8lld %12.2e %12.2e %12.2e %12.2e %10.0f %14.2e\n", (long long)nt, t_plan, t_exec, t_one, t_direct,
           t_direct / t_exec, worst);
    free(r);
    free(a);
    free(b);
  }

  /* Sonine a2 and speed histogram: throughput */
  const int64_t n = bench_quick() ? 100000 : 1000000;
  double *v = malloc(sizeof(double) * 3 * (size_t)n), hist[100], a2;
  if (!v) return 1;
  BENCH_CHECK(gran_rng_normal(&g, 3 * n, v));
  double t0 = bench_now();
  BENCH_CHECK(gran_sonine_a2(n, v, NULL, &a2));
  const double t_a2 = bench_now() - t0;
  t0 = bench_now();
  BENCH_CHECK(gran_speed_histogram(n, v, sqrt(2.0), 100, 4.0, hist, NULL));
  const double t_h = bench_now() - t0;
  printf("\n%-34s %8.2f ns/particle (a2 = %+.4f for %lld Maxwellian samples)\n", "gran_sonine_a2", 1e9 * t_a2 / n, a2,
         (long long)n);
  printf("%-34s %8.2f ns/particle\n", "gran_speed_histogram (100 bins)", 1e9 * t_h / n);
  free(v);
  return 0;
}
