/* t510-dsmc-fast-vs-paper.c - the default low-rank selector (acceptance |g| against a bound half as
 * large, e drawn from its |g.e|-weighted law, pipeline, buffered streams) and `lowrank_paper` (the
 * paper's literal rule: e uniform, accept |g.e|) simulate the same process on the three systems of
 * the speed table in b501 (issue 11), scaled down; and so does the low-rank selector with speed
 * classes (opt.speed_classes = 1, the *_classes cases; other seeds):
 *   table1: n_k = 0.1 k^-3, N_k = round(N_1 k^-3) >= 1 with N_1 = 1e4 (22 species, eps = 0.5,
 *           T_k(0) = 1, t = 10);
 *   mono:   one species, N = 1e4, n = 0.1, eps = 0.5, T(0) = 1, t = 10;
 *   plaw:   1e4 species, theta = 3 (n_k = 0.1 k^-3 in the mixture), N_k = max(1, round(N_1 k^-3))
 *           with N_1 = 5e3 (15e3 particles, most species one particle), V = N_1 / 0.1, t = 10.
 * Quantities: collision count, kinetic energy, temperature of species 1 (and 2 for the mixtures).
 * R seeds per selector (10; 4 under ASan); the standard error of the difference of the two means
 * uses the variance pooled over both selectors (2(R-1) degrees of freedom): tolerance 4.5 standard
 * errors per quantity (the t504 convention), and each quantity resolved to better than 3% (6%
 * under ASan) so that the comparison has teeth. */
#include "dsmc_util.h"

#define NQ 4
static const char *qname[NQ] = {"collisions", "E_kin", "T_1", "T_2"};

typedef struct {
  const char *name;
  int64_t M;
  gran_mixture *mix;
  int64_t *counts; /* NULL: from the volume */
  double volume;
} sys_t;

static void run_one(const sys_t *sy, int sel, int classes, uint64_t seed, double *q) {
  gran_dsmc_options o = dsmc_opts(sel, seed, sy->volume, 0);
  o.speed_classes = classes && sel == GRAN_SELECTOR_LOWRANK; /* the paper's rule: one bound per species */
  double *T0 = (double *)malloc(sizeof(double) * (size_t)sy->M);
  double *T = (double *)malloc(sizeof(double) * (size_t)sy->M);
  for (int64_t k = 0; k < sy->M; k++) T0[k] = 1.0;
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(sy->mix, sy->counts, T0, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 10.0));
  double ek;
  GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, NULL, NULL));
  q[0] = (double)dsmc_collisions(sim);
  q[1] = ek;
  q[2] = T[0];
  q[3] = sy->M > 1 ? T[1] : T[0];
  gran_dsmc_destroy(&sim);
  free(T0);
  free(T);
}

static void compare(const sys_t *sy, int classes) {
  const int R = DSMC_ASAN ? 4 : 10;
  const int sels[2] = {GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_LOWRANK_PAPER};
  double q[2][10][NQ];
  for (int a = 0; a < 2; a++)
    for (int r = 0; r < R; r++) run_one(sy, sels[a], classes, (classes ? 5110 : 5100) + (uint64_t)r, q[a][r]);
  const int nq = sy->M > 1 ? NQ : NQ - 1;
  for (int i = 0; i < nq; i++) {
    double mean[2], var = 0;
    for (int a = 0; a < 2; a++) {
      mean[a] = 0;
      for (int r = 0; r < R; r++) mean[a] += q[a][r][i] / R;
      for (int r = 0; r < R; r++) var += (q[a][r][i] - mean[a]) * (q[a][r][i] - mean[a]);
    }
    var /= 2.0 * (R - 1);
    const double se = sqrt(2.0 * var / R);
    print_message("%-6s %-10s %s %.6g lowrank-paper %.6g (se of the difference %.2g)\n", sy->name, qname[i],
                  classes ? "lowrank+classes" : "lowrank", mean[0], mean[1], se);
    GRAN_ASSERT_SIGMA(mean[1], mean[0], se, 4.5);
    assert_true(se < (DSMC_ASAN ? 0.06 : 0.03) * fabs(mean[0]));
  }
}

static void table1(int classes) {
  const double N1 = 1e4;
  int64_t M = 0;
  while (llround(N1 * pow((double)(M + 1), -3.0)) >= 1) M++;
  sys_t sy = {"table1", M, NULL, NULL, N1 / 0.1};
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &sy.mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(sy.mix, 0.5));
  compare(&sy, classes);
  gran_mixture_destroy(&sy.mix);
}

static void mono(int classes) {
  sys_t sy = {"mono", 1, dsmc_mono(0.1, 0.5), NULL, 1e5};
  compare(&sy, classes);
  gran_mixture_destroy(&sy.mix);
}

static void powerlaw_1e4(int classes) {
  const int64_t M = 10000;
  const double N1 = 5e3;
  sys_t sy = {"plaw", M, NULL, NULL, N1 / 0.1};
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &sy.mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(sy.mix, 0.5));
  sy.counts = (int64_t *)malloc(sizeof(int64_t) * (size_t)M);
  for (int64_t k = 0; k < M; k++) {
    const int64_t c = llround(N1 * pow((double)(k + 1), -3.0));
    sy.counts[k] = c > 1 ? c : 1;
  }
  compare(&sy, classes);
  free(sy.counts);
  gran_mixture_destroy(&sy.mix);
}

static void test_table1(void **state) { (void)state, table1(0); }
static void test_mono(void **state) { (void)state, mono(0); }
static void test_powerlaw_1e4(void **state) { (void)state, powerlaw_1e4(0); }
static void test_table1_classes(void **state) { (void)state, table1(1); }
static void test_mono_classes(void **state) { (void)state, mono(1); }
static void test_powerlaw_1e4_classes(void **state) { (void)state, powerlaw_1e4(1); }

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_table1),
      cmocka_unit_test(test_mono),
      cmocka_unit_test(test_powerlaw_1e4),
      cmocka_unit_test(test_table1_classes),
      cmocka_unit_test(test_mono_classes),
      cmocka_unit_test(test_powerlaw_1e4_classes),
  };
  return cmocka_run_group_tests_name("t510-dsmc-fast-vs-paper", tests, NULL, NULL);
}
