/* t527-dsmc-agg-scene.c - the [aggregation] table of a scene, for every selector: an aggregating,
 * fragmenting scene with selector "lowrank" and "bird" runs through the run driver, writes
 * clusters/n within 4 sqrt(n) + 1.5 % of clusters/n_theory (as t522 for the cell selector) and a
 * closing ledger; a run split by a checkpoint writes the same datasets bit for bit; the same keys
 * drive the cell selector (e_agg, e_frag, eps_f, frag_law into gran_dsmc_cell_options);
 * gran_scene_dsmc equals gran_dsmc_create_agg with gran_scene_dsmc_agg_options; bad keys named. */
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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_keys),
      cmocka_unit_test(test_scene_engine),
      cmocka_unit_test(test_lowrank),
      cmocka_unit_test(test_bird),
  };
  return cmocka_run_group_tests_name("t527-dsmc-agg-scene", tests, NULL, NULL);
}
