/* t510-dsmc-fast-vs-paper.c - the default low-rank selector (acceptance |g| against a bound half as
 * large, e drawn from its |g.e|-weighted law, pipeline, buffered streams) and `lowrank_paper` (the
 * paper's literal rule: e uniform, accept |g.e|) simulate the same process on the three systems of
 * the speed table in b501, scaled down; and so does the low-rank selector with speed
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
 * under ASan) so that the comparison has teeth.
 * test_auto_choice: the default speed_classes = GRAN_SPEED_CLASSES_AUTO decides at creation:
 * on for the two mixtures (with and without displacements), off for the monodisperse
 * gas, the paper's rule, Bird, with trajectories and for a mixture without a species of 256 particles; an auto engine runs bit for bit as the engine with
 * the setting it chose (so the statistics above cover it). */
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

/* run sy with the given speed_classes setting to t = 2: collisions, energy, class moves */
static int auto_observe = 0; /* observables of run_setting */
static void run_setting(const sys_t *sy, int sel, int setting, double out[3]) {
  gran_dsmc_options o = dsmc_opts(sel, 5120, sy->volume, auto_observe);
  if (auto_observe & GRAN_OBSERVE_TRAJECTORIES) {
    o.traj_per_species = 2;
    o.traj_dt = 0.5;
    o.traj_samples = 5;
  }
  o.speed_classes = setting;
  double *T0 = (double *)malloc(sizeof(double) * (size_t)sy->M);
  for (int64_t k = 0; k < sy->M; k++) T0[k] = 1.0;
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(sy->mix, sy->counts, T0, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 2.0));
  gran_dsmc_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &out[1], NULL, NULL));
  out[0] = (double)st.collisions;
  out[2] = (double)st.class_moves;
  assert_true(st.collisions > 100);
  gran_dsmc_destroy(&sim);
  free(T0);
}

/* the default is auto; auto on sy with selector sel must equal the explicit setting `want` bit for bit */
static void expect_auto(const sys_t *sy, int sel, int want) {
  gran_dsmc_options d;
  GRAN_ASSERT_OK(gran_dsmc_options_default(&d));
  assert_int_equal(d.speed_classes, GRAN_SPEED_CLASSES_AUTO);
  double a[3], b[3];
  run_setting(sy, sel, GRAN_SPEED_CLASSES_AUTO, a);
  run_setting(sy, sel, want, b);
  print_message("auto %-7s selector %d: %s (collisions %.0f, class moves %.0f)\n", sy->name, sel,
                want == GRAN_SPEED_CLASSES_ON ? "classes on" : "classes off", a[0], a[2]);
  assert_true(a[0] == b[0] && a[1] == b[1] && a[2] == b[2]);
  if (want == GRAN_SPEED_CLASSES_ON) assert_true(a[2] > 0.01 * a[0]); /* particles do move between classes */
  else assert_true(a[2] == 0.0);
}

static void test_auto_choice(void **state) {
  (void)state;
  const double N1 = 1e4;
  int64_t M = 0;
  while (llround(N1 * pow((double)(M + 1), -3.0)) >= 1) M++;
  sys_t t1 = {"table1", M, NULL, NULL, N1 / 0.1};
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &t1.mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(t1.mix, 0.5));
  expect_auto(&t1, GRAN_SELECTOR_LOWRANK, GRAN_SPEED_CLASSES_ON);
  expect_auto(&t1, GRAN_SELECTOR_LOWRANK_PAPER, GRAN_SPEED_CLASSES_OFF); /* the paper's rule stays literal */
  expect_auto(&t1, GRAN_SELECTOR_BIRD, GRAN_SPEED_CLASSES_OFF);
  auto_observe = GRAN_OBSERVE_DISPLACEMENT;
  expect_auto(&t1, GRAN_SELECTOR_LOWRANK, GRAN_SPEED_CLASSES_ON);
  auto_observe = GRAN_OBSERVE_TRAJECTORIES; /* identities: a cache miss per move */
  expect_auto(&t1, GRAN_SELECTOR_LOWRANK, GRAN_SPEED_CLASSES_OFF);
  auto_observe = 0;
  /* the 1e4-species power law (N_1 = 5e3: species 1..2 have >= 256 particles) */
  sys_t pl = {"plaw", 10000, NULL, NULL, 5e3 / 0.1};
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(pl.M, 1.0, 1.0, 0.1, 3.0, &pl.mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(pl.mix, 0.5));
  pl.counts = (int64_t *)malloc(sizeof(int64_t) * (size_t)pl.M);
  for (int64_t k = 0; k < pl.M; k++) {
    const int64_t c = llround(5e3 * pow((double)(k + 1), -3.0));
    pl.counts[k] = c > 1 ? c : 1;
  }
  expect_auto(&pl, GRAN_SELECTOR_LOWRANK, GRAN_SPEED_CLASSES_ON);
  /* a mixture whose species all have fewer than 256 particles: no species would have classes */
  int64_t small[2] = {255, 200};
  sys_t sm = {"small", 2, t1.mix, small, 0.0};
  gran_mixture *m2;
  double mm[2] = {1.0, 2.0}, ss[2] = {1.0, 1.2}, nn[2] = {0.05, 0.05};
  GRAN_ASSERT_OK(gran_mixture_create(2, mm, ss, nn, &m2));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(m2, 0.5));
  sm.mix = m2;
  expect_auto(&sm, GRAN_SELECTOR_LOWRANK, GRAN_SPEED_CLASSES_OFF);
  /* the monodisperse gas */
  sys_t mo = {"mono", 1, dsmc_mono(0.1, 0.5), NULL, 1e5};
  expect_auto(&mo, GRAN_SELECTOR_LOWRANK, GRAN_SPEED_CLASSES_OFF);
  gran_mixture_destroy(&mo.mix);
  gran_mixture_destroy(&m2);
  free(pl.counts);
  gran_mixture_destroy(&pl.mix);
  gran_mixture_destroy(&t1.mix);
}

/* the scene key: speed_classes = "auto" (also the default: t511), true, false; another string is
 * refused naming the key */
static void test_auto_scene_key(void **state) {
  (void)state;
  const char *base = "[mixture]\ndensity = [0.1, 0.05]\nmass = [1.0, 2.0]\n[restitution]\neps = 0.8\n[engine]\n"
                     "counts = [1000, 500]\nt_end = 10\n";
  const char *val[4] = {"\"auto\"", "true", "false", "\"fast\""};
  const int want[3] = {GRAN_SPEED_CLASSES_AUTO, GRAN_SPEED_CLASSES_ON, GRAN_SPEED_CLASSES_OFF};
  char txt[512];
  for (int q = 0; q < 4; q++) {
    snprintf(txt, sizeof txt, "%sspeed_classes = %s\n", base, val[q]);
    gran_scene *sc = NULL;
    if (q == 3) {
      assert_int_not_equal(gran_scene_parse(txt, "k.toml", &sc), GRAN_SUCCESS);
      assert_non_null(strstr(gran_last_error_message(), "speed_classes"));
      assert_null(sc);
      continue;
    }
    GRAN_ASSERT_OK(gran_scene_parse(txt, "k.toml", &sc));
    gran_dsmc_options o;
    GRAN_ASSERT_OK(gran_scene_dsmc_options(sc, &o, NULL, NULL));
    assert_int_equal(o.speed_classes, want[q]);
    gran_scene_destroy(&sc);
  }
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
      cmocka_unit_test(test_auto_choice),
      cmocka_unit_test(test_auto_scene_key),
  };
  return cmocka_run_group_tests_name("t510-dsmc-fast-vs-paper", tests, NULL, NULL);
}
