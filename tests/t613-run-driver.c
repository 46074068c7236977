/* t613-run-driver.c - the run driver (src/io/run.cpp) around any engine: files compared by
 * identity (two spellings, a symbolic link, the scene file itself are refused before any work),
 * the default checkpoint follows the output path, a stopped run leaves its recorded rows in
 * OUTPUT.partial.h5 (equal to the first rows of the finished run), every dataset carries `units`
 * and `description` as variable-length UTF-8 strings, progress is weighted by the theory's
 * collision count, and the CLI refuses an existing output without --force and prints the title
 * first and no MSD columns when MSD is off. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

static const char *cli(void) {
  const char *c = getenv("GRAN_CLI");
  return c ? c : "build/granary";
}

static int sh(const char *cmd, char *out, size_t len) {
  char full[4096];
  snprintf(full, sizeof full, "%s 2>&1", cmd);
  FILE *p = popen(full, "r");
  if (!p) return -1;
  size_t n = 0, got;
  if (out && len) {
    while (n + 1 < len && (got = fread(out + n, 1, len - 1 - n, p)) > 0) n += got;
    out[n] = '\0';
  }
  int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void test_identity(void **state) {
  (void)state;
  const char *out = io_path("id.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  char two[600];
  snprintf(two, sizeof two, "%s/./id.h5", io_tmpdir);
  /* two spellings of one (not yet existing) file */
  assert_int_equal(gran_scene_run(s, out, two, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "same file"));
  assert_false(io_exists(out));
  /* a symbolic link to an existing file */
  io_write_file(out, "x");
  const char *link = io_path("link.ckpt");
  assert_int_equal(symlink(out, link), 0);
  assert_int_equal(gran_scene_run(s, out, link, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "same file"));
  gran_scene_destroy(&s);
  /* the scene file is never an output */
  const char *sc = io_path("scene.toml");
  io_write_file(sc, io_tiny_text("lowrank", out));
  GRAN_ASSERT_OK(gran_scene_load(sc, &s));
  assert_int_equal(gran_scene_run(s, sc, "", NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "scene file"));
  char *back = io_read_file(sc);
  assert_string_equal(back, io_tiny_text("lowrank", out));
  free(back);
  gran_scene_destroy(&s);
}

/* -o moves the default checkpoint with it; a stopped run's rows are in OUTPUT.partial.h5 */
static void test_checkpoint_follows_output_and_partial(void **state) {
  (void)state;
  const char *scene_out = io_path("scene-out.h5"), *full = io_path("full.h5"), *other = io_path("other.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", scene_out), "tiny.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, full, "", NULL, NULL));
  gran_run_control ctl = {0};
  ctl.stop_after_checkpoints = 1; /* checkpoint_every = 2: stops after 2 output times */
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, other, NULL, &ctl, &res));
  assert_int_equal(res.finished, 0);
  char ck[600], part[600], sck[600];
  snprintf(ck, sizeof ck, "%s.ckpt", other);
  snprintf(sck, sizeof sck, "%s.ckpt", scene_out);
  snprintf(part, sizeof part, "%s/other.partial.h5", io_tmpdir);
  assert_true(io_exists(ck));
  assert_false(io_exists(sck));
  assert_false(io_exists(other));
  assert_true(io_exists(part));
  hid_t f = H5Fopen(part, H5F_ACC_RDONLY, H5P_DEFAULT), g = H5Fopen(full, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0 && g >= 0);
  int64_t complete = -1, recorded = -1;
  hid_t a = H5Aopen(f, "complete", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_INT64, &complete);
  H5Aclose(a);
  a = H5Aopen(f, "recorded", H5P_DEFAULT);
  H5Aread(a, H5T_NATIVE_INT64, &recorded);
  H5Aclose(a);
  assert_int_equal(complete, 0);
  assert_int_equal(recorded, 2);
  hsize_t d[4];
  assert_int_equal(io_h5_dims(f, "temperatures/T", d), 2);
  assert_int_equal(d[0], 2);
  size_t n1 = 0, n2 = 0;
  double *T1 = io_h5_read_double(f, "temperatures/T", &n1), *T2 = io_h5_read_double(g, "temperatures/T", &n2);
  assert_int_equal(n1, 2 * IO_TINY_M);
  for (size_t i = 0; i < n1; i++) assert_true(T1[i] == T2[i]); /* the same rows, bit for bit */
  free(T1);
  free(T2);
  assert_true(H5Lexists(f, "temperatures/T_theory", H5P_DEFAULT) > 0);
  assert_false(H5Lexists(f, "tamsd", H5P_DEFAULT) > 0); /* needs the whole run */
  H5Fclose(f);
  H5Fclose(g);
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_true(io_exists(other));
  assert_false(io_exists(part)); /* replaced by the finished output */
  int nd = 0;
  char diff[600];
  assert_int_equal(io_h5_compare(full, other, &nd, diff, sizeof diff), 0);
  gran_scene_destroy(&s);
}

static int stop_at_3(const gran_run_progress *p, void *params) {
  (void)params;
  return p->output_index == 3;
}

/* without checkpoints a stop still leaves the recorded rows */
static void test_partial_without_checkpoint(void **state) {
  (void)state;
  const char *out = io_path("nock.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("bird", out), "tiny.toml", &s));
  gran_run_control ctl = {0};
  ctl.progress = stop_at_3;
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", &ctl, &res));
  assert_int_equal(res.finished, 0);
  assert_false(io_exists(out));
  hid_t f = H5Fopen(io_path("nock.partial.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hsize_t d[4];
  assert_int_equal(io_h5_dims(f, "stats/collisions", d), 1);
  assert_int_equal(d[0], 3);
  assert_int_equal(io_h5_dims(f, "time", d), 1);
  assert_int_equal(d[0], 3);
  H5Fclose(f);
  gran_scene_destroy(&s);
}

static int nbad;
static char first_bad[256];
static int check_str_attr(hid_t obj, const char *name, const char *path) {
  if (H5Aexists(obj, name) <= 0) {
    if (!nbad++) snprintf(first_bad, sizeof first_bad, "%s has no '%s'", path, name);
    return 0;
  }
  hid_t a = H5Aopen(obj, name, H5P_DEFAULT), t = H5Aget_type(a);
  int ok = H5Tget_class(t) == H5T_STRING && H5Tis_variable_str(t) > 0 && H5Tget_cset(t) == H5T_CSET_UTF8;
  H5Tclose(t);
  H5Aclose(a);
  if (!ok && !nbad++) snprintf(first_bad, sizeof first_bad, "%s: '%s' is not a variable-length UTF-8 string", path, name);
  return ok;
}
static herr_t visit_cb(hid_t f, const char *name, const H5O_info_t *info, void *op) {
  (void)op;
  int *count = op;
  if (info->type != H5O_TYPE_DATASET) return 0;
  (*count)++;
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  check_str_attr(d, "units", name);
  check_str_attr(d, "description", name);
  H5Dclose(d);
  return 0;
}

static void test_units_and_utf8(void **state) {
  (void)state;
  const char *out = io_path("units.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  int count = 0;
  nbad = 0;
#if H5_VERSION_GE(1, 12, 0)
  H5Ovisit3(f, H5_INDEX_NAME, H5_ITER_NATIVE, visit_cb, &count, H5O_INFO_BASIC);
#else
  H5Ovisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, visit_cb, &count);
#endif
  if (nbad) fail_msg("%d problems; first: %s", nbad, first_bad);
  assert_true(count >= 25); /* every observable of the tiny scene is on */
  check_str_attr(f, "title", "/");
  check_str_attr(f, "scene", "/");
  assert_int_equal(nbad, 0);
  char *t = io_h5_attr_string(f, "title");
  assert_string_equal(t, "tiny");
  free(t);
  H5Fclose(f);
  gran_scene_destroy(&s);
}

typedef struct {
  int n;
  double frac[16], T[16];
  int64_t coll[16];
  int32_t unit[16];
} prog_log;
static int log_progress(const gran_run_progress *p, void *params) {
  prog_log *l = params;
  if (l->n < 16) {
    l->frac[l->n] = p->fraction;
    l->coll[l->n] = p->collisions;
    l->T[l->n] = p->temperature;
    l->unit[l->n] = p->work_unit;
    l->n++;
  }
  return 0;
}

/* The progress report's temperature is the gas temperature of the row just recorded: DSMC
 * 2 E_kin / (3 N) of the output's energy/e_kin (N = 2400), GSRD the output's temperature/T; its
 * work unit names what `collisions` counts. */
static void test_progress_temperature(void **state) {
  (void)state;
  const char *out = io_path("progT.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  prog_log l = {0};
  gran_run_control ctl = {0};
  ctl.progress = log_progress;
  ctl.progress_params = &l;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", &ctl, NULL));
  gran_scene_destroy(&s);
  assert_int_equal(l.n, IO_TINY_NT);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t ne = 0;
  double *e = io_h5_read_double(f, "energy/e_kin", &ne);
  assert_int_equal(ne, IO_TINY_NT);
  for (int i = 0; i < l.n; i++) {
    const double T = 2.0 * e[i] / (3.0 * 2400.0);
    if (!(fabs(l.T[i] - T) <= 1e-12 * T)) fail_msg("output %d: progress T %.17g, 2 E_kin / 3N %.17g", i, l.T[i], T);
    assert_int_equal(l.unit[i], GRAN_WORK_COLLISIONS);
    if (i) assert_true(l.T[i] < l.T[i - 1]); /* a cooling gas */
  }
  free(e);
  H5Fclose(f);

  const char *out2 = io_path("progT-srd.h5");
  char text[1024];
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 8\nn0 = 5\ndt = 0.5\nsteps = 40\neps = 0.8\n"
           "sigma = 0.1\nseed = 3\n[observables]\ntimes = [1, 5, 10, 20]\n[output]\npath = \"%s\"\n",
           out2);
  GRAN_ASSERT_OK(gran_scene_parse(text, "srd.toml", &s));
  prog_log m = {0};
  ctl.progress_params = &m;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", &ctl, NULL));
  gran_scene_destroy(&s);
  assert_int_equal(m.n, 4);
  f = H5Fopen(out2, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  double *T = io_h5_read_double(f, "temperature/T", &ne);
  assert_int_equal(ne, 4);
  for (int i = 0; i < m.n; i++) {
    assert_true(m.T[i] == T[i]);
    assert_int_equal(m.unit[i], GRAN_WORK_PARTICLE_STEPS);
  }
  assert_true(m.coll[3] == 40 * 320); /* particle-steps: 40 steps x 8^2 cells x 5 */
  free(T);
  H5Fclose(f);
}

/* fraction done = expected collisions so far / expected in all (theory), not output times done */
static void test_progress_by_work(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", io_path("prog.h5")), "tiny.toml", &s));
  prog_log l = {0};
  gran_run_control ctl = {0};
  ctl.progress = log_progress;
  ctl.progress_params = &l;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", &ctl, NULL));
  assert_int_equal(l.n, IO_TINY_NT);
  assert_true(l.frac[l.n - 1] == 1.0);
  for (int i = 0; i < l.n; i++) {
    const double real = (double)l.coll[i] / (double)l.coll[l.n - 1];
    /* ~1.4e4 collisions: Poisson noise 0.8 %, the Maxwellian theory's rate is good to ~2 % here */
    if (fabs(l.frac[i] - real) > 0.03) fail_msg("output %d: fraction %g, collisions done %g", i, l.frac[i], real);
    if (i) assert_true(l.frac[i] >= l.frac[i - 1]);
  }
  assert_true(l.frac[0] < 0.05); /* counting output times would say 1/8 */
  gran_scene_destroy(&s);
}

static void test_cli(void **state) {
  (void)state;
  char cmd[2048], out[16384];
  const char *h5 = io_path("cli.h5"), *sc = io_path("cli.toml");
  char text[4096];
  snprintf(text, sizeof text, "%s", io_tiny_text("lowrank", h5));
  char *m = strstr(text, "msd = true\n");
  assert_non_null(m);
  memcpy(m, "msd =false\n", 11);
  io_write_file(sc, text);
  snprintf(cmd, sizeof cmd, "%s run %s --no-checkpoint", cli(), sc);
  assert_int_equal(sh(cmd, out, sizeof out), 0);
  assert_true(strncmp(out, "tiny\n", 5) == 0); /* the title first */
  assert_non_null(strstr(out, "T_theory"));
  assert_null(strstr(out, "MSD"));
  assert_null(strstr(out, "nan"));
  /* the output exists now: refused without --force, file untouched */
  struct stat before, after;
  assert_int_equal(stat(h5, &before), 0);
  assert_int_equal(sh(cmd, out, sizeof out), 1);
  assert_non_null(strstr(out, "--force"));
  assert_int_equal(stat(h5, &after), 0);
  assert_true(before.st_mtime == after.st_mtime && before.st_size == after.st_size);
  snprintf(cmd, sizeof cmd, "%s run %s --no-checkpoint --force -q", cli(), sc);
  assert_int_equal(sh(cmd, out, sizeof out), 0);
  /* -o the scene file: refused, scene untouched */
  snprintf(cmd, sizeof cmd, "%s run %s -o %s --force -q", cli(), sc, sc);
  assert_int_equal(sh(cmd, out, sizeof out), 1);
  assert_non_null(strstr(out, "scene file"));
  char *back = io_read_file(sc);
  assert_string_equal(back, text);
  free(back);
}

int main(void) {
  io_tmp("t613");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_identity),
      cmocka_unit_test(test_checkpoint_follows_output_and_partial),
      cmocka_unit_test(test_partial_without_checkpoint),
      cmocka_unit_test(test_units_and_utf8),
      cmocka_unit_test(test_progress_by_work),
      cmocka_unit_test(test_progress_temperature),
      cmocka_unit_test(test_cli),
  };
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
