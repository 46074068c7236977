/* t522-dsmc-cell-scene.c - the cell selector through scenes and the run driver: [engine] selector =
 * "cell" with a [cell] table runs, writes HDF5 (selector attribute "cell", T(t) within 2 % of the
 * kinetic theory written beside it), and a run split by a checkpoint writes the same datasets as
 * an uninterrupted one, bit for bit; gran_scene_dsmc builds the same engine as
 * gran_dsmc_create_cell with gran_scene_dsmc_cell_options; every bad [cell] key is refused with
 * GRAN_ERR_PARSE naming it. */
#include "io_test_util.h"
#include "agg_test_util.h"

static const char *kFmt =
    "title = \"cell\"\n"
    "[mixture]\n"
    "nspecies = 2\n"
    "mass = [1.0, 2.0]\n"
    "density = [0.01, 0.01]\n"
    "[restitution]\n"
    "eps = 0.8\n"
    "[initial]\n"
    "temperatures = \"hcs\"\n"
    "[engine]\n"
    "selector = \"cell\"\n"
    "counts = [4000, 4000]\n"
    "seed = 7\n"
    "t_end = 60.0\n"
    "[cell]\n"
    "dt = 0.5\n"
    "%s\n"
    "[observables]\n"
    "times = { linear = { start = 10.0, stop = 60.0, n = 6 } }\n"
    "temperatures = true\n"
    "msd = true\n"
    "energy = true\n"
    "collision_counts = true\n"
    "[output]\n"
    "path = \"%s\"\n"
    "checkpoint_every = 3\n";

static char *text(const char *extra, const char *out) {
  static char buf[4096];
  snprintf(buf, sizeof buf, kFmt, extra, out);
  return buf;
}

static void test_run_and_resume(void **state) {
  (void)state;
  char straight[600], split[600], ck[600];
  snprintf(straight, sizeof straight, "%s", io_path("straight.h5"));
  snprintf(split, sizeof split, "%s", io_path("split.h5"));
  snprintf(ck, sizeof ck, "%s", io_path("split.ckpt"));
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text("cells = 3", split), "cell.toml", &s));
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, straight, "", NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_true(res.collisions > 10000);
  gran_run_control ctl = {1, NULL, NULL};
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  int nds = 0;
  char first[512] = "";
  int ndiff = io_h5_compare(straight, split, &nds, first, sizeof first);
  if (ndiff) fail_msg("%d of %d datasets differ, first %s", ndiff, nds, first);
  assert_true(nds >= 5);
  hid_t f = H5Fopen(straight, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  char *sel = io_h5_attr_string(f, "selector");
  assert_non_null(sel);
  assert_string_equal(sel, "cell");
  free(sel);
  size_t n = 0, nt = 0;
  double *T = io_h5_read_double(f, "/temperatures/T", &n);
  double *Tt = io_h5_read_double(f, "/temperatures/T_theory", &nt);
  assert_int_equal(n, 12);
  assert_int_equal(nt, 12);
  /* 8000 particles: 1.6 % per species is 4 standard errors of T_k (sqrt(2/3/4000) = 1.3 %) plus
   * the first-Sonine error of the theory (about 1 %): 4 % */
  for (size_t i = 0; i < n; i++) GRAN_ASSERT_REL(T[i], Tt[i], 0.04);
  free(T);
  free(Tt);
  H5Fclose(f);
  gran_scene_destroy(&s);
}

static void test_scene_engine(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text("cells = 3\nfn = 2.0\nheat_rate = 0.001\nplacement = \"collision\"", "x.h5"), "c.toml", &s));
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_scene_dsmc_cell_options(s, &c));
  assert_int_equal(c.cells, 3);
  assert_true(c.dt == 0.5 && c.fn == 2.0 && c.heat_rate == 0.001 && c.placement == GRAN_PLACE_COLLISION);
  assert_true(c.e_agg == 0 && isinf(c.e_frag) && c.eps_f == 1);
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  gran_dsmc *a = NULL, *b = NULL;
  GRAN_ASSERT_OK(gran_scene_dsmc(s, mix, &a));
  gran_dsmc_options o;
  int64_t counts[2];
  int have = 0;
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &o, counts, &have));
  assert_int_equal(o.selector, GRAN_SELECTOR_CELL);
  double T0[2];
  GRAN_ASSERT_OK(gran_scene_initial_temperatures(s, mix, T0, NULL));
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, counts, T0, &o, &c, &b));
  GRAN_ASSERT_OK(gran_dsmc_advance(a, 5.0));
  GRAN_ASSERT_OK(gran_dsmc_advance(b, 5.0));
  const gran_particles *pa, *pb;
  GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
  GRAN_ASSERT_OK(gran_dsmc_particles(b, &pb));
  assert_memory_equal(pa->v, pb->v, 3 * sizeof(double) * (size_t)pa->n);
  assert_memory_equal(pa->x, pb->x, 3 * sizeof(double) * (size_t)pa->n);
  double L;
  GRAN_ASSERT_OK(gran_dsmc_cell_info(a, NULL, &L, NULL));
  GRAN_ASSERT_REL(L, cbrt(2.0 * 8000 / 0.02), 1e-14); /* F_N V */
  gran_dsmc_destroy(&a);
  gran_dsmc_destroy(&b);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);
}

/* aggregation through the run driver: clusters/n against clusters/n_theory, the ledger in clusters/ledger */
static void test_agg_scene(void **state) {
  (void)state;
  char out[600];
  snprintf(out, sizeof out, "%s", io_path("agg.h5"));
  char text2[4096];
  snprintf(text2, sizeof text2,
           "[mixture]\nnspecies = 30\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.01, theta = 400.0 }\n"
           "[restitution]\neps = 0.9\n[initial]\ntemperatures = \"equal\"\n"
           "[engine]\nselector = \"cell\"\nvolume = 5e6\nseed = 3\nt_end = 40.0\n"
           "[cell]\ncells = 3\ndt = 0.5\ne_agg = 1.0\ne_frag = 3.0\neps_f = 0.7\n"
           "[observables]\ntimes = [10.0, 20.0, 40.0]\nmsd = false\n[output]\npath = \"%s\"\n",
           out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text2, "agg.toml", &s));
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, &res));
  assert_int_equal(res.finished, 1);
  agg_check_run_output(out, 30);
  gran_scene_destroy(&s);
}


static void test_bad_keys(void **state) {
  (void)state;
  agg_expect_parse_error(text("cells = 0", "x.h5"), "cell.cells");
  agg_expect_parse_error(text("cells = 5000", "x.h5"), "cell.cells");
  agg_expect_parse_error(text("fn = -1.0", "x.h5"), "cell.fn");
  agg_expect_parse_error(text("e_agg = -1.0", "x.h5"), "cell.e_agg");
  agg_expect_parse_error(text("e_frag = -1.0", "x.h5"), "cell.e_frag");
  agg_expect_parse_error(text("eps_f = 2.0", "x.h5"), "cell.eps_f");
  agg_expect_parse_error(text("heat_rate = -1.0", "x.h5"), "cell.heat_rate");
  agg_expect_parse_error(text("placement = \"nowhere\"", "x.h5"), "cell.placement");
  agg_expect_parse_error(text("bath_density = -1.0", "x.h5"), "cell.bath_density");
  agg_expect_parse_error(text("bath_mass = 0.0", "x.h5"), "cell.bath_mass");
  agg_expect_parse_error(text("bath_T = -2.0", "x.h5"), "cell.bath_T");
  agg_expect_parse_error(text("bath_sigma = -1.0", "x.h5"), "cell.bath_sigma");
  agg_expect_parse_error(text("nonsense = 1", "x.h5"), "cell.nonsense");
  /* dt: a second dt line would be a TOML error; replace it */
  {
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", text("cells = 3", "x.h5"));
    char *p = strstr(buf, "dt = 0.5");
    memcpy(p, "dt =-1.0", 8);
    agg_expect_parse_error(buf, "cell.dt");
    p = strstr(buf, "dt =-1.0");
    memcpy(p, "#t = 0.5", 8);
    agg_expect_parse_error(buf, "dt");
  }
  /* [cell] without selector "cell", and selector "cell" without [cell] */
  {
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", text("cells = 3", "x.h5"));
    char *p = strstr(buf, "selector = \"cell\"");
    memcpy(p + 11, "\"bird\"", 6);
    agg_expect_parse_error(buf, "cell");
    snprintf(buf, sizeof buf, "%s", text("cells = 3", "x.h5"));
    p = strstr(buf, "[cell]");
    memcpy(p, "[cel2]", 6);
    agg_expect_parse_error(buf, "cel");
  }
  /* a dt too large for the gas: refused when the engine is made, naming dt */
  {
    gran_scene *s = NULL;
    char buf[4096];
    snprintf(buf, sizeof buf, "%s", text("cells = 3", "x.h5"));
    char *p = strstr(buf, "dt = 0.5");
    memcpy(p, "dt = 9e9", 8);
    GRAN_ASSERT_OK(gran_scene_parse(buf, "big.toml", &s));
    gran_mixture *mix = NULL;
    gran_dsmc *d = NULL;
    GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
    GRAN_ASSERT_ERR(gran_scene_dsmc(s, mix, &d), GRAN_ERR_DOMAIN);
    assert_non_null(strstr(gran_last_error_message(), "'dt'"));
    GRAN_ASSERT_ERR(gran_scene_run(s, io_path("big.h5"), "", NULL, NULL), GRAN_ERR_DOMAIN);
    gran_mixture_destroy(&mix);
    gran_scene_destroy(&s);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_run_and_resume),
      cmocka_unit_test(test_scene_engine),
      cmocka_unit_test(test_bad_keys),
      cmocka_unit_test(test_agg_scene),
  };
  io_tmp("t522"); /* every file in a private temporary folder (io_path) */
  int rc = cmocka_run_group_tests_name("t522-dsmc-cell-scene", tests, NULL, NULL);
  io_tmp_cleanup();
  return rc;
}
