/* t411-sonine-cli.c - `granary theory --approximation sonine` ($GRAN_CLI): the JSON output carries
 * the first Sonine HCS of the library (gran_theory_hcs_approx, same mean temperature), and bad values
 * exit 2 naming the option. */
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

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_json), cmocka_unit_test(test_bad_value)};
  return cmocka_run_group_tests_name("t411-sonine-cli", tests, NULL, NULL);
}
