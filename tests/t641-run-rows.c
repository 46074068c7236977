/* t641-run-rows.c - the run driver's rules on what a run records and accepts (src/io/run.cpp,
 * src/io/scene.cpp):
 *  - every recorded row is checked: a non-finite value stops the run with GRAN_ERR_NUMERIC naming
 *    the dataset and the output time, the rows before it go to OUTPUT.partial.h5 (no output file,
 *    nothing non-finite written); values that may not exist carry the _FillValue attribute;
 *  - replicas (the scene's and gran_scene_set_replicas) go through the memory check;
 *  - output times and t_end are bounded by the step counter and by t_end, naming the key;
 *  - messages of the cell selector, engine.type and the public entry points name the key. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

#include <math.h>

#define FILLV 9.969209968386869e36

/* GSRD under a gravity that overflows the kinetic energy after a few output times (T0 and g are
 * within the parser's bounds; the energies are not representable from about t = 5e-152 on) */
static const char *overflow_scene(const char *out) {
  static char b[1024];
  snprintf(b, sizeof b,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 10\nn0 = 10\ndt = 1e-153\nT0 = 1e303\nsteps = 100\n"
           "[forces]\ngravity = [0, -1e304]\n[observables]\nevery = 10\n[output]\npath = \"%s\"\n",
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
  assert_int_equal(gran_scene_run(s, out, "", NULL, &res), GRAN_ERR_NUMERIC);
  const char *m = gran_last_error_message();
  assert_non_null(strstr(m, "dataset '"));
  assert_non_null(strstr(m, "is inf at output time 5"));
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

int main(void) {
  io_tmp("t641");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_numeric_row_stops),
      cmocka_unit_test(test_fill_value),
  };
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
