/* t529-dsmc-edges.c - the DSMC engine at its edges:
 *  - checkpoint counters: every stored counter is bounded by the rest of the state (the cell
 *    selector's step by its time, merges + breakups + bounces = collisions in both selector
 *    families, per-pair collision counts summing to at most the collisions, bound raises and
 *    speed-class moves at most 2 per collision, the next bound refresh one interval after the
 *    last): a CRC-consistent edit of each (9.2e18 among them) is refused with GRAN_ERR_IO naming
 *    the counter;
 *  - steps: a cell-selector advance (C API) or scene ([cell] dt, [engine] t_end) whose number of
 *    steps or particle-steps exceeds the shared bound (dt = 1e-300, 5e-324, 1e-9; t_end = 1e15,
 *    1.79e308 with dt = 0.5) is refused with the estimate instead of running without end; the
 *    GSRD scene parser uses the same bound ([engine] steps);
 *  - the molecular-gas bath: density, T, sigma = 1e300 or mass = 1e-300 give unbounded bath
 *    collisions per step and are refused at creation naming the options, with the estimate;
 *  - an empty gas: a cell run whose fn or volume gives 0 particles is refused (C API and scene,
 *    naming fn or volume) instead of returning NaN temperatures. */
#include "io_test_util.h"
#include "dsmc_util.h"
#include "agg_test_util.h"

static gran_dsmc *cell_engine(gran_mixture *mix, const int64_t *counts, double volume, double dt, double e_agg,
                              double e_frag, uint64_t seed) {
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, seed, volume, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = dt;
  c.cells = 2;
  c.e_agg = e_agg;
  c.e_frag = e_frag;
  c.eps_f = 0.7;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, counts, NULL, &o, &c, &d));
  return d;
}

static void expect_edit_refused(const char *ck, const char *ed, const char *dataset, int64_t index, double value,
                                const gran_mixture *mix, const char *field) {
  io_edit_copy(ck, ed, dataset, index, value, 1);
  gran_dsmc *c = NULL;
  const int rc = gran_dsmc_checkpoint_read(ed, "state", mix, &c);
  if (rc != GRAN_ERR_IO || !strstr(gran_last_error_message(), field))
    fprintf(stderr, "edit %s[%lld] = %g: rc %d, %s\n", dataset, (long long)index, value, rc, gran_last_error_message());
  assert_int_equal(rc, GRAN_ERR_IO);
  assert_null(c);
  assert_non_null(strstr(gran_last_error_message(), field));
}

static int64_t read_i64(const char *path, const char *dataset, int64_t index) {
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  hid_t sp = H5Dget_space(d);
  const hssize_t n = H5Sget_simple_extent_npoints(sp);
  int64_t *v = malloc((size_t)n * sizeof *v);
  assert_true(H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  const int64_t x = v[index];
  free(v);
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  return x;
}

/* counters: "counters" = collisions, trials, bound_raises, bound_tightenings, next_refresh,
 * coll_at_refresh, ...; "cell_counters" = step, merges, breakups, bounces, kmax, monomers;
 * "agg_counters" = merges, breakups, bounces, kmax, monomers, ncap */
static void test_checkpoint_counters(void **state) {
  (void)state;
  const char *ck = io_path("cell.h5"), *ed = io_path("edit.h5");
  const double big = 9.2e18;
  /* the cell selector with aggregation */
  gran_mixture *mix = agg_kmers(6, 0.01, 0.9);
  gran_dsmc *d = cell_engine(mix, NULL, 2000 / 0.01, 0.5, 0.5, 3.0, 5);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 6.0));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(d, ck, "state"));
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  {
    gran_dsmc *c = NULL;
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(ck, "state", mix, &c)); /* as written */
    GRAN_ASSERT_OK(gran_dsmc_advance(c, 7.0));
    GRAN_ASSERT_OK(gran_dsmc_destroy(&c));
  }
  const int64_t C = read_i64(ck, "state/counters", 0), step = read_i64(ck, "state/cell_counters", 0);
  assert_true(C > 10);
  assert_int_equal(step, 12);
  expect_edit_refused(ck, ed, "state/cell_counters", 0, big, mix, "'step'");
  expect_edit_refused(ck, ed, "state/cell_counters", 0, (double)(step + 1), mix, "'step'");
  expect_edit_refused(ck, ed, "state/cell_counters", 0, (double)(step - 2), mix, "'step'");
  expect_edit_refused(ck, ed, "state/cell_counters", 1, big, mix, "'merges'");
  expect_edit_refused(ck, ed, "state/cell_counters", 2, (double)(read_i64(ck, "state/cell_counters", 2) + 1), mix,
                      "'breakups'");
  expect_edit_refused(ck, ed, "state/cell_counters", 3, big, mix, "'bounces'");
  expect_edit_refused(ck, ed, "state/counters", 0, (double)(C - 1), mix, "'merges'"); /* collisions */
  expect_edit_refused(ck, ed, "state/counters", 2, big, mix, "'bound_raises'");
  expect_edit_refused(ck, ed, "state/counters", 4, big, mix, "'next_refresh'");
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));

  /* the low-rank selector with per-pair collision counts and speed classes */
  mix = NULL;
  {
    double m[2] = {1, 2}, s[2] = {1, 1.2}, n[2] = {0.01, 0.01};
    GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
    GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.8));
  }
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 3, 1000 / 0.01, GRAN_OBSERVE_COLLISION_COUNTS);
  o.speed_classes = GRAN_SPEED_CLASSES_ON;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &d));
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 20.0));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(d, ck, "state"));
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  {
    gran_dsmc *c = NULL;
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(ck, "state", mix, &c));
    GRAN_ASSERT_OK(gran_dsmc_destroy(&c));
  }
  const int64_t C2 = read_i64(ck, "state/counters", 0);
  assert_true(C2 > 100);
  /* two pair counts each within the collisions, together beyond them */
  io_edit_copy(ck, ed, "state/collision_counts", 0, (double)C2, 1);
  expect_edit_refused(ed, io_path("edit2.h5"), "state/collision_counts", 3, (double)C2, mix, "'collision_counts'");
  expect_edit_refused(ck, ed, "state/class_counters", 0, big, mix, "'class_moves'");
  expect_edit_refused(ck, ed, "state/class_counters", 1, big, mix, "'class_rebuilds'");
  expect_edit_refused(ck, ed, "state/class_counters", 2, -5, mix, "'class_counters[2]'");
  expect_edit_refused(ck, ed, "state/counters", 2, (double)(2 * C2 + 1), mix, "'bound_raises'");
  expect_edit_refused(ck, ed, "state/counters", 4, (double)(read_i64(ck, "state/counters", 4) + 1), mix,
                      "'next_refresh'");
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));

  /* the event selectors' aggregation */
  mix = agg_kmers(6, 0.01, 0.9);
  gran_dsmc_agg_options a;
  GRAN_ASSERT_OK(gran_dsmc_agg_options_default(&a));
  a.e_agg = 0.5;
  a.e_frag = 3.0;
  o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 4, 2000 / 0.01, 0);
  GRAN_ASSERT_OK(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d));
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 5.0));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(d, ck, "state"));
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  {
    gran_dsmc *c = NULL;
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(ck, "state", mix, &c));
    GRAN_ASSERT_OK(gran_dsmc_destroy(&c));
  }
  expect_edit_refused(ck, ed, "state/agg_counters", 0, big, mix, "'merges'");
  expect_edit_refused(ck, ed, "state/agg_counters", 2, big, mix, "'bounces'");
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));
}

/* ---- hangs from accepted inputs: the number of steps ------------------------------------------ */
static void expect_advance_refused(double dt, double t_end) {
  gran_mixture *mix = dsmc_mono(0.01, 0.9);
  gran_dsmc *d = cell_engine(mix, NULL, 1000 / 0.01, dt, 0, INFINITY, 2);
  const int rc = gran_dsmc_advance(d, t_end);
  if (rc != GRAN_ERR_ARG || !strstr(gran_last_error_message(), "'t_end'") ||
      !strstr(gran_last_error_message(), "'dt'") || !strstr(gran_last_error_message(), "steps"))
    fprintf(stderr, "dt %g, t_end %g: rc %d, %s\n", dt, t_end, rc, gran_last_error_message());
  assert_int_equal(rc, GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "updates")); /* the estimate */
  int64_t steps = -1;
  GRAN_ASSERT_OK(gran_dsmc_cell_info(d, &steps, NULL, NULL));
  assert_int_equal(steps, 0); /* refused before any step */
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));
}

static const char *cell_scene(const char *engine_extra, const char *cell_extra) {
  static char text[1024];
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 1\ndensity = [0.01]\n[restitution]\neps = 0.9\n[initial]\ntemperatures = \"hcs\"\n"
           "[engine]\nselector = \"cell\"\nseed = 7\n%s\n[cell]\n%s\n[output]\npath = \"x.h5\"\n",
           engine_extra, cell_extra);
  return text;
}
static void expect_scene_refused(const char *text, const char *key, const char *also) {
  gran_scene *s = NULL;
  const int rc = gran_scene_parse(text, "edge.toml", &s);
  if (rc != GRAN_ERR_PARSE || !strstr(gran_last_error_message(), key) || (also && !strstr(gran_last_error_message(), also)))
    fprintf(stderr, "scene (%s): rc %d, %s\n", key, rc, gran_last_error_message());
  assert_int_equal(rc, GRAN_ERR_PARSE);
  assert_null(s);
  assert_non_null(strstr(gran_last_error_message(), key));
  if (also) assert_non_null(strstr(gran_last_error_message(), also));
}

static void test_step_bounds(void **state) {
  (void)state;
  expect_advance_refused(1e-300, 1.0);
  expect_advance_refused(5e-324, 1.0);
  expect_advance_refused(1e-9, 1e3); /* 1e12 steps of 1000 particles */
  expect_advance_refused(0.5, 1e15);
  expect_advance_refused(0.5, 1.79e308);
  /* a run within the bound goes, and the bound counts from the current step */
  gran_mixture *mix = dsmc_mono(0.01, 0.9);
  gran_dsmc *d = cell_engine(mix, NULL, 1000 / 0.01, 0.5, 0, INFINITY, 2);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 2.0));
  GRAN_ASSERT_ERR(gran_dsmc_advance(d, 1e15), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 3.0));
  int64_t steps = 0;
  GRAN_ASSERT_OK(gran_dsmc_cell_info(d, &steps, NULL, NULL));
  assert_int_equal(steps, 6);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));
  /* scenes: [cell] dt with [engine] t_end */
  expect_scene_refused(cell_scene("volume = 1e5\nt_end = 10.0", "dt = 1e-300"), "key 'cell.dt'", "updates");
  expect_scene_refused(cell_scene("volume = 1e5\nt_end = 10.0", "dt = 5e-324"), "key 'cell.dt'", "t_end");
  expect_scene_refused(cell_scene("volume = 1e5\nt_end = 1e4", "dt = 1e-9"), "key 'cell.dt'", "steps");
  expect_scene_refused(cell_scene("volume = 1e5\nt_end = 1e15", "dt = 0.5"), "key 'cell.dt'", "t_end");
  expect_scene_refused(cell_scene("volume = 1e5\nt_end = 1.79e308", "dt = 0.5"), "key 'cell.dt'", NULL);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(cell_scene("volume = 1e5\nt_end = 10.0", "dt = 0.5"), "ok.toml", &s));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  /* GSRD: the same bound on steps x particles ([engine] steps, t_end) */
  expect_scene_refused("[engine]\ntype = \"srd\"\ncells = 16\nsteps = 100000000000000\n", "key 'engine.steps'", "updates");
  expect_scene_refused("[engine]\ntype = \"srd\"\ncells = 16\ndt = 0.5\nt_end = 5e12\n", "key 'engine.t_end'", "updates");
  expect_scene_refused("[engine]\ntype = \"srd\"\ncells = 16\ndt = 0.5\n[observables]\ntimes = [0.0, 5e12]\n",
                       "key 'observables.times'", "updates");
}

/* ---- the molecular-gas bath ------------------------------------------------------------------ */
static void bath_case(double density, double T, double mass, double sigma, int ok, const char *name) {
  gran_mixture *mix = dsmc_mono(0.01, 0.9);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 2, 1000 / 0.01, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = 0.5;
  c.cells = 2;
  c.bath_density = density;
  c.bath_T = T;
  c.bath_mass = mass;
  c.bath_sigma = sigma;
  gran_dsmc *d = NULL;
  const int rc = gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d);
  if (ok) {
    GRAN_ASSERT_OK(rc);
    GRAN_ASSERT_OK(gran_dsmc_advance(d, 2.0));
    double Tk;
    GRAN_ASSERT_OK(gran_dsmc_temperatures(d, &Tk));
    assert_true(isfinite(Tk) && Tk > 0);
  } else {
    if (rc != GRAN_ERR_ARG || !strstr(gran_last_error_message(), name))
      fprintf(stderr, "bath %s: rc %d, %s\n", name, rc, gran_last_error_message());
    assert_int_equal(rc, GRAN_ERR_ARG);
    assert_null(d);
    assert_non_null(strstr(gran_last_error_message(), name));
    assert_non_null(strstr(gran_last_error_message(), "bath collisions per particle and step"));
  }
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));
}

static void test_bath_bound(void **state) {
  (void)state;
  bath_case(0.01, 1.0, 1.0, 1.0, 1, NULL);
  bath_case(1e300, 1.0, 1.0, 1.0, 0, "'bath_density'");
  bath_case(0.01, 1e300, 1.0, 1.0, 0, "'bath_T'");
  bath_case(0.01, 1.0, 1e-300, 1.0, 0, "'bath_mass'");
  bath_case(0.01, 1.0, 1.0, 1e300, 0, "'bath_sigma'");
  bath_case(1e6, 1.0, 1.0, 1.0, 0, "'bath_density'"); /* finite, but ~1e6 bath collisions per step */
}

/* ---- an empty gas ------------------------------------------------------------------------------ */
static void test_empty_gas(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(0.01, 0.9);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 2, 1e-300, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = 0.5;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "at least 1 particle"));
  assert_null(d);
  o.volume = 1e5;
  c.fn = 1e9; /* n V / fn = 1e-6 */
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'fn'"));
  assert_null(d);
  GRAN_ASSERT_OK(gran_mixture_destroy(&mix));
  expect_scene_refused(cell_scene("volume = 1e5\nt_end = 10.0", "dt = 0.5\nfn = 1e9"), "key 'cell.fn'", "0 simulated");
  expect_scene_refused(cell_scene("volume = 1e-300\nt_end = 10.0", "dt = 0.5"), "key 'engine.volume'", "species 0");
  expect_scene_refused(cell_scene("N1 = 1\nt_end = 10.0", "dt = 0.5\nfn = 4"), "key 'cell.fn'", NULL);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_checkpoint_counters),
      cmocka_unit_test(test_step_bounds),
      cmocka_unit_test(test_bath_bound),
      cmocka_unit_test(test_empty_gas),
  };
  io_tmp("t529");
  const int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
