/* t645-theory-sonine-run.c - `[observables] theory_sonine = true`: the run driver writes the first
 * Sonine theory (temperatures/T_theory_sonine, temperatures/a2_theory_sonine) beside T_theory, and
 * msd/msd_theory_sonine (the two-moment velocity correlation) beside msd_theory;
 * the values are gran_theory_temperatures_approx's from the scene's start (T0, a2 = 0) at the
 * output times (`sonine_order = 3`: gran_theory_temperatures_sonine2's, plus a3_theory_sonine, and
 * msd_theory_sonine from gran_theory_msd_sonine2 on that trajectory); off by default;
 * refused (GRAN_ERR_PARSE naming the key) where it has no meaning. */
#include "io_test_util.h"

#include <math.h>
#include <string.h>

#define NT 8
#define M 2

static const char *kFmt = "title = \"sonine\"\n"
                          "[mixture]\n"
                          "nspecies = 2\n"
                          "mass = [1.0, 4.0]\n"
                          "density = [0.1, 0.02]\n"
                          "[restitution]\n"
                          "eps = 0.7\n"
                          "[initial]\n"
                          "temperatures = \"hcs\"\n"
                          "[engine]\n"
                          "selector = \"lowrank\"\n"
                          "counts = [2000, 400]\n"
                          "seed = 5\n"
                          "t_end = 20.0\n"
                          "[observables]\n"
                          "times = { log = { start = 0.1, stop = 20.0, n = 8 } }\n"
                          "%s"
                          "[output]\n"
                          "path = \"%s\"\n";

static void run_scene(const char *extra, const char *out, gran_mixture **mix) {
  char text[2048];
  snprintf(text, sizeof text, kFmt, extra, out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "sonine.toml", &s));
  if (mix) GRAN_ASSERT_OK(gran_scene_mixture(s, mix));
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  gran_scene_destroy(&s);
}

static void test_datasets(void **state) {
  (void)state;
  const char *out = io_path("sonine.h5");
  gran_mixture *mix = NULL;
  run_scene("theory_sonine = true\n", out, &mix);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t n = 0, nt = 0, nT0 = 0, na = 0, nm = 0;
  double *t = io_h5_read_double(f, "temperatures/time", &nt);
  double *T0 = io_h5_read_double(f, "species/T0", &nT0);
  double *Tm = io_h5_read_double(f, "temperatures/T_theory", &nm);
  double *Ts = io_h5_read_double(f, "temperatures/T_theory_sonine", &n);
  double *as = io_h5_read_double(f, "temperatures/a2_theory_sonine", &na);
  assert_non_null(t);
  assert_non_null(T0);
  assert_non_null(Tm);
  assert_non_null(Ts);
  assert_non_null(as);
  assert_int_equal(nt, NT);
  assert_int_equal(nT0, M);
  assert_int_equal(n, NT * M);
  assert_int_equal(na, NT * M);
  size_t nms = 0, nmm = 0;
  double *ms = io_h5_read_double(f, "msd/msd_theory_sonine", &nms);
  double *mm = io_h5_read_double(f, "msd/msd_theory", &nmm);
  assert_non_null(ms);
  assert_non_null(mm);
  assert_int_equal(nms, NT * M);
  /* the two-moment correlation: finite, positive, the same ballistic start (t = 0.1: within 1 %)
   * and below Eq. 4 at the last time (eps = 0.7: D2/D1 ~ 0.98) */
  for (int j = 0; j < NT * M; j++) assert_true(isfinite(ms[j]) && ms[j] > 0);
  for (int k = 0; k < M; k++) {
    assert_true(fabs(ms[k] / mm[k] - 1) < 0.01);
    const double r = ms[(NT - 1) * M + k] / mm[(NT - 1) * M + k] - 1;
    if (!(r < -0.002 && r > -0.05)) fail_msg("species %d: msd_theory_sonine/msd_theory - 1 = %g at t_end", k, r);
  }
  free(ms), free(mm);
  hsize_t d[4];
  assert_int_equal(io_h5_dims(f, "temperatures/T_theory_sonine", d), 2);
  assert_int_equal(d[0], NT);
  assert_int_equal(d[1], M);
  hid_t ds = H5Dopen2(f, "temperatures/T_theory_sonine", H5P_DEFAULT);
  char *u = io_h5_attr_string(ds, "units");
  H5Dclose(ds);
  H5Fclose(f);

  /* the same call the driver makes: Sonine trajectory from T0 with Maxwellian velocities (a2 = 0) */
  double Tr[NT * M], ar[NT * M];
  GRAN_ASSERT_OK(gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, T0, NULL, NT, t, 1e-8, Tr, ar));
  double a2h[M], Th[M];
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Th, a2h, NULL));
  for (int j = 0; j < NT * M; j++) {
    assert_true(isfinite(Ts[j]) && Ts[j] > 0);
    assert_true(isfinite(as[j]) && fabs(as[j]) < 1);
    GRAN_ASSERT_REL(Ts[j], Tr[j], 1e-14);
    GRAN_ASSERT_ABS(as[j], ar[j], 1e-15);
    /* first Sonine correction of a Maxwellian-HCS start: a fraction of a per cent of T */
    assert_true(fabs(Ts[j] / Tm[j] - 1) < 0.01);
  }
  /* a2_k grows from 0 towards the Sonine HCS values (same sign) and T departs from the Maxwellian */
  for (int k = 0; k < M; k++) {
    const double a_last = as[(NT - 1) * M + k];
    assert_true(a_last * a2h[k] > 0);
    assert_true(fabs(a_last) > fabs(as[k]));
    assert_true(fabs(Ts[(NT - 1) * M + k] / Tm[(NT - 1) * M + k] - 1) > 1e-5);
  }
  assert_non_null(u);
  assert_string_equal(u, "energy");
  free(u);
  free(t), free(T0), free(Tm), free(Ts), free(as);
  gran_mixture_destroy(&mix);

  /* off by default: no Sonine datasets */
  const char *out2 = io_path("plain.h5");
  run_scene("", out2, NULL);
  f = H5Fopen(out2, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  assert_int_equal(H5Lexists(f, "temperatures/T_theory", H5P_DEFAULT), 1);
  assert_int_equal(H5Lexists(f, "temperatures/T_theory_sonine", H5P_DEFAULT), 0);
  assert_int_equal(H5Lexists(f, "temperatures/a2_theory_sonine", H5P_DEFAULT), 0);
  assert_int_equal(H5Lexists(f, "msd/msd_theory", H5P_DEFAULT), 1);
  assert_int_equal(H5Lexists(f, "msd/msd_theory_sonine", H5P_DEFAULT), 0);
  H5Fclose(f);
}

/* sonine_order = 3: the second Sonine trajectory (gran_theory_temperatures_sonine2 from T0, a2 = a3 = 0) in
 * T_theory_sonine, a2_theory_sonine, plus a3_theory_sonine and the attribute naming the level; sonine_order = 2 is
 * the default bit for bit (no a3, no attribute). */
static void test_order(void **state) {
  (void)state;
  const char *o2 = io_path("order2.h5"), *o3 = io_path("order3.h5"), *od = io_path("orderd.h5");
  gran_mixture *mix = NULL;
  run_scene("msd = true\ntheory_sonine = true\nsonine_order = 3\n", o3, &mix);
  run_scene("msd = true\ntheory_sonine = true\nsonine_order = 2\n", o2, NULL);
  run_scene("msd = true\ntheory_sonine = true\n", od, NULL);
  size_t nt = 0, n0 = 0, n3 = 0, na2 = 0, na3 = 0, n2 = 0, nd = 0, nb2 = 0, nbd = 0;
  hid_t f = H5Fopen(o3, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  double *t = io_h5_read_double(f, "temperatures/time", &nt);
  double *T0 = io_h5_read_double(f, "species/T0", &n0);
  double *T3 = io_h5_read_double(f, "temperatures/T_theory_sonine", &n3);
  double *a2 = io_h5_read_double(f, "temperatures/a2_theory_sonine", &na2);
  double *a3 = io_h5_read_double(f, "temperatures/a3_theory_sonine", &na3);
  size_t nm3 = 0, nm2 = 0, nmd = 0;
  double *ms3 = io_h5_read_double(f, "msd/msd_theory_sonine", &nm3);
  assert_non_null(t), assert_non_null(T0), assert_non_null(T3), assert_non_null(a2), assert_non_null(a3);
  assert_non_null(ms3);
  assert_int_equal(nm3, NT * M);
  hid_t dm = H5Dopen2(f, "msd/msd_theory_sonine", H5P_DEFAULT);
  char *desc = io_h5_attr_string(dm, "description");
  H5Dclose(dm);
  assert_non_null(desc);
  assert_non_null(strstr(desc, "gran_theory_msd_sonine2"));
  free(desc);
  assert_int_equal(nt, NT);
  assert_int_equal(n3, NT * M);
  assert_int_equal(na3, NT * M);
  hid_t g = H5Gopen2(f, "temperatures", H5P_DEFAULT);
  char *lev = io_h5_attr_string(g, "theory_sonine_level");
  assert_non_null(lev);
  assert_non_null(strstr(lev, "second Sonine"));
  free(lev);
  H5Gclose(g);
  H5Fclose(f);
  double Tr[NT * M], ar2[NT * M], ar3[NT * M];
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, NT, t, 1e-8, Tr, ar2, ar3));
  for (int j = 0; j < NT * M; j++) {
    GRAN_ASSERT_REL(T3[j], Tr[j], 1e-14);
    GRAN_ASSERT_ABS(a2[j], ar2[j], 1e-15);
    GRAN_ASSERT_ABS(a3[j], ar3[j], 1e-15);
  }
  /* msd_theory_sonine: Eq. 4 on the same trajectory, a2 in the correlation */
  double mr[NT * M];
  GRAN_ASSERT_OK(gran_theory_msd_sonine2(mix, T0, NULL, NULL, 1, NT, t, 1e-8, mr, NULL));
  for (int j = 0; j < NT * M; j++) GRAN_ASSERT_REL(ms3[j], mr[j], 1e-14);
  /* a3 grows from 0 towards the second Sonine HCS values (same sign) */
  double Th[M], a2h[M], a3h[M];
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_T1, 1.0, Th, a2h, a3h, NULL));
  for (int k = 0; k < M; k++) {
    assert_true(a3[(NT - 1) * M + k] * a3h[k] > 0);
    assert_true(fabs(a3[(NT - 1) * M + k]) > fabs(a3[k]));
  }
  f = H5Fopen(o2, H5F_ACC_RDONLY, H5P_DEFAULT);
  double *T2 = io_h5_read_double(f, "temperatures/T_theory_sonine", &n2);
  double *b2 = io_h5_read_double(f, "temperatures/a2_theory_sonine", &nb2);
  assert_int_equal(H5Lexists(f, "temperatures/a3_theory_sonine", H5P_DEFAULT), 0);
  double *ms2 = io_h5_read_double(f, "msd/msd_theory_sonine", &nm2);
  g = H5Gopen2(f, "temperatures", H5P_DEFAULT);
  assert_int_equal(H5Aexists(g, "theory_sonine_level"), 0);
  H5Gclose(g);
  H5Fclose(f);
  f = H5Fopen(od, H5F_ACC_RDONLY, H5P_DEFAULT);
  double *Td = io_h5_read_double(f, "temperatures/T_theory_sonine", &nd);
  double *bd = io_h5_read_double(f, "temperatures/a2_theory_sonine", &nbd);
  double *msd_d = io_h5_read_double(f, "msd/msd_theory_sonine", &nmd);
  H5Fclose(f);
  assert_int_equal(n2, NT * M), assert_int_equal(nd, NT * M);
  assert_memory_equal(T2, Td, NT * M * sizeof(double));
  assert_memory_equal(b2, bd, NT * M * sizeof(double));
  assert_int_equal(nm2, NT * M), assert_int_equal(nmd, NT * M);
  assert_memory_equal(ms2, msd_d, NT * M * sizeof(double));
  /* the levels' MSDs differ */
  assert_true(fabs(ms3[NT * M - 2] / ms2[NT * M - 2] - 1) > 1e-4);
  /* the two levels differ: T_2/T_1 at t_end 1.41186 against 1.41328 at the first level */
  const double r3 = T3[(NT - 1) * M + 1] / T3[(NT - 1) * M], r2 = T2[(NT - 1) * M + 1] / T2[(NT - 1) * M];
  print_message("t_end: T2/T1 first level %.6f, second %.6f\n", r2, r3);
  assert_true(fabs(r3 / r2 - 1) > 1e-4);
  free(t), free(T0), free(T3), free(a2), free(a3), free(T2), free(b2), free(Td), free(bd), free(ms3), free(ms2), free(msd_d);
  gran_mixture_destroy(&mix);
}

static void expect_refused_key(const char *text, const char *key, const char *why) {
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_parse(text, "bad.toml", &s), GRAN_ERR_PARSE);
  assert_null(s);
  const char *msg = gran_last_error_message();
  if (!strstr(msg, key) || !strstr(msg, why)) fail_msg("message '%s' lacks '%s' or '%s'", msg, key, why);
}

static void test_order_refused(void **state) {
  (void)state;
  const char *head = "[mixture]\nnspecies = 1\ndensity = [0.1]\n[engine]\ncounts = [100]\nt_end = 1.0\n[observables]\n";
  char text[1024];
  snprintf(text, sizeof text, "%ssonine_order = 3\n", head);
  expect_refused_key(text, "key 'observables.sonine_order'", "needs theory_sonine = true");
  snprintf(text, sizeof text, "%stheory_sonine = false\nsonine_order = 2\n", head);
  expect_refused_key(text, "key 'observables.sonine_order'", "needs theory_sonine = true");
  snprintf(text, sizeof text, "%stheory_sonine = true\nsonine_order = 4\n", head);
  expect_refused_key(text, "key 'observables.sonine_order'", "got 4");
  snprintf(text, sizeof text, "%stheory_sonine = true\nsonine_order = \"3\"\n", head);
  expect_refused_key(text, "key 'observables.sonine_order'", "integer");
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 1\ndensity = [0.1]\n[restitution]\nmodel = \"viscoelastic\"\nbeta = 0.1\n[initial]\n"
           "temperatures = \"equal\"\n[engine]\ncounts = [100]\nt_end = 1.0\n[observables]\ntheory_sonine = true\n"
           "sonine_order = 3\n");
  expect_refused_key(text, "key 'observables.sonine_order'", "viscoelastic");
  snprintf(text, sizeof text, "[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\n[observables]\nsonine_order = 3\n");
  expect_refused_key(text, "key 'observables.sonine_order'", "GSRD");
}

static void expect_refused(const char *text, const char *why) {
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_parse(text, "bad.toml", &s), GRAN_ERR_PARSE);
  assert_null(s);
  const char *msg = gran_last_error_message();
  if (!strstr(msg, "key 'observables.theory_sonine'") || !strstr(msg, why))
    fail_msg("message '%s' lacks the key or '%s'", msg, why);
}

static void test_refused(void **state) {
  (void)state;
  const char *tail = "[observables]\ntheory_sonine = true\n";
  char text[1024];
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 1\ndensity = [0.1]\n[restitution]\nmodel = \"viscoelastic\"\nbeta = 0.1\n[initial]\n"
           "temperatures = \"equal\"\n[engine]\ncounts = [100]\nt_end = 1.0\n%s",
           tail);
  /* viscoelastic: the Sonine trajectory (no HCS); its two-moment MSD is not written, and says why */
  {
    char vt[1024];
    const char *out = io_path("visco.h5");
    snprintf(vt, sizeof vt,
             "[mixture]\nnspecies = 1\ndensity = [0.1]\n[restitution]\nmodel = \"viscoelastic\"\nbeta = 0.1\n"
             "[initial]\ntemperatures = \"equal\"\n[engine]\ncounts = [2000]\nseed = 5\nt_end = 20.0\n"
             "[observables]\ntimes = [1.0, 5.0, 20.0]\nmsd = true\ntheory_sonine = true\n[output]\npath = \"%s\"\n",
             out);
    gran_scene *s = NULL;
    GRAN_ASSERT_OK(gran_scene_parse(vt, "visco.toml", &s));
    GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
    gran_scene_destroy(&s);
    hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f >= 0);
    size_t n = 0;
    double *a2 = io_h5_read_double(f, "temperatures/a2_theory_sonine", &n);
    assert_int_equal(n, 3);
    for (int i = 0; i < 3; i++) assert_true(a2[i] < 0); /* viscoelastic gases have a2 < 0 */
    free(a2);
    assert_int_equal(H5Lexists(f, "msd/msd_theory_sonine", H5P_DEFAULT), 0);
    hid_t g = H5Gopen2(f, "msd", H5P_DEFAULT);
    assert_true(H5Aexists(g, "theory_sonine_error") > 0);
    H5Gclose(g);
    H5Fclose(f);
  }
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 30\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.01, theta = 400.0 }\n"
           "[restitution]\neps = 0.9\n[initial]\ntemperatures = \"equal\"\n[engine]\nvolume = 5e6\nt_end = 1.0\n"
           "[aggregation]\ne_agg = 1.0\n%s",
           tail);
  expect_refused(text, "aggregation");
  snprintf(text, sizeof text, "[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\n%s", tail);
  expect_refused(text, "GSRD");
  snprintf(text, sizeof text, "[mixture]\nnspecies = 1\ndensity = [0.1]\n[engine]\ncounts = [100]\nt_end = 1.0\n%stheory = false\n",
           tail);
  expect_refused(text, "theory = true");
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 1\ndensity = [0.1]\n[engine]\ncounts = [100]\nt_end = 1.0\n%stemperatures = false\n", tail);
  expect_refused(text, "temperatures = true");
  /* not a boolean */
  snprintf(text, sizeof text, "[mixture]\nnspecies = 1\ndensity = [0.1]\n[engine]\ncounts = [100]\nt_end = 1.0\n"
                              "[observables]\ntheory_sonine = 1\n");
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_parse(text, "bad.toml", &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "observables.theory_sonine"));
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t645");
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_datasets),
      cmocka_unit_test(test_refused),
      cmocka_unit_test(test_order),
      cmocka_unit_test(test_order_refused),
  };
  return cmocka_run_group_tests_name("t645-theory-sonine-run", tests, NULL, teardown);
}
