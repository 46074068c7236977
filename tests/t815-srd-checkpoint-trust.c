/* t815-srd-checkpoint-trust.c - a GSRD checkpoint (an HDF5 group "granary-srd-state 1" of named
 * fields, src/srd/checkpoint.cpp) is validated value by value, not trusted once its checksum
 * matches:
 *  - gran_srd_checkpoint_read: one checksum-consistent edit per stored option and per class of
 *    stored values (invalid eps, alpha, sigma, thermostat, dt, T0, shear rate, acceleration, wall
 *    rule, dimension, cells, n0; the step against the time, the time, e_initial, the clamp count,
 *    stress_t0, dt_max, flux and wall impulse; a particle at x = L, below 0, a velocity of 1e300
 *    (square not finite) and of 1e150 (more energy than the ledger holds), a cell reference velocity
 *    of 1e200, zero and near-zero RNG states of the grid shift and of a cell) is refused with
 *    GRAN_ERR_IO naming the field; every stored field (but options/creation: absent in states
 *    written before it, read as serial creation) removed, lengthened by one value, shortened
 *    or stored with another type is refused naming it; the unedited file reads;
 *  - gran_scene_resume: a valid but different value of every stored option that the run's scene
 *    fixes (every field of gran_srd_options but threads and device; the seed against the
 *    replica's) is refused naming the option, and a checkpoint whose next_index claims rows that
 *    were never recorded (or fewer than were) is refused naming next_index. */
#include <stddef.h>

#include "io_test_util.h"

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

enum { kNp = 320, kNcell = 64 }; /* n0 x cells, cells of the binning grid (periodic) */

static void write_ckp(const char *path, int64_t steps) {
  gran_srd_options o = opts();
  gran_srd *s = NULL;
  remove(path);
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, steps));
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(s, path, "/srd"));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* reads `bad` and expects GRAN_ERR_IO with `field` in the message */
static void expect_read_refused(const char *bad, const char *what, const char *field) {
  gran_srd *t = NULL;
  const int rc = gran_srd_checkpoint_read(bad, "/srd", &t);
  if (rc != GRAN_ERR_IO || !strstr(gran_last_error_message(), field))
    fprintf(stderr, "edit of '%s' (%s): rc %d, message: %s\n", field, what, rc, gran_last_error_message());
  assert_int_equal(rc, GRAN_ERR_IO);
  assert_null(t);
  assert_non_null(strstr(gran_last_error_message(), field));
}
/* dataset[index] = v (double / int64 / int32 / uint64 values), checksum recomputed, then refused */
static void edit_d(const char *path, const char *bad, const char *ds, int64_t index, double v, const char *field) {
  char d[128];
  snprintf(d, sizeof d, "/srd/%s", ds);
  io_edit_raw(path, bad, d, index, &v, 1, H5T_NATIVE_DOUBLE);
  expect_read_refused(bad, ds, field);
}
static void edit_i64(const char *path, const char *bad, const char *ds, int64_t index, int64_t v, const char *field) {
  char d[128];
  snprintf(d, sizeof d, "/srd/%s", ds);
  io_edit_raw(path, bad, d, index, &v, 1, H5T_NATIVE_INT64);
  expect_read_refused(bad, ds, field);
}
static void edit_i32(const char *path, const char *bad, const char *ds, int32_t v, const char *field) {
  char d[128];
  snprintf(d, sizeof d, "/srd/%s", ds);
  io_edit_raw(path, bad, d, 0, &v, 1, H5T_NATIVE_INT32);
  expect_read_refused(bad, ds, field);
}
static void edit_rng(const char *path, const char *bad, const char *ds, int64_t cell, const uint64_t v[4],
                     const char *field) {
  char d[128];
  snprintf(d, sizeof d, "/srd/%s", ds);
  io_edit_raw(path, bad, d, 4 * cell, v, 4, H5T_NATIVE_UINT64);
  expect_read_refused(bad, ds, field);
}

/* the names of every dataset below /srd (options/NAME included) */
typedef struct {
  char name[64][48];
  int n;
} ds_list;
static void list_group(hid_t f, const char *grp, const char *prefix, ds_list *l) {
  hid_t g = H5Gopen2(f, grp, H5P_DEFAULT);
  assert_true(g >= 0);
  H5G_info_t gi;
  assert_true(H5Gget_info(g, &gi) >= 0);
  for (hsize_t i = 0; i < gi.nlinks && l->n < 64; i++) {
    char nm[40];
    assert_true(H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, nm, sizeof nm, H5P_DEFAULT) > 0);
    hid_t o = H5Oopen(g, nm, H5P_DEFAULT);
    if (H5Iget_type(o) == H5I_DATASET) snprintf(l->name[l->n++], sizeof l->name[0], "%s%s", prefix, nm);
    H5Oclose(o);
  }
  H5Gclose(g);
}
static ds_list datasets(const char *path) {
  ds_list l;
  memset(&l, 0, sizeof l);
  hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  list_group(f, "/srd", "", &l);
  list_group(f, "/srd/options", "options/", &l);
  H5Fclose(f);
  return l;
}
/* Copy of path with dataset /srd/NAME rewritten as a float of another size (or an integer of
 * another sign): the reader takes no value through a conversion. */
static void edit_type(const char *path, const char *bad, const char *name) {
  size_t n = 0;
  unsigned char *b = io_read_all(path, &n);
  io_write_all(bad, b, n);
  free(b);
  char d[128];
  snprintf(d, sizeof d, "/srd/%s", name);
  hid_t f = H5Fopen(bad, H5F_ACC_RDWR, H5P_DEFAULT);
  hid_t ds = H5Dopen2(f, d, H5P_DEFAULT);
  hid_t sp = H5Dget_space(ds), ft = H5Dget_type(ds);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  double *v = (double *)calloc((size_t)np + 1, sizeof *v);
  assert_true(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  const hid_t nt = H5Tget_class(ft) == H5T_FLOAT ? H5T_NATIVE_FLOAT : H5T_NATIVE_DOUBLE;
  H5Tclose(ft);
  H5Dclose(ds);
  assert_true(H5Ldelete(f, d, H5P_DEFAULT) >= 0);
  ds = H5Dcreate2(f, d, nt, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(ds >= 0 && H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) >= 0);
  free(v);
  H5Dclose(ds);
  H5Sclose(sp);
  H5Fclose(f);
  io_refresh_crc(bad);
}

static void test_reader_edits(void **state) {
  (void)state;
  const char *path = io_path("a.ckp"), *bad = io_path("bad.ckp");
  write_ckp(path, 9);
  gran_srd *t = NULL;
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(path, "/srd", &t)); /* the file as written */
  GRAN_ASSERT_OK(gran_srd_destroy(&t));
  /* options: the same check as gran_srd_create, naming the option */
  edit_d(path, bad, "options/eps", 0, 1.5, "'eps'");
  edit_d(path, bad, "options/alpha", 0, 0.0, "'alpha'");
  edit_d(path, bad, "options/sigma", 0, -1.0, "'sigma'");
  edit_d(path, bad, "options/sigma", 0, NAN, "'sigma'");
  edit_d(path, bad, "options/sigma", 0, 1e300, "'sigma'");
  edit_i32(path, bad, "options/thermostat", 7, "'thermostat'");
  edit_d(path, bad, "options/dt", 0, -1.0, "'dt'");
  edit_d(path, bad, "options/T0", 0, 0.0, "'T0'");
  edit_d(path, bad, "options/shear_rate", 0, INFINITY, "'shear_rate'");
  edit_d(path, bad, "options/accel", 0, NAN, "'accel[0]'");
  edit_i32(path, bad, "options/dim", 4, "'dim'");
  edit_i32(path, bad, "options/wall_axis", 7, "'wall_axis'");
  edit_i32(path, bad, "options/threads", -3, "'threads'");
  edit_i32(path, bad, "options/sort_every", -1, "'sort_every'");
  edit_i32(path, bad, "options/creation", 7, "'creation'");
  edit_i64(path, bad, "options/cells", 1, 0, "'cells[1]'");
  edit_d(path, bad, "options/n0", 0, -5.0, "'n0'");
  edit_d(path, bad, "options/a", 0, 0.0, "'a'");
  /* valid options of another run: the arrays they imply are not the stored ones */
  edit_d(path, bad, "options/n0", 0, 6.0, "'x'");
  edit_i64(path, bad, "options/cells", 2, 5, "'x'");
  /* scalars: time, e_initial, e_collisions, e_external, dt_max, flux_kin, flux_coll, stress_t0,
   * wall impulses */
  edit_d(path, bad, "time", 0, 1e300, "'time'");
  edit_d(path, bad, "time", 0, 4.0, "'time'"); /* 9 steps of dt = 1 */
  edit_d(path, bad, "e_initial", 0, 0.0, "'e_initial'");
  edit_d(path, bad, "e_initial", 0, -5.0, "'e_initial'");
  edit_d(path, bad, "e_initial", 0, NAN, "'e_initial'");
  edit_d(path, bad, "e_collisions", 0, -1e9, "'e_collisions'"); /* a negative kinetic energy */
  edit_d(path, bad, "e_external", 0, INFINITY, "'e_external'");
  edit_d(path, bad, "dt_max", 0, 0.0, "'dt_max'");
  edit_d(path, bad, "flux_kin", 0, NAN, "'flux_kin'");
  edit_d(path, bad, "flux_coll", 0, -INFINITY, "'flux_coll'");
  edit_d(path, bad, "stress_t0", 0, -1.0, "'stress_t0'");
  edit_d(path, bad, "stress_t0", 0, 100.0, "'stress_t0'");
  edit_d(path, bad, "wall_impulse", 1, INFINITY, "'wall_impulse[1]'");
  /* integers: step, clamped, n */
  edit_i64(path, bad, "step", 0, 10, "'time'"); /* one step more than the time holds */
  edit_i64(path, bad, "step", 0, INT64_C(9200000000000000000), "'time'");
  edit_i64(path, bad, "step", 0, -1, "'step'");
  edit_i64(path, bad, "clamped", 0, -1, "'clamped'");
  edit_i64(path, bad, "clamped", 0, INT64_C(9200000000000000000), "'clamped'");
  edit_i64(path, bad, "n", 0, kNp + 1, "'n'");
  /* positions: [0, L) on each axis; L = 4 */
  edit_d(path, bad, "x", 3, 4.0, "'x'");
  edit_d(path, bad, "y", 5, -1e-300, "'y'");
  edit_d(path, bad, "z", 2, 4.0, "'z'");
  edit_d(path, bad, "z", 2, NAN, "'z'");
  /* velocities: finite squares, and no particle above 1e3 x the stored kinetic energy */
  edit_d(path, bad, "vx", 7, 1e300, "'vx'");
  edit_d(path, bad, "vy", 7, 1e155, "'vy'");
  edit_d(path, bad, "vx", 7, 1e150, "'v' of particle 7");
  edit_d(path, bad, "vx", 7, 1e4, "'v' of particle 7"); /* E_kin ~ 480 for T0 = 1 */
  edit_d(path, bad, "vz", 11, NAN, "'vz'");
  /* cell reference velocities */
  edit_d(path, bad, "cell_velocity", 3 * 5, 1e200, "'cell_velocity'");
  edit_d(path, bad, "cell_velocity", 3 * 5 + 1, NAN, "'cell_velocity'");
  /* RNG states: zero (xoshiro's forbidden state) and near zero */
  {
    const uint64_t zero[4] = {0, 0, 0, 0}, one[4] = {1, 0, 0, 0}, few[4] = {0xff, 0, 0x3, 0};
    const uint64_t full[4] = {~0ull, ~0ull, ~0ull, ~0ull};
    edit_rng(path, bad, "shift_rng", 0, zero, "'shift_rng'");
    edit_rng(path, bad, "shift_rng", 0, one, "'shift_rng'");
    edit_rng(path, bad, "rng", 9, zero, "'rng' of cell 9");
    edit_rng(path, bad, "rng", 9, few, "'rng' of cell 9");
    edit_rng(path, bad, "rng", kNcell - 1, full, "'rng' of cell 63");
  }
  /* every stored field: removed, one value more, one fewer, another type: refused naming it */
  {
    const ds_list l = datasets(path);
    assert_int_equal(l.n, 23 + 21); /* the 23 options and 21 state fields of a 3-D run */
    for (int k = 0; k < l.n; k++) {
      char d[128], field[64];
      snprintf(d, sizeof d, "/srd/%s", l.name[k]);
      const char *leaf = strrchr(l.name[k], '/') ? strrchr(l.name[k], '/') + 1 : l.name[k];
      snprintf(field, sizeof field, "'%s'", leaf);
      hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
      hid_t ds = H5Dopen2(f, d, H5P_DEFAULT), sp = H5Dget_space(ds);
      const int64_t np = (int64_t)H5Sget_simple_extent_npoints(sp);
      H5Sclose(sp);
      H5Dclose(ds);
      H5Fclose(f);
      io_edit_resize(path, bad, d, -1);
      if (!strcmp(leaf, "creation")) { /* a state written before the option: serial creation */
        gran_srd *r = NULL;
        GRAN_ASSERT_OK(gran_srd_checkpoint_read(bad, "/srd", &r));
        char again[700];
        snprintf(again, sizeof again, "%s.again", bad);
        GRAN_ASSERT_OK(gran_srd_checkpoint_write(r, again, "/srd"));
        gran_srd_destroy(&r);
        hid_t fa = H5Fopen(again, H5F_ACC_RDONLY, H5P_DEFAULT);
        int32_t cr = -1;
        hid_t dc = H5Dopen2(fa, "/srd/options/creation", H5P_DEFAULT);
        assert_true(dc >= 0 && H5Dread(dc, H5T_NATIVE_INT32, H5S_ALL, H5S_ALL, H5P_DEFAULT, &cr) >= 0);
        assert_int_equal(cr, GRAN_SRD_CREATE_SERIAL);
        H5Dclose(dc);
        H5Fclose(fa);
        remove(again);
      } else {
        expect_read_refused(bad, "removed", field);
      }
      io_edit_resize(path, bad, d, np + 1);
      expect_read_refused(bad, "one value more", field);
      io_edit_resize(path, bad, d, np - 1);
      expect_read_refused(bad, "one value fewer", field);
      edit_type(path, bad, l.name[k]);
      expect_read_refused(bad, "another type", field);
    }
  }
  /* the group's format: another version, or none */
  {
    size_t n = 0;
    unsigned char *b = io_read_all(path, &n);
    io_write_all(bad, b, n);
    free(b);
    hid_t f = H5Fopen(bad, H5F_ACC_RDWR, H5P_DEFAULT);
    hid_t g = H5Gopen2(f, "/srd", H5P_DEFAULT);
    assert_true(H5Adelete(g, "format") >= 0);
    H5Gclose(g);
    H5Fclose(f);
    io_refresh_crc(bad);
    expect_read_refused(bad, "format removed", "not a GSRD engine state");
    gran_srd *u = NULL;
    GRAN_ASSERT_ERR(gran_srd_checkpoint_read(path, "/other", &u), GRAN_ERR_IO); /* no such group */
    assert_non_null(strstr(gran_last_error_message(), "'/other'"));
    assert_null(u);
  }
  /* a checkpoint at step 0: time 0 exactly, and a reader of it continues */
  write_ckp(path, 0);
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(path, "/srd", &t));
  GRAN_ASSERT_OK(gran_srd_advance(t, 2));
  GRAN_ASSERT_OK(gran_srd_destroy(&t));
  edit_d(path, bad, "time", 0, 1e-300, "'time'");
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

static void edit_root_attr(const char *src, const char *dst, const char *name, int64_t v) {
  hid_t f = io_copy_open(src, dst);
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
  /* valid values of another run: every stored option but threads and device is compared with
   * the scene's (the seed with the replica's) */
  struct {
    const char *ds;
    int64_t index;
    double d;
    int type; /* 0 double, 1 int32, 2 int64, 3 uint64 */
    const char *name;
  } e[] = {
      {"options/eps", 0, 0.5, 0, "'eps'"},
      {"options/alpha", 0, 45.0, 0, "'alpha'"},
      {"options/sigma", 0, 0.3, 0, "'sigma'"},
      {"options/thermostat", 0, 1, 1, "'thermostat'"},
      {"options/shear_rate", 0, 0.05, 0, "'shear_rate'"},
      {"options/accel", 1, -0.01, 0, "'accel[1]'"},
      {"options/accel", 0, 0.01, 0, "'accel[0]'"},
      {"options/dt", 0, 0.25, 0, "'dt'"},
      {"options/T0", 0, 2.0, 0, "'T0'"},
      {"options/sort_every", 0, 9, 1, "'sort_every'"},
      {"options/wall_T", 0, 0.5, 0, "'wall_T'"},
      {"options/a", 0, 2.0, 0, "'a'"},
      {"options/n0", 0, 6.0, 0, "'n0'"},
      {"options/cells", 0, 7, 2, "'cells[0]'"},
      {"options/cells", 1, 5, 2, "'cells[1]'"},
      {"options/dim", 0, 3, 1, "'dim'"},
      {"options/wall_axis", 0, 2, 1, "'wall_axis'"},
      {"options/vib_amp", 0, 0.1, 0, "'vib_amp'"},
      {"options/vib_omega", 0, 0.2, 0, "'vib_omega'"},
      {"options/precision", 0, 1, 1, "'precision'"},
      {"options/creation", 0, 1, 1, "'creation'"},
      {"options/seed", 0, 4, 3, "'seed'"},
  };
  for (size_t k = 0; k < sizeof e / sizeof e[0]; k++) {
    char d[128];
    snprintf(d, sizeof d, "/engine/%s", e[k].ds);
    const int32_t i32 = (int32_t)e[k].d;
    const int64_t i64 = (int64_t)e[k].d;
    const uint64_t u64 = (uint64_t)e[k].d;
    if (e[k].type == 0) io_edit_raw(ck, ed, d, e[k].index, &e[k].d, 1, H5T_NATIVE_DOUBLE);
    else if (e[k].type == 1) io_edit_raw(ck, ed, d, e[k].index, &i32, 1, H5T_NATIVE_INT32);
    else if (e[k].type == 2) io_edit_raw(ck, ed, d, e[k].index, &i64, 1, H5T_NATIVE_INT64);
    else io_edit_raw(ck, ed, d, e[k].index, &u64, 1, H5T_NATIVE_UINT64);
    expect_resume_refused(ed, out2, e[k].name);
  }
  /* threads and device are how, not what, a run computes: a state written with 3 threads resumes
   * (with the resuming run's threads) into the output of the run done in one go, bit for bit */
  {
    const char *full = io_path("full.h5");
    gran_scene *s1 = NULL;
    GRAN_ASSERT_OK(gran_scene_parse(scene_text(full), "t815.toml", &s1));
    GRAN_ASSERT_OK(gran_scene_run(s1, full, io_path("full.ckpt"), NULL, &res));
    GRAN_ASSERT_OK(gran_scene_destroy(&s1));
    const int32_t th = 3;
    io_edit_raw(ck, ed, "/engine/options/threads", 0, &th, 1, H5T_NATIVE_INT32);
    GRAN_ASSERT_OK(gran_scene_resume(ed, out2, NULL, &res));
    assert_int_equal(res.finished, 1);
    int nd = 0;
    char first[512] = "";
    const int ndiff = io_h5_compare(full, out2, &nd, first, sizeof first);
    if (ndiff) fprintf(stderr, "resumed output differs from the run in one go: %d of %d datasets, first '%s'\n", ndiff,
                       nd, first);
    assert_int_equal(ndiff, 0);
    assert_true(nd > 5);
    remove(out2);
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
