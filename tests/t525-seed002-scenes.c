/* t525-seed002-scenes.c - the scenes of scenes/seed002 (the DSMC outline's Figs. 1-6, aggregation in
 * the cell and the low-rank selectors, an aggregation-fragmentation steady state) load, build their
 * mixture and engine and advance; Figs. 1-2 (N = 2000) run through the driver to the end: T(t) within
 * 4 standard errors (sqrt(2/(3N)) T) plus 1 % (a2 and the sample's initial temperature) of the theory
 * written beside it, and the collision count at the end within 3 % of Eq. 35 integrated along that
 * theory. */
#include "io_test_util.h"

#include <dirent.h>

static void test_load_all(void **state) {
  (void)state;
  char dir[1024];
  snprintf(dir, sizeof dir, "%s/scenes/seed002", gran_test_source_dir());
  DIR *d = opendir(dir);
  assert_non_null(d);
  struct dirent *e;
  int n = 0;
  while ((e = readdir(d))) {
    const size_t L = strlen(e->d_name);
    if (L < 5 || strcmp(e->d_name + L - 5, ".toml")) continue;
    char path[2048];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    gran_scene *s = NULL;
    if (gran_scene_load(path, &s)) fail_msg("%s: %s", path, gran_last_error_message());
    gran_mixture *mix = NULL;
    gran_dsmc *sim = NULL;
    GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
    if (gran_scene_dsmc(s, mix, &sim)) fail_msg("%s: engine: %s", path, gran_last_error_message());
    gran_dsmc_options o;
    GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &o, NULL, NULL));
    if (o.selector == GRAN_SELECTOR_CELL) {
      gran_dsmc_cell_options c;
      GRAN_ASSERT_OK(gran_scene_dsmc_cell_options(s, &c));
      GRAN_ASSERT_OK(gran_dsmc_advance(sim, 10 * c.dt));
      int64_t steps = 0;
      GRAN_ASSERT_OK(gran_dsmc_cell_info(sim, &steps, NULL, NULL));
      assert_int_equal(steps, 10);
    } else { /* an event selector (aggregation-event.toml): it collides */
      GRAN_ASSERT_OK(gran_dsmc_advance(sim, 5.0));
      gran_dsmc_stats st;
      GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
      assert_true(st.collisions > 0);
    }
    gran_dsmc_destroy(&sim);
    gran_mixture_destroy(&mix);
    gran_scene_destroy(&s);
    n++;
  }
  closedir(d);
  assert_true(n >= 6);
}

static void test_fig1_2(void **state) {
  (void)state;
  char path[2048], out[600];
  snprintf(path, sizeof path, "%s/scenes/seed002/fig1-2.toml", gran_test_source_dir());
  snprintf(out, sizeof out, "%s", io_path("fig1-2.h5"));
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_load(path, &s));
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, &res));
  assert_int_equal(res.finished, 1);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t nT = 0, nt = 0, nc = 0;
  double *T = io_h5_read_double(f, "/temperatures/T", &nT);
  double *Tt = io_h5_read_double(f, "/temperatures/T_theory", &nt);
  double *C = io_h5_read_double(f, "/stats/collisions", &nc);
  assert_int_equal(nT, 20);
  for (size_t i = 0; i < nT; i++)
    GRAN_ASSERT_SIGMA(T[i], Tt[i], sqrt(2.0 / (3.0 * 2000)) * Tt[i] + 0.01 * Tt[i] / 4, 4);
  /* Eq. 35 along Haff's law: N omega_0 tau_0 ln(1 + t/tau_0) / 2, tau_0 from the last T_theory */
  const double t = 4000, tau0 = t / (1 / sqrt(Tt[nT - 1]) - 1), omega0 = 4 * sqrt(M_PI) * 0.01;
  GRAN_ASSERT_REL(C[nc - 1], 0.5 * 2000 * omega0 * tau0 * log(1 + t / tau0), 0.03);
  free(T);
  free(Tt);
  free(C);
  H5Fclose(f);
  gran_scene_destroy(&s);
}

int main(void) {
  io_tmp("t525"); /* io_path writes into it (without this call: into "/") */
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_load_all),
      cmocka_unit_test(test_fig1_2),
  };
  int rc = cmocka_run_group_tests_name("t525-seed002-scenes", tests, NULL, NULL);
  io_tmp_cleanup();
  return rc;
}
