/* t641-run-rows.c - the run driver's rules on what a run records and accepts
 * (src/io/run_output.cpp, src/io/scene.cpp):
 *  - every recorded row is checked: a non-finite value stops the run with GRAN_ERR_NUMERIC naming
 *    the dataset and the output time, the rows before it go to OUTPUT.partial.h5 (no output file,
 *    nothing non-finite written); values that may not exist carry the _FillValue attribute;
 *  - replicas (the scene's and gran_scene_set_replicas) go through the memory check;
 *  - output times and t_end are bounded by the step counter and by t_end, naming the key; the
 *    theory beside a DSMC run by its pair evaluations (refused above 1e13, a warning above 1e10);
 *  - messages of the cell selector, engine.type and the public entry points name the key. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

#include <math.h>

#define FILLV 9.969209968386869e36

/* A GSRD run of 100 steps, rows every 10; the driver's fault hook (GRAN_FAULT_ROW) makes the row
 * of output time 5 non-finite: accepted scenes no longer give such rows (the engines' bounds), the
 * driver's rule is tested on its own. */
static const char *overflow_scene(const char *out) {
  static char b[1024];
  snprintf(b, sizeof b,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 10\nn0 = 10\ndt = 0.1\nT0 = 1\nsteps = 100\n"
           "[forces]\ngravity = [0, -0.01]\n[observables]\nevery = 10\n[output]\npath = \"%s\"\n",
           out);
  return b;
}

static int all_finite(hid_t f, const char *name, size_t *n) {
  double *v = io_h5_read_double(f, name, n);
  int ok = v != NULL;
  for (size_t i = 0; v && i < *n; i++) ok = ok && isfinite(v[i]);
  free(v);
  return ok;
}

static void test_numeric_row_stops(void **state) {
  (void)state;
  const char *out = io_path("ovf.h5"), *part = io_path("ovf.partial.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(overflow_scene(out), "ovf.toml", &s));
  gran_run_result res;
  setenv("GRAN_FAULT_ROW", "5", 1);
  const int st = gran_scene_run(s, out, "", NULL, &res);
  unsetenv("GRAN_FAULT_ROW");
  assert_int_equal(st, GRAN_ERR_NUMERIC);
  const char *m = gran_last_error_message();
  assert_non_null(strstr(m, "dataset '"));
  assert_non_null(strstr(m, "at output time 5"));
  assert_non_null(strstr(m, "the 5 output time(s) before it are in"));
  assert_non_null(strstr(m, "ovf.partial.h5"));
  assert_false(io_exists(out));
  assert_true(io_exists(part));
  hid_t f = H5Fopen(part, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t n = 0;
  assert_true(all_finite(f, "time", &n));
  assert_int_equal(n, 5); /* output times 0..4: the good rows */
  assert_true(all_finite(f, "energy/e_kin", &n) && n == 5);
  assert_true(all_finite(f, "clustering/E_kin", &n) && n == 5);
  assert_true(all_finite(f, "temperature/T", &n) && n == 5);
  H5Fclose(f);
  gran_scene_destroy(&s);
}

/* values that may not exist: the fill value, with its _FillValue attribute; never NaN */
static void test_fill_value(void **state) {
  (void)state;
  const char *out = io_path("fill.h5");
  char text[1024];
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 4\nn0 = 5\ndt = 0.5\nsteps = 4\neps = 0.5\nsigma = 0.1\n"
           "[observables]\nevery = 2\nstructure_factor = {bins = 5}\n[output]\npath = \"%s\"\n", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "fill.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, NULL));
  gran_scene_destroy(&s);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  const char *sets[] = {"structure_factor/S", "structure_factor/k", "clamps/dt_max"};
  for (int j = 0; j < 3; j++) {
    size_t n = 0;
    double *v = io_h5_read_double(f, sets[j], &n);
    assert_non_null(v);
    int nfill = 0;
    for (size_t i = 0; i < n; i++) {
      assert_true(isfinite(v[i]));
      nfill += v[i] == FILLV;
    }
    assert_true(nfill > 0); /* 4x4 cells have shells without modes; no clamp before the first step */
    free(v);
    hid_t d = H5Dopen2(f, sets[j], H5P_DEFAULT);
    assert_true(d >= 0 && H5Aexists(d, "_FillValue") > 0);
    hid_t a = H5Aopen(d, "_FillValue", H5P_DEFAULT);
    double fv = 0;
    assert_true(H5Aread(a, H5T_NATIVE_DOUBLE, &fv) >= 0);
    assert_true(fv == FILLV);
    H5Aclose(a);
    H5Dclose(d);
  }
  /* a dataset that must always have a value has no fill */
  hid_t d = H5Dopen2(f, "temperature/T", H5P_DEFAULT);
  assert_true(d >= 0 && H5Aexists(d, "_FillValue") == 0);
  H5Dclose(d);
  H5Fclose(f);
}

/* ---- replicas: every override goes through the memory check, which counts fixed costs ---- */
static const char *tiny_srd(int64_t replicas, double max_gb) {
  static char b[512];
  snprintf(b, sizeof b,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 2\nn0 = 1\nsteps = 20\nreplicas = %lld\n"
           "max_memory_gb = %g\n[observables]\nevery = 1\n[output]\ncheckpoint = \"\"\n",
           (long long)replicas, max_gb);
  return b;
}

static void test_replicas_memory(void **state) {
  (void)state;
  gran_scene *s = NULL;
  /* 1e6 replicas of 4 particles: about 10 GB (measured 9.0 kB a replica), not 6 */
  assert_int_equal(gran_scene_parse(tiny_srd(1000000, 8), "rep.toml", &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "key 'engine.replicas'"));
  assert_null(s);
  /* the same through gran_scene_set_replicas (granary run --replicas): refused, scene unchanged */
  GRAN_ASSERT_OK(gran_scene_parse(tiny_srd(1, 1), "rep.toml", &s));
  assert_int_equal(gran_scene_set_replicas(s, 1000000, 0), GRAN_ERR_NOMEM);
  assert_non_null(strstr(gran_last_error_message(), "argument 'replicas'"));
  int64_t R = 0;
  GRAN_ASSERT_OK(gran_scene_replicas(s, &R, NULL));
  assert_int_equal(R, 1);
  GRAN_ASSERT_OK(gran_scene_set_replicas(s, 1000, 0)); /* 10 MB */
  gran_scene_destroy(&s);
  /* a DSMC scene of 4 particles likewise (measured 13 kB a replica) */
  const char *d = "[mixture]\nnspecies = 1\nmass = [1.0]\ndensity = [0.1]\n[restitution]\neps = 0.9\n[engine]\n"
                  "counts = [4]\nt_end = 1.0\nmax_memory_gb = 1\n[observables]\ntheory = false\n";
  GRAN_ASSERT_OK(gran_scene_parse(d, "d.toml", &s));
  assert_int_equal(gran_scene_set_replicas(s, 1000000, 0), GRAN_ERR_NOMEM);
  assert_non_null(strstr(gran_last_error_message(), "argument 'replicas'"));
  gran_scene_destroy(&s);
}

/* ---- times: bounded by the step counter (1e15 steps) and by the end of the run ---- */
static void expect_parse(const char *text, const char *key, const char *also) {
  gran_scene *s = NULL;
  assert_int_equal(gran_scene_parse(text, "t.toml", &s), GRAN_ERR_PARSE);
  const char *m = gran_last_error_message();
  if (!strstr(m, key) || (also && !strstr(m, also))) fail_msg("message '%s' lacks '%s' / '%s'", m, key, also ? also : "");
  assert_null(s);
}

static const char *kCellAgg =
    "[mixture]\nnspecies = 30\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.01, theta = 400.0 }\n"
    "[restitution]\neps = 0.9\n[initial]\ntemperatures = \"equal\"\nT_mean = 1.0\n"
    "[engine]\nselector = \"cell\"\nvolume = 1e5\nseed = 7\nt_end = %s\n"
    "[cell]\ncells = 4\ndt = 0.5\ne_agg = 1.0\ne_frag = 3.0\neps_f = 0.7\n"
    "[observables]\n%s\n[output]\npath = \"%s\"\ncheckpoint = \"\"\n";

static void test_time_bounds(void **state) {
  (void)state;
  /* a time beyond the step counter was dropped silently (llround overflowed) */
  expect_parse("[engine]\ntype = \"srd\"\ncells = 4\nsteps = 40\n[observables]\ntimes = [0, 5, 1e20]\n",
               "key 'observables.times'", "1e15 steps");
  expect_parse("[engine]\ntype = \"srd\"\ncells = 4\nsteps = 40\n[observables]\ntimes = [0, 5, 1e20]\n", "engine.dt",
               NULL);
  expect_parse("[engine]\ntype = \"srd\"\ncells = 4\ndt = 1e-300\nt_end = 1\n", "key 'engine.t_end'", "1e15 steps");
  expect_parse("[engine]\ntype = \"srd\"\ncells = 4\nsteps = 10\n[observables]\nevery = 5\nsnapshots = {times = [1e300]}\n",
               "key 'observables.snapshots.times'", "1e15 steps");
  char b[2048];
  /* the cell selector: the run-length bound (1e12 steps) comes first, naming the step and t_end */
  snprintf(b, sizeof b, kCellAgg, "1e300", "msd = false", "x.h5");
  expect_parse(b, "key 'cell.dt'", "t_end");
  snprintf(b, sizeof b, kCellAgg, "1e17", "msd = false", "x.h5");
  expect_parse(b, "key 'cell.dt'", "at most 1e+12 steps");
}

/* The theory beside a DSMC run costs passes over the M^2 species pairs: a scene of 1e6 species
 * starting in the HCS with the theory observables on needs at least 12 passes (1.2e13 pair
 * evaluations, hours) and is refused naming mixture.nspecies, with the estimate; 2e5 species
 * with the theory off and equal temperatures (tau0 alone: 4e10) parse with a warning that gives
 * the estimate; 2000 species parse without one. */
static const char *kManySpecies =
    "[mixture]\nnspecies = %s\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.05, theta = 3.0 }\n"
    "[restitution]\neps = 0.9\n[initial]\ntemperatures = \"%s\"\n%s\n[engine]\nvolume = 1e3\nseed = 7\n"
    "[observables]\ntimes = [0, 1, 2]\ntheory = %s\n[output]\npath = \"x.h5\"\ncheckpoint = \"\"\n";

static int64_t warnings_after_parse(const char *text, char *last, int64_t len) {
  int64_t w0 = 0, w1 = 0;
  GRAN_ASSERT_OK(gran_warning_count(&w0));
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "t.toml", &s));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  GRAN_ASSERT_OK(gran_warning_count(&w1));
  last[0] = 0;
  if (w1 > w0) GRAN_ASSERT_OK(gran_last_warning_copy(last, len));
  return w1 - w0;
}

static void test_theory_work(void **state) {
  (void)state;
  char b[2048], w[1024];
  snprintf(b, sizeof b, kManySpecies, "1000000", "hcs", "", "true");
  expect_parse(b, "key 'mixture.nspecies'", "1.2e+13 pair evaluations");
  assert_non_null(strstr(gran_last_error_message(), "theory = false"));
  snprintf(b, sizeof b, kManySpecies, "200000", "equal", "T_mean = 1.0", "false");
  assert_int_equal(warnings_after_parse(b, w, sizeof w), 1);
  printf("warning: %s\n", w);
  assert_non_null(strstr(w, "mixture.nspecies"));
  assert_non_null(strstr(w, "4e+10 pair evaluations"));
  snprintf(b, sizeof b, kManySpecies, "2000", "hcs", "", "true");
  assert_int_equal(warnings_after_parse(b, w, sizeof w), 0);
}

/* ---- messages and defaults at the edges of the scene and the C API ---- */
static void test_messages(void **state) {
  (void)state;
  char b[2048];
  const char *out = io_path("agg.h5");
  /* aggregation: msd defaults to off (clusters appear and vanish), msd = true refused by name */
  snprintf(b, sizeof b, kCellAgg, "10.0", "times = [5.0, 10.0]\nmsd = true", out);
  expect_parse(b, "key 'observables.msd'", "aggregation");
  snprintf(b, sizeof b, kCellAgg, "10.0", "times = [5.0, 10.0]\ncollision_counts = true", out);
  expect_parse(b, "key 'observables.collision_counts'", NULL);
  snprintf(b, sizeof b, kCellAgg, "10.0", "times = [5.0, 10.0]", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(b, "agg.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, NULL));
  gran_scene_destroy(&s);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  assert_true(H5Lexists(f, "msd", H5P_DEFAULT) == 0 && H5Lexists(f, "clusters", H5P_DEFAULT) > 0);
  H5Fclose(f);
  /* the engine type is checked first, by name */
  expect_parse("[engine]\ntype = 0\n", "key 'engine.type'", "must be a string");
  expect_parse("[engine]\ntype = \"gsrd\"\n", "key 'engine.type'", "\"srd\"");
  /* the C API names its public parameter, not the variable behind it */
  assert_int_equal(gran_srd_advance(NULL, 1), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "argument 'srd'"));
  gran_srd_obs ob;
  assert_int_equal(gran_srd_observe(NULL, &ob), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "argument 'srd'"));
  double k[2];
  int64_t c[2];
  assert_int_equal(gran_srd_structure_factor(NULL, 2, k, k, c), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "argument 'srd'"));
}

/* the rows a checkpoint carries obey the same rule: a recorded non-finite value is refused on
 * resume (a file error naming the dataset), a NaN where "no value" is allowed becomes the fill */
static void test_checkpoint_rows(void **state) {
  (void)state;
  const char *out = io_path("ckrows.h5"), *ck = io_path("ckrows.ckpt"), *ed = io_path("ckrows-ed.ckpt");
  char text[1024];
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 4\nn0 = 5\ndt = 0.5\nsteps = 8\neps = 0.5\nsigma = 0.1\n"
           "[observables]\nevery = 2\n[output]\npath = \"%s\"\ncheckpoint_every = 2\n", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "ckrows.toml", &s));
  gran_run_control ctl;
  memset(&ctl, 0, sizeof ctl);
  ctl.stop_after_checkpoints = 1; /* stops after output times 0 and 1 */
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, out, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  io_edit_copy(ck, ed, "observer/energy.e_kin", 1, NAN, 0);
  assert_int_equal(gran_scene_resume(ed, out, NULL, &res), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "energy/e_kin"));
  assert_false(io_exists(out));
  io_edit_copy(ck, ed, "observer/clamps.dt_max", 0, NAN, 0); /* dt_max: "no clamp" may be recorded */
  GRAN_ASSERT_OK(gran_scene_resume(ed, out, NULL, &res));
  assert_int_equal(res.finished, 1);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t n = 0;
  double *v = io_h5_read_double(f, "clamps/dt_max", &n);
  assert_non_null(v);
  assert_true(n >= 1 && v[0] == FILLV);
  free(v);
  H5Fclose(f);
  unlink(ed);
}

int main(void) {
  io_tmp("t641");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_numeric_row_stops),
      cmocka_unit_test(test_fill_value), cmocka_unit_test(test_checkpoint_rows),
      cmocka_unit_test(test_replicas_memory),
      cmocka_unit_test(test_time_bounds), cmocka_unit_test(test_theory_work),
      cmocka_unit_test(test_messages),
  };
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
