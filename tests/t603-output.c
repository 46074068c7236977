/* t603-output.c - the HDF5 output of gran_scene_run: layout (groups, datasets, shapes, root
 * attributes), values equal to a direct engine run, the units of the run (unit_system and the
 * reference values) and the dimension scales of the rows, writability checked before any work,
 * and no half-written file ever under the final name. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

#include <hdf5_hl.h>

static void expect_dims(hid_t f, const char *name, int rank, hsize_t d0, hsize_t d1, hsize_t d2) {
  hsize_t d[4] = {0, 0, 0, 0};
  int r = io_h5_dims(f, name, d);
  if (r != rank) fail_msg("%s: rank %d, expected %d", name, r, rank);
  hsize_t want[3] = {d0, d1, d2};
  for (int i = 0; i < rank; i++)
    if (d[i] != want[i]) fail_msg("%s: dimension %d is %llu, expected %llu", name, i, (unsigned long long)d[i], (unsigned long long)want[i]);
}

static herr_t doc_cb(hid_t loc, const char *name, const H5O_info_t *info, void *op) {
  if (info->type != H5O_TYPE_DATASET) return 0;
  hid_t d = H5Oopen(loc, name, H5P_DEFAULT);
  char *u = io_h5_attr_string(d, "units"), *w = io_h5_attr_string(d, "description");
  if (!u || !w || !w[0]) fail_msg("dataset '%s' lacks units or description", name);
  free(u);
  free(w);
  H5Oclose(d);
  ++*(int *)op;
  return 0;
}

static void test_layout_and_values(void **state) {
  (void)state;
  const char *out = io_path("layout.h5");
  const char *text = io_tiny_text("lowrank", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "tiny.toml", &s));
  gran_run_result res;
  memset(&res, 0xff, sizeof res);
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_true(res.collisions > 1000);
  assert_true(res.time == 20.0);
  assert_true(res.checkpoints >= 1); /* checkpoint_every = 2 */
  assert_true(io_exists(out));
  char tmp[600];
  snprintf(tmp, sizeof tmp, "%s.tmp", out);
  assert_false(io_exists(tmp));
  snprintf(tmp, sizeof tmp, "%s.ckpt", out);
  assert_false(io_exists(tmp)); /* removed after success (keep_checkpoint = false) */
  snprintf(tmp, sizeof tmp, "%s.ckpt.tmp", out);
  assert_false(io_exists(tmp));

  const hsize_t NT = IO_TINY_NT, M = IO_TINY_M;
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  expect_dims(f, "time", 1, NT, 0, 0);
  expect_dims(f, "species/mass", 1, M, 0, 0);
  expect_dims(f, "species/counts", 1, M, 0, 0);
  expect_dims(f, "species/T0", 1, M, 0, 0);
  expect_dims(f, "stats/collisions", 1, NT, 0, 0);
  expect_dims(f, "stats/trials", 1, NT, 0, 0);
  expect_dims(f, "temperatures/time", 1, NT, 0, 0);
  expect_dims(f, "temperatures/T", 2, NT, M, 0);
  expect_dims(f, "temperatures/T_theory", 2, NT, M, 0);
  expect_dims(f, "msd/msd", 2, NT, M, 0);
  expect_dims(f, "msd/msd_total", 1, NT, 0, 0);
  expect_dims(f, "msd/msd_theory", 2, NT, M, 0);
  expect_dims(f, "msd/msd_total_theory", 1, NT, 0, 0);
  expect_dims(f, "energy/e_kin", 1, NT, 0, 0);
  expect_dims(f, "energy/e_initial", 1, NT, 0, 0);
  expect_dims(f, "energy/e_dissipated", 1, NT, 0, 0);
  expect_dims(f, "momentum/p", 2, NT, 3, 0);
  expect_dims(f, "collision_counts/counts", 3, NT, M, M);
  expect_dims(f, "sonine_a2/a2", 2, NT, M, 0);
  expect_dims(f, "velocity_distribution/pdf", 3, NT, M, 8);
  expect_dims(f, "velocity_distribution/edges", 1, 9, 0, 0);
  expect_dims(f, "velocity_distribution/pdf_maxwell", 1, 8, 0, 0);
  expect_dims(f, "tamsd/lag", 1, 3, 0, 0);
  expect_dims(f, "tamsd/tamsd", 2, 3, M, 0);
  expect_dims(f, "tamsd/tamsd_theory", 2, 3, M, 0);
  expect_dims(f, "tamsd/tamsd_se", 2, 3, M, 0);
  expect_dims(f, "tamsd/tracers", 1, M, 0, 0);

  /* every dataset says what it holds and in which units, as UTF-8 strings (h5py: str) */
  int ndoc = 0;
  assert_true(H5Ovisit(f, H5_INDEX_NAME, H5_ITER_NATIVE, doc_cb, &ndoc) >= 0);
  assert_true(ndoc >= 25);

  /* root attributes: the whole scene text, the version, the seed */
  char *a = io_h5_attr_string(f, "scene");
  assert_non_null(a);
  assert_string_equal(a, text);
  free(a);
  a = io_h5_attr_string(f, "granary_version");
  assert_string_equal(a, GRAN_VERSION_STRING);
  free(a);
  a = io_h5_attr_string(f, "format");
  assert_string_equal(a, "granary-output 1");
  free(a);
  uint64_t seed = 0;
  hid_t at = H5Aopen(f, "seed", H5P_DEFAULT);
  assert_true(at >= 0);
  H5Aread(at, H5T_NATIVE_UINT64, &seed);
  H5Aclose(at);
  assert_true(seed == 11);

  /* values: the recorded temperatures and MSDs are those of the engine itself */
  size_t n;
  double *T = io_h5_read_double(f, "temperatures/T", &n);
  double *msd = io_h5_read_double(f, "msd/msd", NULL);
  double *ek = io_h5_read_double(f, "energy/e_kin", NULL);
  double *e0 = io_h5_read_double(f, "energy/e_initial", NULL);
  double *ed = io_h5_read_double(f, "energy/e_dissipated", NULL);
  double *lag = io_h5_read_double(f, "tamsd/lag", NULL);
  double *pdf = io_h5_read_double(f, "velocity_distribution/pdf", NULL);
  double *time = io_h5_read_double(f, "time", NULL);
  assert_true(T && msd && ek && e0 && ed && lag && pdf && time);
  gran_mixture *mix = NULL;
  gran_dsmc *sim = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  GRAN_ASSERT_OK(gran_scene_dsmc(s, mix, &sim));
  for (size_t i = 0; i < NT; i++) {
    double Ts[2], ms[2], mt;
    GRAN_ASSERT_OK(gran_dsmc_advance(sim, time[i]));
    GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, Ts));
    GRAN_ASSERT_OK(gran_dsmc_msd(sim, ms, &mt));
    for (size_t k = 0; k < M; k++) {
      assert_true(T[i * M + k] == Ts[k]); /* bit for bit */
      assert_true(msd[i * M + k] == ms[k]);
    }
    GRAN_ASSERT_REL(ek[i] + ed[i], e0[i], 1e-10); /* energy balance */
    if (i) assert_true(T[i * M] < T[(i - 1) * M]); /* the gas cools */
    /* the speed histogram integrates to the fraction below cmax = 3 thermal speeds */
    double sum = 0;
    for (int b = 0; b < 8; b++) sum += pdf[(i * M) * 8 + b] * (3.0 / 8);
    assert_true(sum > 0.97 && sum <= 1.0 + 1e-12);
  }
  assert_true(lag[0] == 0.5 && lag[1] == 1.0 && lag[2] == 5.0);
  /* the TAMSD and its standard error: mean and spread of the per-tracer TAMSDs of the engine's
   * own trajectories (the direct O(N nlag) sum, another method than the file's FFT) */
  {
    double *ta = io_h5_read_double(f, "tamsd/tamsd", NULL), *tse = io_h5_read_double(f, "tamsd/tamsd_se", NULL);
    double *dt = NULL; /* one tracer's TAMSD at lags 0..L */
    int64_t ntraj = 0, ns = 0;
    const double *xyz = NULL;
    const int32_t *sp = NULL;
    GRAN_ASSERT_OK(gran_dsmc_trajectories(sim, &ntraj, &ns, &xyz, &sp));
    assert_true(ta && tse && ntraj >= 2 * (int64_t)M);
    dt = malloc(sizeof(double) * (size_t)ns);
    for (size_t l = 0; l < 3; l++) {
      const int64_t L = llround(lag[l] / 0.5); /* the tiny scene samples every 0.5 */
      for (size_t k = 0; k < M; k++) {
        double sum = 0, sum2 = 0;
        int n = 0;
        for (int64_t j = 0; j < ntraj; j++) {
          if (sp[j] != (int32_t)k) continue;
          GRAN_ASSERT_OK(gran_tamsd_direct(1, ns, xyz + j * ns * 3, L + 1, dt));
          sum += dt[L];
          sum2 += dt[L] * dt[L];
          n++;
        }
        assert_true(n >= 2);
        const double mean = sum / n, se = sqrt((sum2 / n - mean * mean) * n / (n - 1) / n);
        GRAN_ASSERT_REL(ta[l * M + k], mean, 1e-9);
        GRAN_ASSERT_REL(tse[l * M + k], se, 1e-6);
        assert_true(tse[l * M + k] > 0);
      }
    }
    free(ta), free(tse), free(dt);
  }
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
  free(T), free(msd), free(ek), free(e0), free(ed), free(lag), free(pdf), free(time);
  H5Fclose(f);
  gran_scene_destroy(&s);
}

static double attr_double(hid_t loc, const char *name) {
  double v = NAN;
  hid_t a = H5Aopen(loc, name, H5P_DEFAULT);
  if (a < 0) fail_msg("attribute '%s' is missing", name);
  assert_true(H5Aread(a, H5T_NATIVE_DOUBLE, &v) >= 0);
  H5Aclose(a);
  return v;
}

/* the reference units of the root: mass, length, energy, time (energy and time to 1e-12: sums) */
static void check_reference(hid_t f, double m, double l, double e, double t) {
  GRAN_ASSERT_REL(attr_double(f, "reference_mass"), m, 1e-15);
  GRAN_ASSERT_REL(attr_double(f, "reference_length"), l, 1e-15);
  GRAN_ASSERT_REL(attr_double(f, "reference_energy"), e, 1e-12);
  GRAN_ASSERT_REL(attr_double(f, "reference_time"), t, 1e-12);
}

/* 1 when dataset `scale` of group `g` is a dimension scale attached to axis `axis` of `ds` */
static int attached(hid_t f, const char *g, const char *ds, const char *scale, unsigned axis) {
  char a[256], b[256];
  snprintf(a, sizeof a, "%s/%s", g, ds);
  snprintf(b, sizeof b, "%s/%s", g, scale);
  hid_t d = H5Dopen2(f, a, H5P_DEFAULT), s = H5Dopen2(f, b, H5P_DEFAULT);
  if (d < 0 || s < 0) fail_msg("dataset '%s' or '%s' is missing", a, b);
  if (H5DSis_scale(s) <= 0) fail_msg("'%s' is not a dimension scale", b);
  const htri_t r = H5DSis_attached(d, s, axis);
  H5Dclose(d);
  H5Dclose(s);
  return r > 0;
}

/* The time axis and the species axes of every row dataset carry their group's scales `time` and
 * `species` (`species_2`), and only on their own axes. */
static void check_scales(hid_t f, int replicas) {
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  hid_t t = H5Dopen2(f, "time", H5P_DEFAULT);
  assert_true(H5DSis_scale(t) > 0);
  char name[64];
  assert_true(H5DSget_scale_name(t, name, sizeof name) > 0);
  assert_string_equal(name, "time");
  H5Dclose(t);
  const char *x[] = {"T", "T_se"};
  for (int i = 0; i < (replicas ? 2 : 1); i++) {
    assert_true(attached(f, "temperatures", x[i], "time", 0));
    assert_true(attached(f, "temperatures", x[i], "species", 1));
    assert_false(attached(f, "temperatures", x[i], "time", 1));
    assert_false(attached(f, "temperatures", x[i], "species", 0));
  }
  assert_true(attached(f, "msd", "msd", "time", 0));
  assert_true(attached(f, "msd", "msd", "species", 1));
  assert_true(attached(f, "msd", "msd_total", "time", 0));
  assert_true(attached(f, "stats", "collisions", "time", 0));
  assert_true(attached(f, "collision_counts", "counts", "time", 0));
  assert_true(attached(f, "collision_counts", "counts", "species", 1));
  assert_true(attached(f, "collision_counts", "counts", "species_2", 2));
  assert_true(attached(f, "velocity_distribution", "pdf", "species", 1));
  assert_false(attached(f, "velocity_distribution", "pdf", "species", 2)); /* the bins */
  assert_false(attached(f, "momentum", "p", "time", 1));                  /* x, y, z */
  /* the theory beside the rows, and the TAMSD's lag and species axes */
  assert_true(attached(f, "temperatures", "T_theory", "time", 0));
  assert_true(attached(f, "temperatures", "T_theory", "species", 1));
  assert_true(attached(f, "msd", "msd_theory", "time", 0));
  assert_true(attached(f, "msd", "msd_theory", "species", 1));
  assert_true(attached(f, "msd", "msd_total_theory", "time", 0));
  assert_true(attached(f, "tamsd", "tamsd", "lag", 0));
  assert_true(attached(f, "tamsd", "tamsd", "species", 1));
  assert_true(attached(f, "tamsd", "tamsd_theory", "lag", 0));
  assert_true(attached(f, "tamsd", "tamsd_theory", "species", 1));
  assert_true(attached(f, "tamsd", "tracers", "species", 0));
  if (replicas) {                                                          /* [replica][time][k] */
    assert_true(attached(f, "temperatures", "T_replicas", "time", 1));
    assert_true(attached(f, "temperatures", "T_replicas", "species", 2));
    assert_false(attached(f, "temperatures", "T_replicas", "time", 0));
  }
  size_t n = 0;
  double *k = io_h5_read_double(f, "temperatures/species", &n);
  assert_int_equal(n, IO_TINY_M);
  assert_true(k[0] == 1 && k[1] == 2);
  free(k);
}

/* unit_system names the units, the reference values are the scene's (docs/units.md) */
static void test_units_and_scales(void **state) {
  (void)state;
  /* the tiny scene: m_1 = 1, sigma_1 = 1, <T(0)> = 1 (hcs, T_mean = 1) */
  const char *out = io_path("units1.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  gran_scene_destroy(&s);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  char *u = io_h5_attr_string(f, "unit_system");
  assert_non_null(u);
  assert_non_null(strstr(u, "DSMC units: mass m_1"));
  assert_non_null(strstr(u, "energy k_B T0"));
  assert_non_null(strstr(u, "time unit: sigma_1 sqrt(m_1/(k_B T0))"));
  free(u);
  check_reference(f, 1.0, 1.0, 1.0, 1.0);
  check_scales(f, 0);
  H5Fclose(f);

  /* m_1 = 2, sigma_1 = 0.5, <T(0)> = 8: time unit sigma_1 sqrt(m_1/T0) = 0.25 of the scene's; two
   * replicas with their rows (X_se, X_replicas) */
  char text[4096];
  out = io_path("units2.h5");
  snprintf(text, sizeof text, "%s", io_tiny_text("lowrank", out));
  char *m = strstr(text, "mass = [1.0, 4.0]\n");
  assert_non_null(m);
  memcpy(m, "mass = [2.0, 4.0]\n", 18);
  char rest[4096];
  char *in = strstr(text, "[initial]\n") + strlen("[initial]\n");
  snprintf(rest, sizeof rest, "%s", in);
  snprintf(in, sizeof text - (size_t)(in - text), "T_mean = 8.0\n%s", rest);
  char *en = strstr(text, "[engine]\n") + strlen("[engine]\n");
  snprintf(rest, sizeof rest, "%s", en);
  snprintf(en, sizeof text - (size_t)(en - text), "replicas = 2\nkeep_replicas = true\n%s", rest);
  char *mx = strstr(text, "[mixture]\n") + strlen("[mixture]\n");
  snprintf(rest, sizeof rest, "%s", mx);
  snprintf(mx, sizeof text - (size_t)(mx - text), "sigma = [0.5, 1.0]\n%s", rest);
  GRAN_ASSERT_OK(gran_scene_parse(text, "tiny2.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  gran_scene_destroy(&s);
  f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  u = io_h5_attr_string(f, "unit_system");
  assert_non_null(u);
  assert_non_null(strstr(u, "m_1 = 2;"));
  assert_non_null(strstr(u, "sigma_1 = 0.5;"));
  assert_non_null(strstr(u, "k_B T0 = 8,"));
  assert_non_null(strstr(u, "sigma_1 sqrt(m_1/(k_B T0)) = 0.25"));
  free(u);
  check_reference(f, 2.0, 0.5, 8.0, 0.25);
  check_scales(f, 1);
  H5Fclose(f);

  /* GSRD: mass 1, length a, energy T0; T0 = 4: a sqrt(m/(k_B T0)) = 0.5 (a cooling gas: Haff's law beside T) */
  out = io_path("units3.h5");
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 6\nn0 = 5\ndt = 0.1\nT0 = 4\nsteps = 20\neps = 0.9\n"
           "sigma = 0.1\n"
           "[observables]\nevery = 5\n[output]\npath = \"%s\"\n",
           out);
  GRAN_ASSERT_OK(gran_scene_parse(text, "srd.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  gran_scene_destroy(&s);
  f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  u = io_h5_attr_string(f, "unit_system");
  assert_non_null(u);
  assert_non_null(strstr(u, "GSRD units:"));
  assert_non_null(strstr(u, "a sqrt(m/(k_B T0)) = 0.5"));
  free(u);
  check_reference(f, 1.0, 1.0, 4.0, 0.5);
  assert_true(attached(f, "temperature", "T", "time", 0));
  assert_true(attached(f, "temperature", "T_theory", "time", 0)); /* Haff's law of the cooling gas */
  H5Fclose(f);
}

static void test_unwritable(void **state) {
  (void)state;
  const char *blocker = io_path("a-file");
  io_write_file(blocker, "not a folder\n");
  char bad[700];
  snprintf(bad, sizeof bad, "%s/out.h5", blocker);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", bad), "tiny.toml", &s));
  gran_run_result res;
  memset(&res, 0xff, sizeof res);
  /* the scene's [output] path */
  GRAN_ASSERT_ERR(gran_scene_run(s, NULL, NULL, NULL, &res), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), blocker));
  assert_int_equal(res.collisions, 0); /* stopped before any work */
  assert_int_equal(res.finished, 0);
  /* an explicit output path */
  GRAN_ASSERT_ERR(gran_scene_run(s, bad, "", NULL, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "out.h5"));
  /* an unwritable checkpoint with a good output */
  const char *good = io_path("good.h5");
  GRAN_ASSERT_ERR(gran_scene_run(s, good, bad, NULL, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "checkpoint"));
  assert_false(io_exists(good));
  /* output == checkpoint */
  GRAN_ASSERT_ERR(gran_scene_run(s, good, good, NULL, NULL), GRAN_ERR_ARG);
  /* a folder as output */
  GRAN_ASSERT_ERR(gran_scene_run(s, io_tmpdir, "", NULL, NULL), GRAN_ERR_IO);
  gran_run_control ctl = {-1, NULL, NULL};
  GRAN_ASSERT_ERR(gran_scene_run(s, good, "", &ctl, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "stop_after_checkpoints"));
  gran_scene_destroy(&s);
}

/* progress callback that sabotages the final write: a folder where PATH.tmp must go */
static int sabotage(const gran_run_progress *p, void *params) {
  if (p->output_index == p->noutputs) {
    char tmp[700];
    snprintf(tmp, sizeof tmp, "%s.tmp", (const char *)params);
    mkdir(tmp, 0700);
  }
  return 0;
}

static int stop_at_3(const gran_run_progress *p, void *params) {
  (void)params;
  assert_true(p->fraction > 0 && p->fraction <= 1);
  assert_true(p->noutputs == IO_TINY_NT);
  return p->output_index == 3;
}

static void test_no_half_written_files(void **state) {
  (void)state;
  const char *out = io_path("precious.h5");
  io_write_file(out, "OLD CONTENT\n");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  /* a failure while writing the output: the previous file stays as it was */
  gran_run_control ctl = {0, sabotage, (void *)out};
  GRAN_ASSERT_ERR(gran_scene_run(s, NULL, "", &ctl, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "precious.h5.tmp"));
  char *c = io_read_file(out);
  assert_string_equal(c, "OLD CONTENT\n");
  free(c);
  char tmp[700];
  snprintf(tmp, sizeof tmp, "%s.tmp", out);
  rmdir(tmp);
  /* a run stopped by its callback: checkpoint written, the previous output untouched, and the
   * three output times reached in OUTPUT.partial.h5 (complete = 0) */
  const char *ck = io_path("precious.ckpt");
  gran_run_control stop = {0, stop_at_3, NULL};
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, ck, &stop, &res));
  assert_int_equal(res.finished, 0);
  assert_int_equal(res.checkpoints, 2); /* after output 2 (checkpoint_every) and at the stop */
  assert_true(io_exists(ck));
  c = io_read_file(out);
  assert_string_equal(c, "OLD CONTENT\n");
  free(c);
  {
    hid_t p = H5Fopen(io_path("precious.partial.h5"), H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(p >= 0);
    int64_t complete = -1;
    hid_t at = H5Aopen(p, "complete", H5P_DEFAULT);
    H5Aread(at, H5T_NATIVE_INT64, &complete);
    H5Aclose(at);
    assert_int_equal(complete, 0);
    size_t n = 0, nT = 0;
    double *t = io_h5_read_double(p, "time", &n);
    double *T = io_h5_read_double(p, "temperatures/T", &nT);
    assert_int_equal(n, 3);
    for (size_t i = 0; i < nT; i++) assert_true(isfinite(T[i]) && T[i] > 0);
    free(t);
    free(T);
    H5Fclose(p);
  }
  /* and the resumed run replaces the old file by a complete one */
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  H5Fclose(f);
  assert_false(io_exists(ck));
  gran_scene_destroy(&s);
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t603");
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_layout_and_values),
      cmocka_unit_test(test_units_and_scales),
      cmocka_unit_test(test_unwritable),
      cmocka_unit_test(test_no_half_written_files),
  };
  return cmocka_run_group_tests_name("t603-output", tests, NULL, teardown);
}
