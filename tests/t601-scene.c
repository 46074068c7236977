/* t601-scene.c - scene files: every key read into the right C API value, the defaults, the time
 * grids, and every shipped scene (each .toml under scenes/) loading and building its mixture. */
#include "io_test_util.h"

/* every key of the format, with values that differ from the defaults */
static const char *kFull =
    "title = \"every key\"\n"
    "[mixture]\n"
    "nspecies = 3\n"
    "mass = [1.0, 2.5, 7]\n"
    "sigma = [1.0, 1.5, 2.0]\n"
    "density = [0.1, 0.05, 0.0]\n"
    "g2_matrix = [[1.0, 1.1, 1.2], [1.1, 1.3, 1.4], [1.2, 1.4, 1.5]]\n"
    "[restitution]\n"
    "model = \"matrix\"\n"
    "eps_matrix = [[0.9, 0.8, 0.7], [0.8, 0.6, 0.5], [0.7, 0.5, 1]]\n"
    "[initial]\n"
    "temperatures = [1.0, 2.0, 3.0]\n"
    "t_start = 5.0\n"
    "[engine]\n"
    "type = \"dsmc\"\n"
    "selector = \"bird\"\n"
    "seed = 987654321\n"
    "t_end = 50.0\n"
    "counts = [1000, 2e3, 30]\n"
    "bound_refresh = 77\n"
    "[observables]\n"
    "times = [6.0, 10.0, 20.0, 40.0]\n"
    "temperatures = false\n"
    "msd = true\n"
    "energy = false\n"
    "momentum = true\n"
    "collision_counts = true\n"
    "sonine_a2 = true\n"
    "theory = false\n"
    "theory_rtol = 1e-6\n"
    "velocity_distribution = { bins = 10, cmax = 3.0 }\n"
    "tamsd = { tracers = 4, dt = 0.5, samples = 81, lags = [0.5, 1.0, 10.0] }\n"
    "[output]\n"
    "path = \"somewhere/out.h5\"\n"
    "checkpoint = \"somewhere/ck.h5\"\n"
    "checkpoint_interval = 12.5\n"
    "checkpoint_every = 3\n"
    "keep_checkpoint = true\n";

static void test_every_key(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(kFull, "full.toml", &s));
  assert_non_null(s);
  int64_t M = 0, nt = 0, nl = 0;
  double t0 = 0, t1 = 0;
  GRAN_ASSERT_OK(gran_scene_sizes(s, &M, &nt, &nl, &t0, &t1));
  assert_int_equal(M, 3);
  assert_int_equal(nt, 4);
  assert_int_equal(nl, 3);
  assert_true(t0 == 5.0 && t1 == 50.0);
  double times[4], lags[3];
  GRAN_ASSERT_OK(gran_scene_times(s, times));
  assert_true(times[0] == 6.0 && times[3] == 40.0);
  GRAN_ASSERT_OK(gran_scene_lags(s, lags));
  assert_true(lags[0] == 0.5 && lags[2] == 10.0);
  const char *text = NULL, *out = NULL;
  GRAN_ASSERT_OK(gran_scene_text(s, &text));
  assert_string_equal(text, kFull);
  GRAN_ASSERT_OK(gran_scene_output_path(s, &out));
  assert_string_equal(out, "somewhere/out.h5");

  /* mixture: arrays, eps matrix, g2 matrix */
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  double m[3], sg[3], n[3];
  GRAN_ASSERT_OK(gran_mixture_get(mix, m, sg, n));
  assert_true(m[0] == 1.0 && m[1] == 2.5 && m[2] == 7.0);
  assert_true(sg[1] == 1.5 && sg[2] == 2.0);
  assert_true(n[0] == 0.1 && n[1] == 0.05 && n[2] == 0.0);
  int model = -1;
  GRAN_ASSERT_OK(gran_mixture_restitution_model(mix, &model));
  assert_int_equal(model, GRAN_RESTITUTION_MATRIX);
  double eps = 0, g2 = 0;
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 1, 2, &eps, NULL, &g2));
  assert_true(eps == 0.5 && g2 == 1.4);
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 2, 0, &eps, NULL, &g2));
  assert_true(eps == 0.7 && g2 == 1.2);

  /* initial temperatures listed */
  double T0[3], tau0 = 0;
  GRAN_ASSERT_OK(gran_scene_initial_temperatures(s, mix, T0, &tau0));
  assert_true(T0[0] == 1.0 && T0[1] == 2.0 && T0[2] == 3.0);

  /* engine options */
  gran_dsmc_options opt;
  int64_t counts[3];
  int have = -1;
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &opt, counts, &have));
  assert_int_equal(have, 1);
  assert_true(counts[0] == 1000 && counts[1] == 2000 && counts[2] == 30);
  assert_int_equal(opt.selector, GRAN_SELECTOR_BIRD);
  assert_true(opt.seed == 987654321u);
  assert_true(opt.t_start == 5.0);
  assert_int_equal(opt.bound_refresh, 77);
  assert_int_equal(opt.observe, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS | GRAN_OBSERVE_TRAJECTORIES);
  assert_int_equal(opt.traj_per_species, 4);
  assert_true(opt.traj_dt == 0.5);
  assert_int_equal(opt.traj_samples, 81);
  gran_mixture_destroy(&mix);
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  assert_null(s);
  GRAN_ASSERT_OK(gran_scene_destroy(&s)); /* NULL-safe */
}

static void test_defaults(void **state) {
  (void)state;
  const char *text =
      "[mixture]\n"
      "nspecies = 3\n"
      "density = [0.1, 0.01, 0.001]\n"
      "[engine]\n"
      "N1 = 1000\n"
      "t_end = 10\n";
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "dir/minimal.toml", &s));
  int64_t M, nt, nl;
  double t0, t1;
  GRAN_ASSERT_OK(gran_scene_sizes(s, &M, &nt, &nl, &t0, &t1));
  assert_int_equal(M, 3);
  assert_int_equal(nt, 41); /* default output times: 41, log-spaced over three decades */
  assert_int_equal(nl, 0);
  assert_true(t0 == 0.0 && t1 == 10.0);
  double t[41];
  GRAN_ASSERT_OK(gran_scene_times(s, t));
  GRAN_ASSERT_REL(t[0], 0.01, 1e-14);
  assert_true(t[40] == 10.0);
  GRAN_ASSERT_REL(t[20], 10.0 * pow(10.0, -1.5), 1e-14);
  double lags[1];
  GRAN_ASSERT_ERR(gran_scene_lags(s, lags), GRAN_ERR_STATE);
  const char *out;
  GRAN_ASSERT_OK(gran_scene_output_path(s, &out));
  assert_string_equal(out, "minimal.h5");

  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  double m[3], sg[3];
  GRAN_ASSERT_OK(gran_mixture_get(mix, m, sg, NULL));
  for (int k = 0; k < 3; k++) {
    assert_true(m[k] == (double)(k + 1));           /* m_k = k m_1 */
    GRAN_ASSERT_REL(sg[k], cbrt((double)(k + 1)), 1e-15); /* sigma_k = sigma_1 k^(1/3) */
  }
  int model;
  double eps, g2;
  GRAN_ASSERT_OK(gran_mixture_restitution_model(mix, &model));
  assert_int_equal(model, GRAN_RESTITUTION_CONSTANT);
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 0, 2, &eps, NULL, &g2));
  assert_true(eps == 1.0 && g2 == 1.0);

  gran_dsmc_options opt;
  int64_t counts[3];
  int have = -1;
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &opt, counts, &have));
  assert_int_equal(have, 0);
  GRAN_ASSERT_REL(opt.volume, 1000.0 / 0.1, 1e-15); /* V = N1 / n1 */
  assert_true(counts[0] == 1000 && counts[1] == 100 && counts[2] == 10);
  assert_int_equal(opt.selector, GRAN_SELECTOR_LOWRANK);
  assert_true(opt.seed == 1);
  assert_int_equal(opt.observe, GRAN_OBSERVE_DISPLACEMENT); /* msd on by default */
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);
}

static void test_laws_and_grids(void **state) {
  (void)state;
  const char *text =
      "[mixture]\n"
      "nspecies = 4\n"
      "m1 = 2.0\n"
      "sigma1 = 0.5\n"
      "density_law = { n1 = 0.2, theta = 3 }\n"
      "g2 = 1.25\n"
      "[restitution]\n"
      "model = \"viscoelastic\"\n"
      "beta = 0.09\n"
      "[initial]\n"
      "temperatures = \"equal\"\n"
      "T_mean = 2.5\n"
      "[engine]\n"
      "volume = 1000.0\n"
      "[observables]\n"
      "times = { linear = { start = 1, stop = 3, n = 5 } }\n";
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, NULL, &s));
  double t[5];
  GRAN_ASSERT_OK(gran_scene_times(s, t));
  for (int i = 0; i < 5; i++) assert_true(t[i] == 1.0 + 0.5 * i);
  double t1;
  GRAN_ASSERT_OK(gran_scene_sizes(s, NULL, NULL, NULL, NULL, &t1));
  assert_true(t1 == 3.0); /* t_end defaults to the last output time */
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  double m[4], sg[4], n[4];
  GRAN_ASSERT_OK(gran_mixture_get(mix, m, sg, n));
  for (int k = 0; k < 4; k++) {
    GRAN_ASSERT_REL(m[k], 2.0 * (k + 1), 1e-15);
    GRAN_ASSERT_REL(sg[k], 0.5 * cbrt(k + 1.0), 1e-15);
    GRAN_ASSERT_REL(n[k], 0.2 * pow(k + 1.0, -3.0), 1e-15);
  }
  int model;
  double beta, g2;
  GRAN_ASSERT_OK(gran_mixture_restitution_model(mix, &model));
  assert_int_equal(model, GRAN_RESTITUTION_VISCOELASTIC);
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 0, 1, NULL, &beta, &g2));
  assert_true(beta == 0.09 && g2 == 1.25);
  double T0[4];
  GRAN_ASSERT_OK(gran_scene_initial_temperatures(s, mix, T0, NULL));
  for (int k = 0; k < 4; k++) assert_true(T0[k] == 2.5);
  gran_dsmc_options opt;
  int64_t c[4];
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &opt, c, NULL));
  assert_true(opt.volume == 1000.0);
  assert_true(c[0] == 200 && c[1] == 25 && c[2] == 7 && c[3] == 3); /* round(n_k V) */
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);

  /* log grid and the material form of the viscoelastic model */
  const char *t2 =
      "[mixture]\ndensity = [0.1]\n"
      "[restitution]\nmaterial = { A = 1e-3, Y = 1e5, nu = 0.3 }\n"
      "[initial]\ntemperatures = \"equal\"\n"
      "[engine]\ncounts = [10]\nt_end = 1000\n"
      "[observables]\ntimes = { log = { start = 0.1, stop = 1000, n = 5 } }\n";
  GRAN_ASSERT_OK(gran_scene_parse(t2, "t2.toml", &s));
  double tl[5];
  GRAN_ASSERT_OK(gran_scene_times(s, tl));
  assert_true(tl[0] == 0.1 && tl[4] == 1000.0);
  GRAN_ASSERT_REL(tl[1], 1.0, 1e-14);
  GRAN_ASSERT_REL(tl[3], 100.0, 1e-14);
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  GRAN_ASSERT_OK(gran_mixture_restitution_model(mix, &model));
  assert_int_equal(model, GRAN_RESTITUTION_VISCOELASTIC);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);
}

static int ends_with(const char *s, const char *suf) {
  size_t a = strlen(s), b = strlen(suf);
  return a >= b && !strcmp(s + a - b, suf);
}

static void test_shipped_scenes(void **state) {
  (void)state;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/scenes", gran_test_source_dir());
  DIR *d = opendir(dir);
  assert_non_null(d);
  struct dirent *e;
  int nloaded = 0, seen_default = 0, seen_fig[9] = {0}, seen_table1 = 0;
  while ((e = readdir(d))) {
    if (!ends_with(e->d_name, ".toml")) continue;
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    gran_scene *s = NULL;
    int st = gran_scene_load(path, &s);
    if (st) fail_msg("%s: %s", path, gran_last_error_message());
    gran_mixture *mix = NULL;
    st = gran_scene_mixture(s, &mix);
    if (st) fail_msg("%s: mixture: %s", path, gran_last_error_message());
    int64_t M = 0, nt = 0;
    GRAN_ASSERT_OK(gran_scene_sizes(s, &M, &nt, NULL, NULL, NULL));
    assert_true(M >= 1 && nt >= 1);
    gran_dsmc_options opt;
    GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &opt, NULL, NULL));
    gran_mixture_destroy(&mix);
    gran_scene_destroy(&s);
    nloaded++;
    if (!strcmp(e->d_name, "default.toml")) seen_default = 1;
    if (!strcmp(e->d_name, "table1.toml")) seen_table1 = 1;
    int k;
    if (sscanf(e->d_name, "fig%d.toml", &k) == 1 && k >= 1 && k <= 8) seen_fig[k] = 1;
  }
  closedir(d);
  assert_true(seen_default);
  assert_true(seen_table1);
  for (int k = 1; k <= 8; k++)
    if (!seen_fig[k]) fail_msg("scenes/fig%d.toml is missing", k);
  assert_true(nloaded >= 10);
}

/* The parameters of the figure scenes, as the captions of Bodrova & Osinsky give them. */
static void test_figure_parameters(void **state) {
  (void)state;
  char path[1024];
  gran_scene *s = NULL;
  gran_mixture *mix = NULL;
  double m[3], sg[3], n[3], beta, eps;
  int64_t M;

  snprintf(path, sizeof path, "%s/scenes/fig2.toml", gran_test_source_dir());
  GRAN_ASSERT_OK(gran_scene_load(path, &s));
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  GRAN_ASSERT_OK(gran_mixture_get(mix, m, sg, n));
  assert_true(m[0] == 1 && m[1] == 100 && n[0] == 0.1 && n[1] == 0.001 && sg[0] == 1);
  GRAN_ASSERT_REL(sg[1], cbrt(100.0), 1e-15);
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 0, 1, &eps, NULL, NULL));
  assert_true(eps == 0.5);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);

  snprintf(path, sizeof path, "%s/scenes/fig8.toml", gran_test_source_dir());
  GRAN_ASSERT_OK(gran_scene_load(path, &s));
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  GRAN_ASSERT_OK(gran_mixture_nspecies(mix, &M));
  assert_int_equal(M, 3);
  GRAN_ASSERT_OK(gran_mixture_get(mix, m, sg, n));
  assert_true(m[2] == 500 && n[2] == 0.1);
  GRAN_ASSERT_REL(sg[2], cbrt(500.0), 1e-15);
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 1, 2, NULL, &beta, NULL));
  assert_true(beta == 0.09);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);

  snprintf(path, sizeof path, "%s/scenes/table1.toml", gran_test_source_dir());
  GRAN_ASSERT_OK(gran_scene_load(path, &s));
  int64_t c[125];
  gran_dsmc_options opt;
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &opt, c, NULL));
  assert_true(c[0] == 1000000 && c[1] == 125000 && c[9] == 1000 && c[124] == 1); /* round(N_1 k^-3) */
  gran_scene_destroy(&s);
}

static void test_null_arguments(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_load(NULL, &s), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "path"));
  GRAN_ASSERT_ERR(gran_scene_load("x.toml", NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_scene_parse(NULL, "a", &s), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "text"));
  GRAN_ASSERT_ERR(gran_scene_destroy(NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_scene_sizes(NULL, NULL, NULL, NULL, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_scene_mixture(NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_scene_run(NULL, NULL, NULL, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "scene"));
  GRAN_ASSERT_ERR(gran_scene_resume(NULL, NULL, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "checkpoint"));
  GRAN_ASSERT_ERR(gran_scene_load("/nonexistent/granary/scene.toml", &s), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "/nonexistent/granary/scene.toml"));
  assert_null(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_key),       cmocka_unit_test(test_defaults),
      cmocka_unit_test(test_laws_and_grids),  cmocka_unit_test(test_shipped_scenes),
      cmocka_unit_test(test_figure_parameters), cmocka_unit_test(test_null_arguments),
  };
  return cmocka_run_group_tests_name("t601-scene", tests, NULL, NULL);
}
