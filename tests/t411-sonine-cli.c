/* t411-sonine-cli.c - `granary theory --approximation sonine` ($GRAN_CLI): the JSON output carries
 * the first Sonine HCS of the library (gran_theory_hcs_approx, same mean temperature); with
 * --sonine-order 5 the hierarchy's HCS of the Fig. 3 ternary (gran_theory_hcs_sonine_n, to 1e-15),
 * whose T_k/T_1 lie within 0.5 % of the DSMC ratios 22.862, 38.085 (docs/physics-sonine.md Sec. 4,
 * N_k = 1e5; the first level is 1.7-2.2 % off), and --sonine-order 2 is the first level; --sonine-order 3 with
 * --times gives the second Sonine trajectory and its MSD (gran_theory_msd_sonine2); higher orders and
 * viscoelastic restitution say what they do not give; bad values exit 2 naming the option. */
#include "granary_test.h"

#include <sys/wait.h>

static const char *cli(void) {
  const char *c = getenv("GRAN_CLI");
  return c ? c : "build/granary";
}

static char outbuf[1 << 16];

static int sh(const char *cmd, int merge) {
  char full[4096];
  snprintf(full, sizeof full, "%s%s", cmd, merge ? " 2>&1" : " 2>/dev/null");
  FILE *p = popen(full, "r");
  if (!p) return -1;
  size_t n = 0, got;
  while (n + 1 < sizeof outbuf && (got = fread(outbuf + n, 1, sizeof outbuf - 1 - n, p)) > 0) n += got;
  outbuf[n] = '\0';
  int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/* the numbers of the JSON array after `key` (first occurrence after `from`) */
static int json_array(const char *from, const char *key, double *x, int nmax) {
  const char *p = strstr(from, key);
  if (!p) return -1;
  p = strchr(p, '[');
  if (!p) return -1;
  int n = 0;
  p++;
  while (n < nmax) {
    char *end;
    x[n] = strtod(p, &end);
    if (end == p) break;
    n++;
    p = end;
    while (*p == ',' || *p == ' ') p++;
    if (*p == ']') break;
  }
  return n;
}

static void test_json(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/fig2.toml --approximation sonine --json --times 1,10", cli(),
           gran_test_source_dir());
  assert_int_equal(sh(cmd, 0), 0);
  assert_non_null(strstr(outbuf, "\"approximation\": \"sonine\""));
  const char *son = strstr(outbuf, "\"sonine\": {");
  assert_non_null(son);
  double T[2], a2[2], Tt[4];
  assert_int_equal(json_array(son, "\"T0\"", T, 2), 2);
  assert_int_equal(json_array(son, "\"a2\"", a2, 2), 2);
  assert_non_null(strstr(son, "\"a2_t\": [["));
  (void)Tt;
  /* the library's Sonine HCS of the same mixture, same mean temperature */
  gran_scene *scene = NULL;
  gran_mixture *mix = NULL;
  snprintf(cmd, sizeof cmd, "%s/scenes/fig2.toml", gran_test_source_dir());
  GRAN_ASSERT_OK(gran_scene_load(cmd, &scene));
  GRAN_ASSERT_OK(gran_scene_mixture(scene, &mix));
  double n[2], T0[2], Tl[2], al[2], tau0;
  GRAN_ASSERT_OK(gran_mixture_get(mix, NULL, NULL, n));
  GRAN_ASSERT_OK(gran_scene_initial_temperatures(scene, mix, T0, NULL));
  const double mean = (n[0] * T0[0] + n[1] * T0[1]) / (n[0] + n[1]);
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, mean, Tl, al, &tau0));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(T[k], Tl[k], 1e-15);
    GRAN_ASSERT_REL(a2[k], al[k], 1e-15);
  }
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&scene);
  /* the default stays Maxwellian (no "sonine" block) */
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/fig2.toml --json", cli(), gran_test_source_dir());
  assert_int_equal(sh(cmd, 0), 0);
  assert_non_null(strstr(outbuf, "\"approximation\": \"maxwellian\""));
  assert_null(strstr(outbuf, "\"sonine\": {"));
}

static void test_bad_value(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/fig2.toml --approximation second", cli(), gran_test_source_dir());
  assert_int_equal(sh(cmd, 1), 2);
  assert_non_null(strstr(outbuf, "--approximation 'second'"));
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/fig2.toml --approximation", cli(), gran_test_source_dir());
  assert_int_equal(sh(cmd, 1), 2);
  assert_non_null(strstr(outbuf, "--approximation needs a value"));
}

static void test_order(void **state) {
  (void)state;
  char cmd[1024], path[512];
  snprintf(path, sizeof path, "%s/scenes/quick/fig3.toml", gran_test_source_dir());
  snprintf(cmd, sizeof cmd, "%s theory %s --approximation sonine --sonine-order 5 --json", cli(), path);
  assert_int_equal(sh(cmd, 0), 0);
  const char *ord = strstr(outbuf, "\"order\": {\"nmax\": 5");
  assert_non_null(ord);
  double T[3], g[3], a[12];
  assert_int_equal(json_array(ord, "\"T0\"", T, 3), 3);
  assert_int_equal(json_array(ord, "\"gamma\"", g, 3), 3);
  gran_scene *scene = NULL;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_load(path, &scene));
  GRAN_ASSERT_OK(gran_scene_mixture(scene, &mix));
  double n[3], T0[3], Tl[3], al[12], tau0;
  GRAN_ASSERT_OK(gran_mixture_get(mix, NULL, NULL, n));
  GRAN_ASSERT_OK(gran_scene_initial_temperatures(scene, mix, T0, NULL));
  const double mean = (n[0] * T0[0] + n[1] * T0[1] + n[2] * T0[2]) / (n[0] + n[1] + n[2]);
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 5, GRAN_HCS_NORM_MEAN, mean, Tl, al, &tau0));
  for (int k = 0; k < 3; k++) GRAN_ASSERT_REL(T[k], Tl[k], 1e-15);
  GRAN_ASSERT_REL(g[1], 22.862, 5e-3);
  GRAN_ASSERT_REL(g[2], 38.085, 5e-3);
  (void)a;
  /* order 2 is the first Sonine level */
  snprintf(cmd, sizeof cmd, "%s theory %s --approximation sonine --sonine-order 2 --json", cli(), path);
  assert_int_equal(sh(cmd, 0), 0);
  ord = strstr(outbuf, "\"order\": {\"nmax\": 2");
  assert_non_null(ord);
  assert_int_equal(json_array(ord, "\"T0\"", T, 3), 3);
  double a2[3];
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, mean, Tl, a2, &tau0));
  for (int k = 0; k < 3; k++) GRAN_ASSERT_REL(T[k], Tl[k], 1e-10);
  /* order 3 with times: the second Sonine trajectory and Eq. 4 on it (a2 in the correlation), from the second
   * Sonine HCS of the same mean temperature (the scene starts in the HCS) */
  snprintf(cmd, sizeof cmd, "%s theory %s --approximation sonine --sonine-order 3 --times 1,100 --json", cli(), path);
  assert_int_equal(sh(cmd, 0), 0);
  ord = strstr(outbuf, "\"order\": {\"nmax\": 3");
  assert_non_null(ord);
  assert_non_null(strstr(ord, "\"a3_t\": [["));
  double mt[2], T3[3], a3c[6], mref[6], mtref[2];
  const double tq[2] = {1.0, 100.0};
  assert_int_equal(json_array(ord, "\"msd_total\"", mt, 2), 2);
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 3, GRAN_HCS_NORM_MEAN, mean, T3, a3c, &tau0));
  const double b2[3] = {a3c[0], a3c[2], a3c[4]}, b3[3] = {a3c[1], a3c[3], a3c[5]};
  GRAN_ASSERT_OK(gran_theory_msd_sonine2(mix, T3, b2, b3, 1, 2, tq, 1e-8, mref, mtref));
  for (int j = 0; j < 2; j++) GRAN_ASSERT_REL(mt[j], mtref[j], 1e-12);
  /* beyond a_3 the trajectories are not there, and the output says so */
  snprintf(cmd, sizeof cmd, "%s theory %s --approximation sonine --sonine-order 4 --times 1", cli(), path);
  assert_int_equal(sh(cmd, 0), 0);
  assert_non_null(strstr(outbuf, "beyond a_3"));
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&scene);
  /* viscoelastic restitution has no HCS: the hierarchy is not computed, and the output says so */
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/quick/fig7.toml --approximation sonine --sonine-order 3 --times 1", cli(),
           gran_test_source_dir());
  assert_int_equal(sh(cmd, 0), 0);
  assert_non_null(strstr(outbuf, "the Sonine hierarchy to a_3 (an HCS: none for viscoelastic restitution)"));
  /* usage: an order outside 2..5, no value, without --approximation sonine */
  const char *bad[3][2] = {{"--approximation sonine --sonine-order 6", "order 2..5"},
                           {"--approximation sonine --sonine-order", "order 2..5"},
                           {"--sonine-order 3", "needs --approximation sonine"}};
  for (int i = 0; i < 3; i++) {
    snprintf(cmd, sizeof cmd, "%s theory %s %s", cli(), path, bad[i][0]);
    assert_int_equal(sh(cmd, 1), 2);
    assert_non_null(strstr(outbuf, bad[i][1]));
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_json), cmocka_unit_test(test_bad_value),
                                      cmocka_unit_test(test_order)};
  return cmocka_run_group_tests_name("t411-sonine-cli", tests, NULL, NULL);
}
