/* t419-sonine2-dsmc.c - the second Sonine approximation against granary's DSMC (low-rank selector, fixed seeds):
 * T_2/T_1, a2_k and a3_k of the binary part of the Fig. 3 set-up (m = 1, 100; sigma = m^(1/3); n = 0.1, 0.1;
 * eps = 0.5), where the first Sonine level and the Maxwellian one both miss T_2/T_1 by 1.5 %, and a2, a3 of one
 * species at eps = 0.5, T_2/T_1 of the Fig. 5 tracer. a2_k = (3/5) <c^4>/<c^2>^2 - 1, a3_k = 1 + 3 a2_k - (9/35) <v^6>/<v^2>^3 per species from
 * its velocities; standard errors from batch means (batches of 10 windows one collision per particle apart,
 * after 30 collisions per particle from the second Sonine HCS). Tolerances: 4 se + the stated model tolerance. */
#include "dsmc_util.h"

static void moments(const gran_dsmc *sim, int64_t k, int64_t N, double *v, double *a2, double *a3) {
  GRAN_ASSERT_OK(gran_dsmc_species_velocities(sim, k, v));
  double u[3] = {0, 0, 0}, c2 = 0, c4 = 0, c6 = 0;
  for (int64_t j = 0; j < N; j++)
    for (int d = 0; d < 3; d++) u[d] += v[3 * j + d] / (double)N;
  for (int64_t j = 0; j < N; j++) {
    double x = 0;
    for (int d = 0; d < 3; d++) x += (v[3 * j + d] - u[d]) * (v[3 * j + d] - u[d]);
    c2 += x, c4 += x * x, c6 += x * x * x;
  }
  c2 /= (double)N, c4 /= (double)N, c6 /= (double)N;
  *a2 = 0.6 * c4 / (c2 * c2) - 1;
  *a3 = 1 + 3 * *a2 - (9.0 / 35.0) * c6 / (c2 * c2 * c2);
}

/* nb batches of 10 windows; ratio T_2/T_1 (M = 2) and a2_k, a3_k: batch means and their se */
static void run(const gran_mixture *mix, int M, const int64_t *counts, const double *T0, int nb, uint64_t seed,
                double *r, double *rse, double *a2, double *a2se, double *a3, double *a3se) {
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, seed, 0, 0);
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, counts, T0, &o, &sim));
  const int64_t N = counts[0], Nt = M > 1 ? counts[0] + counts[1] : counts[0];
  GRAN_ASSERT_OK(gran_dsmc_advance_collisions(sim, 30 * Nt));
  double *v = malloc(sizeof(double) * 3 * (size_t)N);
  assert_non_null(v);
  double br[64], b2[2][64], b3[2][64];
  for (int b = 0; b < nb; b++) {
    br[b] = 0, b2[0][b] = b2[1][b] = b3[0][b] = b3[1][b] = 0;
    for (int w = 0; w < 10; w++) {
      GRAN_ASSERT_OK(gran_dsmc_advance_collisions(sim, Nt));
      double T[2];
      GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
      br[b] += (M > 1 ? T[1] / T[0] : 1.0) / 10;
      for (int k = 0; k < M; k++) {
        double x2, x3;
        moments(sim, k, counts[k], v, &x2, &x3);
        b2[k][b] += x2 / 10, b3[k][b] += x3 / 10;
      }
    }
  }
  dsmc_mean_se(br, nb, r, rse);
  for (int k = 0; k < M; k++) {
    dsmc_mean_se(b2[k], nb, &a2[k], &a2se[k]);
    dsmc_mean_se(b3[k], nb, &a3[k], &a3se[k]);
  }
  free(v);
  gran_dsmc_destroy(&sim);
}

static void test_binary_fig3(void **state) {
  (void)state;
  const double m[2] = {1, 100}, s[2] = {1, cbrt(100.0)}, n[2] = {0.1, 0.1};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  double T2[2], a2t[2], a3t[2], T1[2], a21[2], TM[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_T1, 1.0, T2, a2t, a3t, &tau0));
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T1, a21, NULL));
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, TM, NULL));
  const int64_t N = dsmc_scale() < 1 ? 10000 : 50000;
  const int nb = dsmc_scale() < 1 ? 6 : 20;
  double r, rse, a2[2], a2se[2], a3[2], a3se[2];
  const int64_t counts[2] = {N, N};
  run(mix, 2, counts, T2, nb, 4190, &r, &rse, a2, a2se, a3, a3se);
  const double g2 = T2[1] / T2[0], g1 = T1[1] / T1[0], gm = TM[1] / TM[0];
  print_message("binary m = 1, 100: DSMC T2/T1 = %.4f (se %.4f); second Sonine %.4f (gap %+.2f%%), first %.4f "
                "(%+.2f%%), Maxwellian %.4f (%+.2f%%)\n",
                r, rse, g2, 100 * (g2 / r - 1), g1, 100 * (g1 / r - 1), gm, 100 * (gm / r - 1));
  for (int k = 0; k < 2; k++)
    print_message("  species %d: a2 DSMC %+.4f (se %.4f), second %+.4f, first %+.4f; a3 DSMC %+.4f (se %.4f), "
                  "second %+.4f\n",
                  k + 1, a2[k], a2se[k], a2t[k], a21[k], a3[k], a3se[k], a3t[k]);
  /* measured: DSMC 13.456 (se 0.005), second Sonine +0.57 %, first +1.56 %: model tolerance 1 % */
  GRAN_ASSERT_ABS(r, g2, 4 * rse + 0.01 * r);
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_ABS(a2[k], a2t[k], 4 * a2se[k] + 0.01);
    GRAN_ASSERT_ABS(a3[k], a3t[k], 4 * a3se[k] + 0.01);
  }
  /* the Sonine hierarchy to a5 (gran_theory_hcs_sonine_n, nmax = 5): measured +0.06 % here, light a2 -0.0007 */
  double T5[2], a5[8];
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 5, GRAN_HCS_NORM_T1, 1.0, T5, a5, NULL));
  const double g5 = T5[1] / T5[0];
  print_message("  nmax = 5: T2/T1 %.4f (gap %+.2f%%), a2 %+.4f %+.4f, a3 %+.4f %+.4f, a4 %+.4f %+.4f\n", g5,
                100 * (g5 / r - 1), a5[0], a5[4], a5[1], a5[5], a5[2], a5[6]);
  GRAN_ASSERT_ABS(r, g5, 4 * rse + 0.005 * r);
  for (int k = 0; k < 2; k++) GRAN_ASSERT_ABS(a2[k], a5[4 * k], 4 * a2se[k] + 0.005);
  if (!DSMC_ASAN) {
    assert_true(fabs(g5 - r) <= 0.5 * fabs(g2 - r));   /* at least half of the second level's gap removed */
    assert_true(fabs(a5[0] - a2[0]) <= 0.5 * fabs(a2t[0] - a2[0]));
    assert_true(fabs(g1 - r) > 4 * rse);              /* the first Sonine gap is resolved */
    assert_true(fabs(g2 - r) <= 0.5 * fabs(g1 - r));  /* and at least halved */
    assert_true(fabs(a2t[0] - a2[0]) <= 0.5 * fabs(a21[0] - a2[0])); /* the light species' a2 */
  }
  gran_mixture_destroy(&mix);
}

static void test_mono(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(0.1, 0.5);
  double T0 = 1, a2t, a3t, a21;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 1.0, &T0, &a2t, &a3t, NULL));
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, &T0, &a21, NULL));
  const int64_t N = dsmc_scale() < 1 ? 20000 : 100000;
  const int nb = dsmc_scale() < 1 ? 4 : 10;
  double r, rse, a2, a2se, a3, a3se;
  run(mix, 1, &N, &T0, nb, 4191, &r, &rse, &a2, &a2se, &a3, &a3se);
  print_message("one species eps 0.5: a2 DSMC %.4f (se %.4f), second Sonine %.4f, first %.4f; a3 DSMC %.4f "
                "(se %.4f), second Sonine %.4f\n",
                a2, a2se, a2t, a21, a3, a3se, a3t);
  /* measured: a2 0.0474, a3 -0.0136 (se 0.0003); second Sonine 0.0450, -0.0177 */
  GRAN_ASSERT_ABS(a2, a2t, 4 * a2se + 0.005);
  GRAN_ASSERT_ABS(a3, a3t, 4 * a3se + 0.006);
  if (!DSMC_ASAN) assert_true(fabs(a2t - a2) < fabs(a21 - a2));
  gran_mixture_destroy(&mix);
}

/* Fig. 5 of the source paper (m = 1, 100; sigma_2 = 100^(1/3); eps = 0.5; n_2 = 0: the tracer limit, the
 * ordered phase): the first Sonine level misses the relaxed DSMC T_2/T_1 (637) by -21 %, the second by -6.6 % */
static void test_fig5_tracer(void **state) {
  (void)state;
  const double m[2] = {1, 100}, s[2] = {1, cbrt(100.0)}, n[2] = {0.1, 0.0};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  double T2[2], a2t[2], a3t[2], T1[2], a21[2];
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_T1, 1.0, T2, a2t, a3t, NULL));
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T1, a21, NULL));
  const int64_t counts[2] = {dsmc_scale() < 1 ? 20000 : 100000, 2000};
  const int nb = dsmc_scale() < 1 ? 4 : 8;
  double r, rse, a2[2], a2se[2], a3[2], a3se[2];
  run(mix, 2, counts, T2, nb, 4192, &r, &rse, a2, a2se, a3, a3se);
  const double g2 = T2[1] / T2[0], g1 = T1[1] / T1[0];
  print_message("Fig. 5 tracer: DSMC T2/T1 = %.1f (se %.1f); second Sonine %.1f (gap %+.1f%%), first %.1f (%+.1f%%); "
                "tracer a2 DSMC %.3f (se %.3f), second %.3f\n",
                r, rse, g2, 100 * (g2 / r - 1), g1, 100 * (g1 / r - 1), a2[1], a2se[1], a2t[1]);
  /* measured: DSMC 635.5 here (637.0 in longer runs); second Sonine -6.4 %: model tolerance 8 % */
  GRAN_ASSERT_ABS(r, g2, 4 * rse + 0.08 * r);
  if (!DSMC_ASAN) assert_true(fabs(g2 - r) <= 0.5 * fabs(g1 - r));
  /* the hierarchy to a5 fails in the ordered phase (tracer a2..a5 = -0.60, -0.66, -0.46, -0.20): T2/T1 = 839,
   * +32 %; the stated bound of that failure */
  double T5[2], a5[8];
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 5, GRAN_HCS_NORM_T1, 1.0, T5, a5, NULL));
  const double g5 = T5[1] / T5[0];
  print_message("  nmax = 5: %.1f (gap %+.1f%%), tracer a2 %.3f\n", g5, 100 * (g5 / r - 1), a5[4]);
  if (!DSMC_ASAN) assert_true(g5 / r - 1 > 0.2 && g5 / r - 1 < 0.45);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_binary_fig3), cmocka_unit_test(test_mono),
                                     cmocka_unit_test(test_fig5_tracer)};
  return cmocka_run_group_tests_name("t419-sonine2-dsmc", tests, NULL, NULL);
}
