/* t412-sonine-dsmc.c - the first Sonine approximation against granary's DSMC (low-rank selector,
 * fixed seeds): a2 of a monodisperse gas at eps = 0.5, and T_2/T_1 and a2_k of a binary mixture
 * (m_2/m_1 = 10, sigma_2/sigma_1 = 2, n_2/n_1 = 1/2, eps = 0.7) in the HCS. Standard errors from
 * window means (one collision per particle apart, after 5 (one species) or 20 (binary) collisions
 * per particle from the theory's HCS start); the Sonine level must be within 4 se + the stated model
 * tolerance, and at least halve the Maxwellian level's gap. Fig. 5's tracer (the ordered phase): windows after 50 N_1
 * collisions, stationary, the relaxed DSMC ratio within 4 se + 1 % of its reference. */
#include "dsmc_util.h"

/* half (may be NULL): mean and se of the ratio over the first and the second half of the windows */
static void hcs_run(const gran_mixture *mix, int M, const int64_t *counts, const double *T0, int64_t ncoll0,
                    int64_t dcoll, int nw, uint64_t seed, double *ratio, double *ratio_se, double *a2, double *a2_se,
                    double *half) {
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, seed, 0, 0);
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, counts, T0, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance_collisions(sim, ncoll0));
  double r[64], a[2][64];
  for (int w = 0; w < nw; w++) {
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(sim, dcoll));
    double T[2], b[2];
    GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
    GRAN_ASSERT_OK(gran_dsmc_sonine_a2(sim, b));
    r[w] = M > 1 ? T[1] / T[0] : 1.0;
    for (int k = 0; k < M; k++) a[k][w] = b[k];
  }
  dsmc_mean_se(r, nw, ratio, ratio_se);
  if (half) {
    dsmc_mean_se(r, nw / 2, &half[0], &half[1]);
    dsmc_mean_se(r + nw / 2, nw - nw / 2, &half[2], &half[3]);
  }
  for (int k = 0; k < M; k++) dsmc_mean_se(a[k], nw, &a2[k], &a2_se[k]);
  gran_dsmc_destroy(&sim);
}

/* One species, eps = 0.5: DSMC a2 against van Noije & Ernst's 0.05246 (the Maxwellian level: 0). */
static void test_mono_a2(void **state) {
  (void)state;
  const int64_t N = dsmc_scale() < 1 ? 10000 : 100000;
  gran_mixture *mix = dsmc_mono(0.1, 0.5);
  double T0 = 1, a2s = 0, tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, &T0, &a2s, &tau0));
  double r, rse, a2, se;
  hcs_run(mix, 1, &N, &T0, 5 * N, N, 40, 4120, &r, &rse, &a2, &se, NULL);
  print_message("eps 0.5: DSMC a2 = %.5f (se %.5f), first Sonine %.5f, Maxwellian 0\n", a2, se, a2s);
  /* measured: 0.0474 (se 0.0005), 0.005 below the first Sonine value (the second Sonine level and
   * the a2^2 terms the linear theory drops lower it); the Maxwellian level misses by 0.047 */
  GRAN_ASSERT_ABS(a2, a2s, 4 * se + 0.0075);
  if (!DSMC_ASAN) assert_true(fabs(a2) > 4 * se + 0.02);
  gran_mixture_destroy(&mix);
}

/* Binary mixture: T_2/T_1 (Sonine 1.80633, Maxwellian 1.82686) and a2_k. */
static void test_binary(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.7));
  double Ts[2], a2s[2], TM[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Ts, a2s, &tau0));
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, TM, NULL));
  const int64_t N1 = dsmc_scale() < 1 ? 8000 : 40000, counts[2] = {N1, N1 / 2};
  double r, rse, a2[2], se[2];
  hcs_run(mix, 2, counts, Ts, 20 * (N1 + N1 / 2), N1 + N1 / 2, 40, 4121, &r, &rse, a2, se, NULL);
  const double gs = Ts[1] / Ts[0], gm = TM[1] / TM[0];
  print_message("binary: DSMC T2/T1 = %.5f (se %.5f), Sonine %.5f (gap %+.2f%%), Maxwellian %.5f (gap %+.2f%%); "
                "a2 = %.4f, %.4f (se %.4f, %.4f), Sonine %.4f, %.4f\n",
                r, rse, gs, 100 * (gs / r - 1), gm, 100 * (gm / r - 1), a2[0], a2[1], se[0], se[1], a2s[0], a2s[1]);
  /* measured: DSMC 1.7947 (se 0.0015); Sonine +0.65 %, Maxwellian +1.79 %: model tolerance 1 % */
  GRAN_ASSERT_ABS(r, gs, 4 * rse + 0.01 * gs);
  if (!DSMC_ASAN) assert_true(fabs(gs - r) <= 0.5 * fabs(gm - r));
  for (int k = 0; k < 2; k++) GRAN_ASSERT_ABS(a2[k], a2s[k], 4 * se[k] + 0.01);
  gran_mixture_destroy(&mix);
}

/* Heavy, dilute species: Fig. 2 of the source paper (m = 1, 100; sigma_2 = 100^(1/3); n_2/n_1 = 0.01;
 * eps = 0.5) and its tracer limit Fig. 5 (n_2 = 0, the ordered phase). T_2/T_1 of DSMC against both
 * levels; Fig. 2: the Sonine level at least halves the gap; Fig. 5: it moves towards DSMC but the
 * gap stays large (the first Sonine approximation fails in the ordered phase; the test says so). */
static void heavy(double n2, int64_t N1, int64_t N2, int64_t warm, uint64_t seed, double *r, double *rse, double *gs,
                  double *gm, double *half) {
  const double m[2] = {1, 100}, s[2] = {1, cbrt(100.0)}, n[2] = {0.1, n2};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  double Ts[2], a2s[2], TM[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Ts, a2s, &tau0));
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, TM, NULL));
  const int64_t counts[2] = {N1, N2};
  double a2[2], se[2];
  hcs_run(mix, 2, counts, Ts, warm * N1, 2 * N1, 30, seed, r, rse, a2, se, half);
  *gs = Ts[1] / Ts[0];
  *gm = TM[1] / TM[0];
  gran_mixture_destroy(&mix);
}

static void test_fig2_heavy(void **state) {
  (void)state;
  const int64_t N1 = dsmc_scale() < 1 ? 40000 : 200000;
  double r, rse, gs, gm;
  heavy(0.001, N1, N1 / 100, 10, 4122, &r, &rse, &gs, &gm, NULL);
  print_message("Fig. 2: DSMC T2/T1 = %.3f (se %.3f), Sonine %.3f (gap %+.2f%%), Maxwellian %.3f (gap %+.2f%%)\n", r,
                rse, gs, 100 * (gs / r - 1), gm, 100 * (gm / r - 1));
  GRAN_ASSERT_ABS(r, gs, 4 * rse + 0.02 * gs);
  if (!DSMC_ASAN) assert_true(fabs(gs - r) <= 0.5 * fabs(gm - r));
}

static void test_fig5_tracer(void **state) {
  (void)state;
  /* N_1 = 1e5 at every scale: at 2e4 (400 tracers) the tracer's temperature drifts over longer times than the
   * windows resolve (under ASan, -O1: 627.8, se 1.4, halves 4.3 se apart); 1e5 takes 14 s under ASan */
  const int64_t N1 = 100000;
  double r, rse, gs, gm, h[4];
  /* from the first Sonine HCS (504.6) the tracer heats for about 40 N_1 collisions (all pairs): the windows start
   * after 50 N_1; N_1/50 tracers at every scale (their share of the collisions stays the same) */
  heavy(0.0, N1, N1 / 50, 50, 4123, &r, &rse, &gs, &gm, h);
  print_message("Fig. 5 (ordered phase): DSMC T2/T1 = %.1f (se %.1f; halves %.1f, %.1f), Sonine %.1f (gap %+.1f%%), "
                "Maxwellian %.1f (gap %+.1f%%)\n",
                r, rse, h[0], h[2], gs, 100 * (gs / r - 1), gm, 100 * (gm / r - 1));
  /* relaxed: the two halves of the windows agree within 4 se (windows from 10 N_1 collisions on: 600.9 and 634.8,
   * 4.8 se apart), and the mean is the reference 637.0 (se 0.3) of docs/tools/sonine_dsmc_moments.c (two runs of
   * N_1 = 1e5 and 2000 tracers from 500 and 700, 250 windows after 50 N_1 collisions; N_1 = 2e4 and 400 tracers:
   * 638.3 (se 1.0)) within 4 se + 1 % */
  GRAN_ASSERT_ABS(h[2], h[0], 4 * sqrt(h[1] * h[1] + h[3] * h[3]));
  GRAN_ASSERT_ABS(r, 637.0, 4 * rse + 0.01 * 637.0);
  /* the Sonine level is closer, but misses by far more than the noise */
  if (!DSMC_ASAN) {
    assert_true(fabs(gs - r) < fabs(gm - r));
    assert_true(fabs(gs - r) > 4 * rse + 0.1 * r);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_mono_a2), cmocka_unit_test(test_binary),
                                     cmocka_unit_test(test_fig2_heavy), cmocka_unit_test(test_fig5_tracer)};
  return cmocka_run_group_tests_name("t412-sonine-dsmc", tests, NULL, NULL);
}
