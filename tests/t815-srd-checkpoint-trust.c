/* t815-srd-checkpoint-trust.c - a GSRD checkpoint is validated value by value, not trusted once its
 * CRC-32 matches:
 *  - gran_srd_checkpoint_read: one CRC-consistent edit per stored option and per class of stored
 *    values (invalid eps, alpha, sigma, thermostat, dt, wall rule; the step against the time, the
 *    time, e_initial, the clamp count, stress_t0, dt_max, the reserved slot; a particle at x = L,
 *    below 0, a velocity of 1e300 (square not finite) and of 1e150 (more energy than the ledger
 *    holds), a cell reference velocity of 1e200, zero and near-zero RNG states of the grid shift
 *    and of a cell) is refused with GRAN_ERR_IO naming the field; the unedited file reads;
 *  - gran_scene_resume: a valid but different option in the stored state (eps, alpha, sigma,
 *    thermostat, shear rate, acceleration, dt, T0, sort_every) is refused naming the option, and a
 *    checkpoint whose next_index claims rows that were never recorded (or fewer than were) is
 *    refused naming next_index. */
#include <stddef.h>

#include "io_test_util.h"

/* ---- the binary layout of gran_srd_checkpoint_write (src/srd/engine.cpp) ---- */
enum { kOpt = 8, kSc = kOpt + (int)sizeof(gran_srd_options), kIc = kSc + 12 * 8, kShift = kIc + 3 * 8, kX = kShift + 32 };

typedef struct {
  unsigned char *b;
  size_t n;
  int64_t np, ncell;
  int dim;
} ckp_img;

/* the trailer: total length (uint64) and the CRC-32 (zlib) of every byte before the CRC */
static void fix_crc(unsigned char *b, size_t n) {
  const uint32_t c = (uint32_t)crc32(crc32(0L, Z_NULL, 0), b, (uInt)(n - 4));
  memcpy(b + n - 4, &c, 4);
}

static gran_srd_options opts(void) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = 3;
  o.cells[0] = o.cells[1] = o.cells[2] = 4;
  o.n0 = 5;
  o.eps = 0.9;
  o.sigma = 0.2;
  o.seed = 77;
  o.shear_rate = 0.01;
  return o;
}

static ckp_img write_ckp(const char *path, int64_t steps) {
  gran_srd_options o = opts();
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, steps));
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(s, path, "/srd"));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  ckp_img c;
  c.b = io_read_all(path, &c.n);
  c.dim = 3;
  c.np = (int64_t)(o.n0 * 64 + 0.5);
  c.ncell = 64;
  return c;
}

/* offsets of the arrays */
static size_t off_x(const ckp_img *c, int axis) { return kX + (size_t)axis * 8 * (size_t)c->np; }
static size_t off_v(const ckp_img *c, int axis) { return kX + (size_t)(2 + axis) * 8 * (size_t)c->np; }
static size_t off_ref(const ckp_img *c) { return kX + (size_t)(2 * c->dim) * 8 * (size_t)c->np; }
static size_t off_rng(const ckp_img *c) { return off_ref(c) + (size_t)c->ncell * 24; }

/* Writes img with `len` bytes at `at` replaced by `val`, CRC recomputed; reads it and expects
 * GRAN_ERR_IO with `field` in the message. */
static void expect_refused(const ckp_img *c, const char *bad, size_t at, const void *val, size_t len,
                           const char *field) {
  unsigned char *b = malloc(c->n);
  assert_non_null(b);
  memcpy(b, c->b, c->n);
  memcpy(b + at, val, len);
  fix_crc(b, c->n);
  io_write_all(bad, b, c->n);
  free(b);
  gran_srd *t = NULL;
  const int rc = gran_srd_checkpoint_read(bad, "/srd", &t);
  if (rc != GRAN_ERR_IO || !strstr(gran_last_error_message(), field))
    fprintf(stderr, "edit of '%s' at byte %zu: rc %d, message: %s\n", field, at, rc, gran_last_error_message());
  assert_int_equal(rc, GRAN_ERR_IO);
  assert_null(t);
  assert_non_null(strstr(gran_last_error_message(), field));
}
static void edit_d(const ckp_img *c, const char *bad, size_t at, double v, const char *field) {
  expect_refused(c, bad, at, &v, 8, field);
}
static void edit_i64(const ckp_img *c, const char *bad, size_t at, int64_t v, const char *field) {
  expect_refused(c, bad, at, &v, 8, field);
}
static void edit_i32(const ckp_img *c, const char *bad, size_t at, int32_t v, const char *field) {
  expect_refused(c, bad, at, &v, 4, field);
}

static void test_reader_edits(void **state) {
  (void)state;
  const char *path = io_path("a.ckp"), *bad = io_path("bad.ckp");
  ckp_img c = write_ckp(path, 9);
  gran_srd *t = NULL;
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(path, "/srd", &t)); /* the file as written */
  GRAN_ASSERT_OK(gran_srd_destroy(&t));
  /* options: the same check as gran_srd_create, naming the option */
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, eps), 1.5, "'eps'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, alpha_deg), 0.0, "'alpha'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, sigma), -1.0, "'sigma'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, sigma), NAN, "'sigma'");
  edit_i32(&c, bad, kOpt + offsetof(gran_srd_options, thermostat), 7, "'thermostat'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, dt), -1.0, "'dt'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, T0), 0.0, "'T0'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, shear_rate), INFINITY, "'shear_rate'");
  edit_d(&c, bad, kOpt + offsetof(gran_srd_options, accel), NAN, "'accel[0]'");
  /* scalars: time, e_initial, e_collisions, e_external, dt_max, flux_kin, flux_coll, stress_t0,
   * wall impulses, reserved */
  edit_d(&c, bad, kSc + 0 * 8, 1e300, "'time'");
  edit_d(&c, bad, kSc + 0 * 8, 4.0, "'time'"); /* 9 steps of dt = 1 */
  edit_d(&c, bad, kSc + 1 * 8, 0.0, "'e_initial'");
  edit_d(&c, bad, kSc + 1 * 8, -5.0, "'e_initial'");
  edit_d(&c, bad, kSc + 1 * 8, NAN, "'e_initial'");
  edit_d(&c, bad, kSc + 2 * 8, -1e9, "'e_collisions'"); /* a negative kinetic energy */
  edit_d(&c, bad, kSc + 3 * 8, INFINITY, "'e_external'");
  edit_d(&c, bad, kSc + 4 * 8, 0.0, "'dt_max'");
  edit_d(&c, bad, kSc + 5 * 8, NAN, "'flux_kin'");
  edit_d(&c, bad, kSc + 7 * 8, -1.0, "'stress_t0'");
  edit_d(&c, bad, kSc + 7 * 8, 100.0, "'stress_t0'");
  edit_d(&c, bad, kSc + 9 * 8, INFINITY, "'wall_impulse[1]'");
  edit_d(&c, bad, kSc + 11 * 8, 3.0, "'reserved'");
  /* integers: step, clamped, n */
  edit_i64(&c, bad, kIc + 0, 10, "'time'"); /* one step more than the time holds */
  edit_i64(&c, bad, kIc + 0, INT64_C(9200000000000000000), "'time'");
  edit_i64(&c, bad, kIc + 0, -1, "'step'");
  edit_i64(&c, bad, kIc + 8, -1, "'clamped'");
  edit_i64(&c, bad, kIc + 8, INT64_C(9200000000000000000), "'clamped'");
  edit_i64(&c, bad, kIc + 16, c.np + 1, "'n'");
  /* positions: [0, L) on each axis; L = 4 */
  edit_d(&c, bad, off_x(&c, 0) + 8 * 3, 4.0, "'x'");
  edit_d(&c, bad, off_x(&c, 1) + 8 * 5, -1e-300, "'y'");
  edit_d(&c, bad, kX + 4 * 8 * (size_t)c.np + 8 * 2, 4.0, "'z'"); /* 3-D: z after vx, vy */
  /* velocities: finite squares, and no particle above 1e3 x the stored kinetic energy */
  {
    ckp_img c3 = c;
    const size_t vz = kX + 5 * 8 * (size_t)c.np;
    edit_d(&c3, bad, off_v(&c3, 0) + 8 * 7, 1e300, "'vx'");
    edit_d(&c3, bad, off_v(&c3, 1) + 8 * 7, 1e155, "'vy'");
    edit_d(&c3, bad, off_v(&c3, 0) + 8 * 7, 1e150, "'v' of particle 7");
    edit_d(&c3, bad, off_v(&c3, 0) + 8 * 7, 1e4, "'v' of particle 7"); /* E_kin ~ 480 for T0 = 1 */
    edit_d(&c3, bad, vz + 8 * 11, NAN, "'vz'");
  }
  /* cell reference velocities */
  edit_d(&c, bad, off_ref(&c) + 24 * 5, 1e200, "'cell reference velocity'");
  edit_d(&c, bad, off_ref(&c) + 24 * 5 + 8, NAN, "'cell reference velocity'");
  /* RNG states: zero (xoshiro's forbidden state) and near zero */
  {
    const uint64_t zero[4] = {0, 0, 0, 0}, one[4] = {1, 0, 0, 0}, few[4] = {0xff, 0, 0x3, 0};
    const uint64_t full[4] = {~0ull, ~0ull, ~0ull, ~0ull};
    expect_refused(&c, bad, kShift, zero, 32, "'shift_rng'");
    expect_refused(&c, bad, kShift, one, 32, "'shift_rng'");
    expect_refused(&c, bad, off_rng(&c) + 32 * 9, zero, 32, "'rng' of cell 9");
    expect_refused(&c, bad, off_rng(&c) + 32 * 9, few, 32, "'rng' of cell 9");
    expect_refused(&c, bad, off_rng(&c) + 32 * 63, full, 32, "'rng' of cell 63");
  }
  free(c.b);
  /* a checkpoint at step 0: time 0 exactly, and a reader of it continues */
  c = write_ckp(path, 0);
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(path, "/srd", &t));
  GRAN_ASSERT_OK(gran_srd_advance(t, 2));
  GRAN_ASSERT_OK(gran_srd_destroy(&t));
  edit_d(&c, bad, kSc + 0 * 8, 1e-300, "'time'");
  free(c.b);
}

/* ---- through the run driver ---------------------------------------------------------------- */
static const char *scene_text(const char *out) {
  static char text[1024];
  snprintf(text, sizeof text,
           "title = \"t815\"\n[engine]\ntype = \"srd\"\ndimension = 2\ncells = [6, 6]\nn0 = 5\ndt = 0.5\n"
           "eps = 0.95\nsigma = 0.1\nsteps = 24\nseed = 3\nsort_every = 5\nthermostat = false\n"
           "[boundaries]\nlees_edwards = {shear_rate = 0.02}\n"
           "[observables]\nevery = 4\n"
           "[output]\npath = \"%s\"\ncheckpoint_every = 2\n",
           out);
  return text;
}

/* the /engine/state blob of a run checkpoint */
static unsigned char *read_blob(hid_t f, size_t *n) {
  hid_t d = H5Dopen2(f, "/engine/state", H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  *n = (size_t)H5Sget_simple_extent_npoints(sp);
  unsigned char *b = malloc(*n);
  assert_true(H5Dread(d, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, b) >= 0);
  H5Sclose(sp);
  H5Dclose(d);
  return b;
}

/* copy of checkpoint src with len bytes at `at` of the GSRD state replaced (state CRC and file
 * checksum recomputed) */
static void edit_state(const char *src, const char *dst, size_t at, const void *val, size_t len) {
  size_t n = 0;
  unsigned char *b = io_read_all(src, &n);
  io_write_all(dst, b, n);
  free(b);
  hid_t f = H5Fopen(dst, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t m = 0;
  unsigned char *s = read_blob(f, &m);
  memcpy(s + at, val, len);
  fix_crc(s, m);
  hid_t d = H5Dopen2(f, "/engine/state", H5P_DEFAULT);
  assert_true(H5Dwrite(d, H5T_NATIVE_UCHAR, H5S_ALL, H5S_ALL, H5P_DEFAULT, s) >= 0);
  H5Dclose(d);
  free(s);
  H5Fclose(f);
  io_refresh_crc(dst);
}
static void edit_root_attr(const char *src, const char *dst, const char *name, int64_t v) {
  size_t n = 0;
  unsigned char *b = io_read_all(src, &n);
  io_write_all(dst, b, n);
  free(b);
  hid_t f = H5Fopen(dst, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  assert_true(a >= 0);
  assert_true(H5Awrite(a, H5T_NATIVE_INT64, &v) >= 0);
  H5Aclose(a);
  H5Fclose(f);
  io_refresh_crc(dst);
}

static void expect_resume_refused(const char *ck, const char *out, const char *field) {
  const int rc = gran_scene_resume(ck, out, NULL, NULL);
  if (rc != GRAN_ERR_IO || !strstr(gran_last_error_message(), field))
    fprintf(stderr, "resume with '%s' edited: rc %d, message: %s\n", field, rc, gran_last_error_message());
  assert_int_equal(rc, GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), field));
  assert_false(io_exists(out));
}

static void test_resume_edits(void **state) {
  (void)state;
  const char *out = io_path("run.h5"), *ck = io_path("run.ckpt"), *ed = io_path("edited.ckpt"),
             *out2 = io_path("edited.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(scene_text(out), "t815.toml", &s));
  gran_run_control ctl;
  memset(&ctl, 0, sizeof ctl);
  ctl.stop_after_checkpoints = 1; /* after output times 0, 1 (steps 0, 4) */
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, out, ck, &ctl, &res));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  assert_int_equal(res.finished, 0);
  /* valid values of another run: every physics option is compared with the scene */
  struct {
    size_t off;
    double d;
    int32_t i;
    int is_int;
    const char *name;
  } e[] = {
      {offsetof(gran_srd_options, eps), 0.5, 0, 0, "'eps'"},
      {offsetof(gran_srd_options, alpha_deg), 45.0, 0, 0, "'alpha'"},
      {offsetof(gran_srd_options, sigma), 0.3, 0, 0, "'sigma'"},
      {offsetof(gran_srd_options, thermostat), 0, 1, 1, "'thermostat'"},
      {offsetof(gran_srd_options, shear_rate), 0.05, 0, 0, "'shear_rate'"},
      {offsetof(gran_srd_options, accel) + 8, -0.01, 0, 0, "'accel[1]'"},
      {offsetof(gran_srd_options, dt), 0.25, 0, 0, "'dt'"},
      {offsetof(gran_srd_options, T0), 2.0, 0, 0, "'T0'"},
      {offsetof(gran_srd_options, sort_every), 0, 9, 1, "'sort_every'"},
      {offsetof(gran_srd_options, wall_T), 0.5, 0, 0, "'wall_T'"},
  };
  for (size_t k = 0; k < sizeof e / sizeof e[0]; k++) {
    if (e[k].is_int) edit_state(ck, ed, kOpt + e[k].off, &e[k].i, 4);
    else edit_state(ck, ed, kOpt + e[k].off, &e[k].d, 8);
    expect_resume_refused(ed, out2, e[k].name);
  }
  /* rows never recorded: next_index 2 is the checkpoint's; 3, 4 claim rows that were not
   * recorded, 1 drops one */
  for (int64_t next = 1; next <= 4; next++) {
    if (next == 2) continue;
    edit_root_attr(ck, ed, "next_index", next);
    expect_resume_refused(ed, out2, "next_index");
  }
  /* the unedited checkpoint resumes */
  GRAN_ASSERT_OK(gran_scene_resume(ck, out2, NULL, &res));
  assert_int_equal(res.finished, 1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_reader_edits),
      cmocka_unit_test(test_resume_edits),
  };
  io_tmp("t815");
  const int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
