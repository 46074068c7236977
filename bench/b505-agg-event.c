/* b505-agg-event.c - the cost of aggregation and fragmentation in the event selectors:
 * per collision, the low-rank and Bird selectors with the processes on (gran_dsmc_create_agg,
 * the loop of src/dsmc/agg_event.cpp) against off (gran_dsmc_create_agg with both off is
 * gran_dsmc_create: the hot loop of dsmc_loop.h). Monomers (k-mer mixture of 8 sizes), eps = 0.8,
 * to t = 3 tau (tau the mean free time); N = 1e6 (BENCH_QUICK: 1e5). Three rows per selector:
 * off; on with thresholds that never fire (e_agg = 1e-300: the loop's own cost); on with
 * e_agg = 0.1, e_frag = 6 (a few % merge or shatter). Ratios are of rows measured side by side in
 * this run (CPU seconds of the advance calls); no number is typed in. */
#include "bench_util.h" /* first: it sets _POSIX_C_SOURCE */

#include <math.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* CPU seconds per collision of one run to t; *coll the collisions */
static double per_collision(const gran_mixture *mix, const double *T0, double N, int sel, double e_agg,
                            double e_frag, double t, int64_t *coll, double *acc, gran_dsmc_cluster_stats *cs) {
  gran_dsmc_options o;
  BENCH_CHECK(gran_dsmc_options_default(&o));
  o.selector = sel;
  o.seed = 3;
  o.volume = N / 0.01;
  gran_dsmc_agg_options a;
  BENCH_CHECK(gran_dsmc_agg_options_default(&a));
  a.e_agg = e_agg;
  a.e_frag = e_frag;
  a.eps_f = 0.7;
  gran_dsmc *d = NULL;
  BENCH_CHECK(gran_dsmc_create_agg(mix, NULL, T0, &o, &a, &d));
  const double c0 = bench_cpu_now();
  BENCH_CHECK(gran_dsmc_advance(d, t));
  const double cpu = bench_cpu_now() - c0;
  gran_dsmc_stats st;
  BENCH_CHECK(gran_dsmc_get_stats(d, &st));
  *coll = st.collisions;
  *acc = (double)st.collisions / (double)st.trials;
  if (e_agg > 0) BENCH_CHECK(gran_dsmc_get_cluster_stats(d, cs));
  gran_dsmc_destroy(&d);
  return cpu / (double)st.collisions;
}

int main(void) {
  const double N = bench_quick() ? 1e5 : 1e6;
  double n[8] = {0.01, 0, 0, 0, 0, 0, 0, 0}, T0[8] = {1, 1, 1, 1, 1, 1, 1, 1}; /* monomers; sizes up to 8 */
  gran_mixture *mix;
  BENCH_CHECK(gran_mixture_create(8, NULL, NULL, n, &mix));
  BENCH_CHECK(gran_mixture_set_restitution(mix, 0.8));
  const double tau = 1 / (4 * sqrt(M_PI) * 0.01), t = 3 * tau;
  printf("b505-agg-event: aggregation and fragmentation in the event selectors, N = %.0f monomers, to t = 3 tau\n"
         "(CPU s per collision; ratios from this run)\n\n", N);
  const int sel[2] = {GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_BIRD};
  const char *name[2] = {"low-rank", "Bird"};
  for (int q = 0; q < 2; q++) {
    int64_t c0, c1, c2;
    double a0, a1, a2;
    gran_dsmc_cluster_stats cs = {0}, cn = {0};
    const double off = per_collision(mix, T0, N, sel[q], 0, INFINITY, t, &c0, &a0, &cs);
    const double idle = per_collision(mix, T0, N, sel[q], 1e-300, INFINITY, t, &c1, &a1, &cn);
    const double on = per_collision(mix, T0, N, sel[q], 0.1, 6.0, t, &c2, &a2, &cs);
    printf("%s:\n", name[q]);
    printf("  off:                                 %lld collisions, %.3e CPU s each (%.3e /s), acceptance %.3f\n",
           (long long)c0, off, 1 / off, a0);
    printf("  on, never firing (e_agg = 1e-300):   %lld collisions, %.3e CPU s each; / off: %.2f, acceptance %.3f\n",
           (long long)c1, idle, idle / off, a1);
    printf("  on (e_agg = 0.1, e_frag = 6: %lld merges, %lld breakups, largest %lld): %lld collisions, %.3e CPU s "
           "each; / off: %.2f (target <= 1.5), acceptance %.3f\n",
           (long long)cs.merges, (long long)cs.breakups, (long long)cs.largest, (long long)c2, on, on / off, a2);
    /* per trial (CPU s per collision x acceptance): what the processes cost the loop, apart from the
     * acceptance, which for Bird follows the one global bound and so the largest cluster pair */
    printf("  per trial, on / off: %.2f (acceptance on / off %.2f%s)\n\n", (on * a2) / (off * a0), a2 / a0,
           q == 1 ? ": every term of Bird's single bound, Eq. 49, carries sigma_M of the largest size present" : "");
  }
  gran_mixture_destroy(&mix);
  return 0;
}
