/* t527-dsmc-agg-scene.c - the [aggregation] table of a scene, for every selector: an aggregating,
 * fragmenting scene with selector "lowrank" and "bird" runs through the run driver, writes
 * clusters/n within 4 sqrt(n) + 1.5 % of clusters/n_theory (as t522 for the cell selector) and a
 * closing ledger; a run split by a checkpoint writes the same datasets bit for bit; the same keys
 * drive the cell selector (e_agg, e_frag, eps_f, frag_law into gran_dsmc_cell_options);
 * gran_scene_dsmc equals gran_dsmc_create_agg with gran_scene_dsmc_agg_options; bad keys named;
 * checkpoint files: a format 3 file of the cell selector (no fragment law) still reads and continues
 * bit for bit; damaged aggregation blocks of the event selectors are refused; a run checkpoint whose
 * stored [cell] or [aggregation] options were edited is refused on resume naming the option. */
#include "io_test_util.h"
#include "agg_test_util.h"

static char *scene(const char *selector, const char *cell, const char *agg, const char *out) {
  static char buf[4096];
  snprintf(buf, sizeof buf,
           "[mixture]\nnspecies = 30\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.01, theta = 400.0 }\n"
           "[restitution]\neps = 0.9\n[initial]\ntemperatures = \"equal\"\n"
           "[engine]\nselector = \"%s\"\nvolume = 5e6\nseed = 3\nt_end = 40.0\n"
           "%s\n[aggregation]\n%s\n"
           "[observables]\ntimes = [10.0, 20.0, 40.0]\nmsd = false\n[output]\npath = \"%s\"\ncheckpoint_every = 1\n",
           selector, cell, agg, out);
  return buf;
}

static void run_case(const char *selector) {
  char out[600], split[600], ck[600];
  snprintf(out, sizeof out, "%s", io_path("agg.h5"));
  snprintf(split, sizeof split, "%s", io_path("agg-split.h5"));
  snprintf(ck, sizeof ck, "%s", io_path("agg.ckpt"));
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(scene(selector, "", "e_agg = 1.0\ne_frag = 3.0\neps_f = 0.7", split), "agg.toml", &s));
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, &res));
  assert_int_equal(res.finished, 1);
  gran_run_control ctl = {1, NULL, NULL}; /* stop after the first output, resume from the checkpoint */
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  int nds = 0;
  char first[512] = "";
  const int ndiff = io_h5_compare(out, split, &nds, first, sizeof first);
  if (ndiff) fail_msg("%s: %d of %d datasets differ, first %s", selector, ndiff, nds, first);
  agg_check_run_output(out, 30);
  gran_scene_destroy(&s);
}

static void test_lowrank(void **state) {
  (void)state;
  run_case("lowrank");
}
static void test_bird(void **state) {
  (void)state;
  run_case("bird");
}

/* the scene's engine is gran_dsmc_create_agg with its options; the cell selector takes the keys */
static void test_scene_engine(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(scene("bird", "", "e_agg = 0.5\nfrag_law = \"binary\"\ne_frag = 2.0", "x.h5"), "a.toml", &s));
  gran_dsmc_agg_options a;
  GRAN_ASSERT_OK(gran_scene_dsmc_agg_options(s, &a));
  assert_true(a.e_agg == 0.5 && a.e_frag == 2.0 && a.eps_f == 1 && a.frag_law == GRAN_FRAG_BINARY);
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  gran_dsmc *x = NULL, *y = NULL;
  GRAN_ASSERT_OK(gran_scene_dsmc(s, mix, &x));
  gran_dsmc_options o;
  int64_t counts[30];
  int have = 0;
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &o, counts, &have));
  double T0[30];
  GRAN_ASSERT_OK(gran_scene_initial_temperatures(s, mix, T0, NULL));
  GRAN_ASSERT_OK(gran_dsmc_create_agg(mix, have ? counts : NULL, T0, &o, &a, &y));
  GRAN_ASSERT_OK(gran_dsmc_advance(x, 5.0));
  GRAN_ASSERT_OK(gran_dsmc_advance(y, 5.0));
  const gran_particles *px, *py;
  GRAN_ASSERT_OK(gran_dsmc_particles(x, &px));
  GRAN_ASSERT_OK(gran_dsmc_particles(y, &py));
  assert_int_equal(px->n, py->n);
  assert_memory_equal(px->v, py->v, 3 * sizeof(double) * (size_t)px->n);
  gran_dsmc_cluster_stats cx;
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(x, &cx));
  assert_true(cx.merges > 0 && cx.breakups > 0);
  gran_dsmc_destroy(&x);
  gran_dsmc_destroy(&y);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);
  /* the cell selector: [aggregation] fills the cell options */
  GRAN_ASSERT_OK(gran_scene_parse(scene("cell", "[cell]\ndt = 0.5\ncells = 2", "e_agg = 0.5\nfrag_law = \"binary\"\ne_frag = 2.0", "x.h5"),
                                  "c.toml", &s));
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_scene_dsmc_cell_options(s, &c));
  assert_true(c.e_agg == 0.5 && c.e_frag == 2.0 && c.frag_law == GRAN_FRAG_BINARY && c.dt == 0.5);
  GRAN_ASSERT_OK(gran_scene_dsmc_agg_options(s, &a));
  assert_true(a.e_agg == 0.5 && a.e_frag == 2.0 && a.frag_law == GRAN_FRAG_BINARY);
  gran_scene_destroy(&s);
  /* [cell] keys alone still work, and gran_scene_dsmc_agg_options reports them */
  GRAN_ASSERT_OK(gran_scene_parse(scene("cell", "[cell]\ndt = 0.5\ne_agg = 2.0", "", "x.h5"), "c.toml", &s));
  GRAN_ASSERT_OK(gran_scene_dsmc_agg_options(s, &a));
  assert_true(a.e_agg == 2.0 && isinf(a.e_frag) && a.frag_law == GRAN_FRAG_MONOMERS);
  GRAN_ASSERT_ERR(gran_scene_dsmc_agg_options(s, NULL), GRAN_ERR_ARG);
  gran_scene_destroy(&s);
}


static void test_bad_keys(void **state) {
  (void)state;
  agg_expect_parse_error(scene("lowrank", "", "e_agg = -1.0", "x.h5"), "aggregation.e_agg");
  agg_expect_parse_error(scene("lowrank", "", "e_frag = -1.0", "x.h5"), "aggregation.e_frag");
  agg_expect_parse_error(scene("bird", "", "eps_f = 1.5", "x.h5"), "aggregation.eps_f");
  agg_expect_parse_error(scene("bird", "", "frag_law = \"dust\"", "x.h5"), "aggregation.frag_law");
  agg_expect_parse_error(scene("bird", "", "nonsense = 1", "x.h5"), "aggregation.nonsense");
  agg_expect_parse_error(scene("cell", "[cell]\ndt = 0.5\ne_agg = 1.0", "e_agg = 1.0", "x.h5"), "aggregation.e_agg");
}

/* a run checkpoint whose stored engine options were edited (checksum recomputed) is refused on
 * resume naming the option: the options of the [cell] table and of [aggregation] are compared with
 * the scene stored beside them, as the engine options are */
static void resume_edited(const char *selector, const char *cell, const char *dataset, int64_t index, double value,
                          int is_int, const char *want) {
  char ck[600], ed[600];
  snprintf(ck, sizeof ck, "%s", io_path("edit.ckpt"));
  snprintf(ed, sizeof ed, "%s", io_path("edited.ckpt"));
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(scene(selector, cell, "e_agg = 1.0\ne_frag = 3.0\neps_f = 0.7", io_path("edit.h5")),
                                  "agg.toml", &s));
  gran_run_control ctl = {1, NULL, NULL};
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  gran_scene_destroy(&s);
  io_edit_copy(ck, ed, dataset, index, value, is_int);
  GRAN_ASSERT_ERR(gran_scene_resume(ed, io_path("edited.h5"), NULL, NULL), GRAN_ERR_IO);
  const char *msg = gran_last_error_message();
  if (!strstr(msg, want) || !strstr(msg, "does not match the scene")) fail_msg("%s: message '%s' lacks '%s'", dataset, msg, want);
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res)); /* the unedited file resumes */
  assert_int_equal(res.finished, 1);
}

static void test_edited_options(void **state) {
  (void)state;
  const char *cell = "[cell]\ncells = 3\ndt = 0.5";
  resume_edited("bird", "", "/engine/agg_options_real", 0, 1.25, 0, "'agg_options.e_agg'");
  resume_edited("lowrank", "", "/engine/agg_options_real", 2, 0.5, 0, "'agg_options.eps_f'");
  resume_edited("cell", cell, "/engine/cell_options_real", 0, 0.25, 0, "'cell_options.dt'");
  resume_edited("cell", cell, "/engine/cell_options_real", 2, 1.5, 0, "'cell_options.e_agg'");
  resume_edited("cell", cell, "/engine/cell_options_real", 5, 0.1, 0, "'cell_options.heat_rate'");
  resume_edited("cell", cell, "/engine/cell_options_int", 2, GRAN_FRAG_BINARY, 1, "'cell_options.frag_law'");
}

/* ---- checkpoint files of aggregating engines ---- */

static gran_dsmc *agg_engine(int sel, gran_mixture *mix, uint64_t seed) {
  gran_dsmc_options o;
  GRAN_ASSERT_OK(gran_dsmc_options_default(&o));
  o.selector = sel;
  o.seed = seed;
  o.volume = 20000 / 0.01;
  gran_dsmc *d = NULL;
  if (sel == GRAN_SELECTOR_CELL) {
    gran_dsmc_cell_options c;
    GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
    c.dt = 0.5;
    c.cells = 3;
    c.e_agg = 1.0;
    c.e_frag = 2.0;
    c.eps_f = 0.7;
    GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d));
  } else {
    gran_dsmc_agg_options a;
    GRAN_ASSERT_OK(gran_dsmc_agg_options_default(&a));
    a.e_agg = 1.0;
    a.e_frag = 2.0;
    a.eps_f = 0.7;
    GRAN_ASSERT_OK(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d));
  }
  return d;
}

static void same_state(const gran_dsmc *a, const gran_dsmc *b) {
  const gran_particles *pa, *pb;
  GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
  GRAN_ASSERT_OK(gran_dsmc_particles(b, &pb));
  assert_int_equal(pa->n, pb->n);
  assert_memory_equal(pa->v, pb->v, 3 * sizeof(double) * (size_t)pa->n);
  assert_memory_equal(pa->species, pb->species, sizeof(int32_t) * (size_t)pa->n);
  gran_dsmc_cluster_stats ca, cb;
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(a, &ca));
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(b, &cb));
  assert_memory_equal(&ca, &cb, sizeof ca);
}

/* the format attribute of group /state */
static void set_format(hid_t f, const char *fmt) {
  hid_t g = H5Gopen2(f, "state", H5P_DEFAULT);
  H5Adelete(g, "format");
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, strlen(fmt));
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t at = H5Acreate2(g, "format", type, sp, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(at >= 0 && H5Awrite(at, type, fmt) >= 0);
  H5Aclose(at), H5Sclose(sp), H5Tclose(type), H5Gclose(g);
}

/* a format 3 file (before the fragment law: two cell option integers) still reads, as monomers,
 * and continues bit for bit */
static void test_format3(void **state) {
  (void)state;
  const char *path = io_path("f3.ckpt");
  gran_mixture *mix = NULL;
  double n[20] = {0.01};
  GRAN_ASSERT_OK(gran_mixture_create(20, NULL, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.9));
  gran_dsmc *a = agg_engine(GRAN_SELECTOR_CELL, mix, 5);
  GRAN_ASSERT_OK(gran_dsmc_advance(a, 13.0));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(a, path, "state"));
  hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  set_format(f, "granary-dsmc-state 3");
  int64_t ci[3];
  hid_t d = H5Dopen2(f, "state/cell_options_int", H5P_DEFAULT);
  H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ci);
  H5Dclose(d);
  assert_int_equal(ci[2], GRAN_FRAG_MONOMERS);
  H5Ldelete(f, "state/cell_options_int", H5P_DEFAULT);
  hsize_t two = 2;
  hid_t sp = H5Screate_simple(1, &two, NULL);
  d = H5Dcreate2(f, "state/cell_options_int", H5T_NATIVE_INT64, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  assert_true(H5Dwrite(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, ci) >= 0);
  H5Dclose(d), H5Sclose(sp), H5Fclose(f);
  io_refresh_crc(path);
  gran_dsmc *b = NULL;
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(path, "state", mix, &b));
  same_state(a, b);
  GRAN_ASSERT_OK(gran_dsmc_advance(a, 30.0));
  GRAN_ASSERT_OK(gran_dsmc_advance(b, 30.0));
  same_state(a, b);
  gran_dsmc_destroy(&a);
  gran_dsmc_destroy(&b);
  gran_mixture_destroy(&mix);
}

/* an int64 value of dataset /state/name set to v */
static void edit_i64(const char *path, const char *name, int64_t index, int64_t v) {
  hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  char full[128];
  snprintf(full, sizeof full, "state/%s", name);
  hid_t d = H5Dopen2(f, full, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  const hssize_t np = H5Sget_simple_extent_npoints(sp);
  int64_t *x = malloc((size_t)np * sizeof *x);
  H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, x);
  x[index] = v;
  H5Dwrite(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, x);
  free(x);
  H5Sclose(sp), H5Dclose(d), H5Fclose(f);
  io_refresh_crc(path);
}

/* damaged aggregation blocks of the event selectors are refused (GRAN_ERR_IO), never used */
static void test_damaged(void **state) {
  (void)state;
  const char *path = io_path("dmg.ckpt"), *copy = io_path("dmg-copy.ckpt");
  gran_mixture *mix = NULL;
  double n[20] = {0.01};
  GRAN_ASSERT_OK(gran_mixture_create(20, NULL, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.9));
  const struct {
    int sel;
    const char *name;
    int64_t index, value;
  } cases[] = {
      {GRAN_SELECTOR_LOWRANK, "agg_mpos", 7, 1 << 30},        /* a member position outside its list */
      {GRAN_SELECTOR_LOWRANK, "agg_slot_size", 0, 19},        /* a slot of the wrong size */
      {GRAN_SELECTOR_LOWRANK, "agg_free", 0, -3},             /* a free slot out of range */
      {GRAN_SELECTOR_LOWRANK, "agg_candidates", 2, 1 << 30},  /* a candidate slot out of range */
      {GRAN_SELECTOR_LOWRANK, "agg_counters", 4, 12345},      /* the mass */
      {GRAN_SELECTOR_BIRD, "agg_candidates", 0, -1},          /* a candidate particle out of range */
      {GRAN_SELECTOR_BIRD, "agg_nsize", 0, 5},                /* counts that are not the particles' */
      {GRAN_SELECTOR_BIRD, "agg_options_int", 0, 9},          /* an unknown fragment law */
  };
  for (int q = 0; q < 2; q++) {
    gran_dsmc *a = agg_engine(q == 0 ? GRAN_SELECTOR_LOWRANK : GRAN_SELECTOR_BIRD, mix, 6);
    GRAN_ASSERT_OK(gran_dsmc_advance(a, 20.0));
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(a, q == 0 ? path : copy, "state"));
    gran_dsmc_destroy(&a);
  }
  size_t nb = 0, nc = 0;
  unsigned char *orig = io_read_all(path, &nb), *orig2 = io_read_all(copy, &nc);
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    const int low = cases[c].sel == GRAN_SELECTOR_LOWRANK;
    io_write_all(path, low ? orig : orig2, low ? nb : nc);
    gran_dsmc *b = NULL;
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(path, "state", mix, &b)); /* intact */
    gran_dsmc_destroy(&b);
    edit_i64(path, cases[c].name, cases[c].index, cases[c].value);
    const int st = gran_dsmc_checkpoint_read(path, "state", mix, &b);
    if (st != GRAN_ERR_IO) fail_msg("%s[%lld] = %lld: status %d", cases[c].name, (long long)cases[c].index,
                                    (long long)cases[c].value, st);
    assert_null(b);
  }
  free(orig);
  free(orig2);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_keys),
      cmocka_unit_test(test_scene_engine),
      cmocka_unit_test(test_lowrank),
      cmocka_unit_test(test_bird),
      cmocka_unit_test(test_edited_options),
      cmocka_unit_test(test_format3),
      cmocka_unit_test(test_damaged),
  };
  io_tmp("t527"); /* every file in a private temporary folder */
  const int rc = cmocka_run_group_tests_name("t527-dsmc-agg-scene", tests, NULL, NULL);
  io_tmp_cleanup();
  return rc;
}
