/* t610-srd-run.c - GSRD scenes through the run driver (`[engine] type = "srd"`, src/io/engine_srd.cpp):
 *  - bad scenes are refused with GRAN_ERR_PARSE naming the key and its line (alpha outside (0, 180],
 *    n0 <= 0, dt <= 0, a box that is not a whole number of cells, walls and shear on the same axis,
 *    unknown keys, eps < 1 without sigma, DSMC tables, snapshot times off the output grid, ...);
 *  - device = "cuda" without a GPU is GRAN_ERR_UNSUPPORTED, "auto" runs on the CPU with a warning;
 *  - the observables written by gran_scene_run equal those of the same engine driven through the
 *    C API (gran_srd_create/advance/observe, bit for bit), the energy ledger closes to 1e-12, the
 *    momentum stays zero, Haff's law beside it (T_theory); eps_eff clamps are counted per output
 *    interval with dt_max and a warning;
 *  - a run stopped after a checkpoint and resumed writes the same output file, dataset for dataset,
 *    bit for bit, as the uninterrupted run (Lees-Edwards stress, snapshots, S(k) included);
 *  - replicas: R = 3 gives X and X_se, replica 0 is the R = 1 run, the mean is the mean of the kept
 *    per-replica rows;
 *  - snapshots: the XDMF sidecar is well-formed XML, its topology a 3DCORECTMesh (2-D: one node
 *    along z) with cell-centred attributes, every HDF reference names an existing dataset of the
 *    stated shape by the output's base name; its grid times, each snapshot group's attributes
 *    time, step and output_index and /fields/{time, step, output_index} agree with /time and
 *    stats/steps (dt = 0.5: step and time differ); the fields sum to N, to the total momentum and
 *    to twice the kinetic energy;
 *  - a vibrated bed (walls, gravity, vibrating bottom wall) runs with its ledger closed;
 *  - every shipped scene of scenes/srd/ parses, and scenes/srd/vibrated-bed.toml runs in full;
 *  - `granary run` prints the GSRD header and the summary (T beside Haff's law, Mach; no species
 *    column and no theory columns where there is none).
 * Sizes are reduced under the sanitizers. */
#include "io_test_util.h"

#include <math.h>

/* the fill value of rows without a value (README: the _FillValue of a dataset) */
#define FILLV 9.969209968386869e36

#if defined(__SANITIZE_ADDRESS__)
#define SAN 1
#else
#define SAN 0
#endif

/* ---- bad scenes ------------------------------------------------------------------------------- */
typedef struct {
  const char *text;
  const char *where; /* "scene.toml:LINE: key 'K'" fragment expected in the message */
} bad_case;

static void test_bad_scenes(void **state) {
  (void)state;
  static const bad_case cases[] = {
      {"[engine]\ntype = \"srd\"\ncells = 4\nalpha = 0\n", "bad.toml:4: key 'engine.alpha'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nalpha = 180.5\n", "bad.toml:4: key 'engine.alpha'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nn0 = 0\n", "bad.toml:4: key 'engine.n0'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nparticles_per_cell = -3\n", "bad.toml:4: key 'engine.particles_per_cell'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\ndt = 0\n", "bad.toml:4: key 'engine.dt'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\ndt = -0.5\n", "bad.toml:4: key 'engine.dt'"},
      {"[engine]\ntype = \"srd\"\ndimension = 2\na = 0.5\nbox = [4.0, 3.3]\nsteps = 3\n", "bad.toml:5: key 'engine.box'"},
      {"[engine]\ntype = \"srd\"\ndimension = 3\ncells = 4\nsteps = 3\n[boundaries]\nlees_edwards = {shear_rate = 0.1}\n"
       "walls = {axis = \"y\"}\n",
       "bad.toml:8: key 'boundaries.walls.axis'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\ncolour = 1\n", "bad.toml:5: key 'engine.colour': unknown key"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\n[boundaries]\nlees = {shear_rate = 1}\n",
       "bad.toml:6: key 'boundaries.lees': unknown key"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\n[observables]\nmsd = true\n", "bad.toml:6: key 'observables.msd': unknown key"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\neps = 0.9\n", "bad.toml:5: key 'engine.eps'"},
      {"[mixture]\nnspecies = 1\n[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\n", "bad.toml:1: key 'mixture'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\ndevice = \"gpu\"\n", "bad.toml:5: key 'engine.device'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 3\nthermostat = \"hot\"\n", "bad.toml:5: key 'engine.thermostat'"},
      {"[engine]\ntype = \"srd\"\ncells = [4, 4]\nsteps = 3\n", "bad.toml:3: key 'engine.cells'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\ndt = 0.5\nt_end = 1.2\n", "bad.toml:5: key 'engine.t_end'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 10\n[observables]\nevery = 5\nsnapshots = {times = [3.0, 12.0]}\n",
       "bad.toml:7: key 'observables.snapshots.times'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 10\n[observables]\nstress = true\n", "bad.toml:6: key 'observables.stress'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 10\n[boundaries]\nwalls = {axis = \"z\"}\n[observables]\n"
       "structure_factor = true\n",
       "bad.toml:8: key 'observables.structure_factor'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 10\n[boundaries]\nvibrating_wall = {amplitude = 1, omega = 1}\n",
       "bad.toml:6: key 'boundaries.vibrating_wall'"},
      {"[engine]\ntype = \"srd\"\ndimension = 2\ncells = 4\nsteps = 10\n[forces]\ngravity = [0, -1, 0]\n",
       "bad.toml:7: key 'forces.gravity'"},
      {"[engine]\ntype = \"srd\"\ncells = 4\n", "key 'engine.steps' is missing"},
      {"[engine]\ntype = \"srd\"\ncells = 1048576\nn0 = 1e-9\nsteps = 1\n", "bad.toml:3: key 'engine.cells'"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    gran_scene *s = NULL;
    int st = gran_scene_parse(cases[i].text, "bad.toml", &s);
    if (st != GRAN_ERR_PARSE || !strstr(gran_last_error_message(), cases[i].where))
      fprintf(stderr, "case %zu: status %d, message '%s', expected '%s'\n", i, st, gran_last_error_message(), cases[i].where);
    assert_int_equal(st, GRAN_ERR_PARSE);
    assert_non_null(strstr(gran_last_error_message(), cases[i].where));
    assert_null(s);
  }
  /* a good one parses: box given in length units, a whole number of cells */
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse("[engine]\ntype = \"srd\"\ndimension = 2\na = 0.5\nbox = [4.0, 3.0]\nsteps = 3\n", "ok.toml", &s));
  int64_t nt = 0;
  double t0 = -1, t1 = -1;
  GRAN_ASSERT_OK(gran_scene_sizes(s, NULL, &nt, NULL, &t0, &t1));
  assert_true(nt == 4 && t0 == 0.0 && t1 == 3.0); /* every = max(1, steps / 50): steps 0..3 */
  gran_mixture *mix = NULL;
  GRAN_ASSERT_ERR(gran_scene_mixture(s, &mix), GRAN_ERR_ARG); /* DSMC-only functions refuse a GSRD scene */
  assert_non_null(strstr(gran_last_error_message(), "GSRD scene"));
  gran_dsmc_options dop;
  GRAN_ASSERT_ERR(gran_scene_dsmc_options(s, &dop, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
}

static double *rd(hid_t f, const char *name, size_t *n);

/* ---- device ----------------------------------------------------------------------------------- */
static void test_device(void **state) {
  (void)state;
  char text[512];
  const char *out = io_path("dev.h5");
  int compiled = 0, count = 0;
  GRAN_ASSERT_OK(gran_cuda_compiled(&compiled));
  if (compiled) GRAN_ASSERT_OK(gran_cuda_device_count(&count));
  snprintf(text, sizeof text, "[engine]\ntype = \"srd\"\ncells = 4\nsteps = 2\ndevice = \"cuda\"\n[output]\npath = \"%s\"\n", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "dev.toml", &s)); /* a scene names a device; the run resolves it */
  if (count == 0) {
    GRAN_ASSERT_ERR(gran_scene_run(s, NULL, "", NULL, NULL), GRAN_ERR_UNSUPPORTED);
    assert_non_null(strstr(gran_last_error_message(), "cuda"));
    assert_false(io_exists(out));
  } else {
    GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
    assert_true(io_exists(out));
    remove(out);
  }
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  snprintf(text, sizeof text, "[engine]\ntype = \"srd\"\ncells = 4\nsteps = 2\ndevice = \"auto\"\n[output]\npath = \"%s\"\n", out);
  GRAN_ASSERT_OK(gran_scene_parse(text, "dev.toml", &s));
  int64_t w0 = 0, w1 = 0;
  GRAN_ASSERT_OK(gran_warning_count(&w0));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_warning_count(&w1));
  if (count == 0) assert_true(w1 > w0); /* auto without a GPU: the CPU engine, with a warning */
  assert_true(io_exists(out));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  /* the host reference of the GPU algorithm (device = "reference") follows the CPU engine to
   * rounding (t890 compares them particle by particle): same temperatures to 1e-12 */
  const char *outr = io_path("dev-ref.h5"), *outc = io_path("dev-cpu.h5");
  const char *devs[2] = {"reference", "cpu"}, *outs[2] = {outr, outc};
  for (int d = 0; d < 2; ++d) {
    snprintf(text, sizeof text,
             "[engine]\ntype = \"srd\"\ndimension = 2\ncells = [8, 8]\neps = 0.9\nsigma = 0.1\nsteps = 30\n"
             "device = \"%s\"\n[output]\npath = \"%s\"\n", devs[d], outs[d]);
    GRAN_ASSERT_OK(gran_scene_parse(text, "dev.toml", &s));
    GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
    GRAN_ASSERT_OK(gran_scene_destroy(&s));
  }
  hid_t fr = H5Fopen(outr, H5F_ACC_RDONLY, H5P_DEFAULT), fc = H5Fopen(outc, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(fr >= 0 && fc >= 0);
  size_t nr = 0, nc = 0;
  double *Tr = rd(fr, "temperature/T", &nr), *Tc = rd(fc, "temperature/T", &nc);
  assert_non_null(Tr);
  assert_non_null(Tc);
  assert_int_equal(nr, nc);
  assert_true(nr >= 2);
  assert_true(Tc[nc - 1] < 0.99 * Tc[0]); /* it cooled */
  for (size_t i = 0; i < nr; ++i) assert_true(fabs(Tr[i] - Tc[i]) <= 1e-12 * Tc[i]);
  free(Tr);
  free(Tc);
  H5Fclose(fr);
  H5Fclose(fc);
}

/* ---- observables against the C API ---------------------------------------------------------- */
static double *rd(hid_t f, const char *name, size_t *n) {
  double *x = io_h5_read_double(f, name, n);
  if (!x) fprintf(stderr, "missing dataset %s\n", name);
  assert_non_null(x);
  return x;
}

static void test_against_api(void **state) {
  (void)state;
  const char *out = io_path("api.h5");
  char text[1024];
  const int L = SAN ? 8 : 16, every = 10, steps = 60;
  snprintf(text, sizeof text,
           "title = \"t610 api\"\n[engine]\ntype = \"srd\"\ndimension = 2\ncells = [%d, %d]\nn0 = 8\ndt = 0.5\nalpha = 120\n"
           "eps = 0.9\nsigma = 0.1\nT0 = 2.0\nsteps = %d\nseed = 61\nsort_every = 7\nthreads = 1\n"
           "[observables]\nevery = %d\nsonine_a2 = true\nstructure_factor = {bins = 5}\n[output]\npath = \"%s\"\n",
           L, L, steps, every, out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "api.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));

  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 2;
  o.cells[0] = o.cells[1] = L;
  o.n0 = 8;
  o.dt = 0.5;
  o.alpha_deg = 120;
  o.eps = 0.9;
  o.sigma = 0.1;
  o.T0 = 2.0;
  o.seed = 61;
  o.sort_every = 7;
  o.threads = 1;
  gran_srd *e = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &e));
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t n;
  double *t = rd(f, "time", &n), *T = rd(f, "temperature/T", NULL), *Th = rd(f, "temperature/T_theory", NULL);
  double *ek = rd(f, "energy/e_kin", NULL), *led = rd(f, "energy/ledger_error", NULL), *p = rd(f, "momentum/p", NULL);
  double *Ek = rd(f, "clustering/E_kin", NULL), *ma = rd(f, "clustering/mach", NULL), *sr = rd(f, "clustering/sigma_rho", NULL);
  double *a2 = rd(f, "sonine_a2/a2", NULL), *S = rd(f, "structure_factor/S", NULL);
  assert_int_equal(n, steps / every + 1);
  const double N = 8.0 * L * L, rate = (1 - 0.81) * 0.01 * 8 * sqrt(2.0);
  for (size_t i = 0; i < n; i++) {
    assert_true(t[i] == (double)(i * every) * 0.5);
    if (i > 0) GRAN_ASSERT_OK(gran_srd_advance(e, every));
    gran_srd_obs ob;
    GRAN_ASSERT_OK(gran_srd_observe(e, &ob));
    double k[5], sk[5];
    int64_t c[5];
    GRAN_ASSERT_OK(gran_srd_structure_factor(e, 5, k, sk, c));
    /* the driver's numbers are the engine's, bit for bit */
    assert_true(T[i] == ob.temperature && ek[i] == ob.energy && Ek[i] == ob.e_kin && ma[i] == ob.mach &&
                sr[i] == ob.sigma_rho && a2[i] == ob.a2 && led[i] == ob.ledger_error);
    for (int b = 0; b < 5; b++) assert_true(c[b] == 0 ? S[i * 5 + b] == FILLV : S[i * 5 + b] == sk[b]); /* empty shell: _FillValue */
    /* physics: ledger closed, momentum zero, Haff's law */
    GRAN_ASSERT_ABS(led[i], 0.0, 1e-12);
    for (int k3 = 0; k3 < 3; k3++) GRAN_ASSERT_ABS(p[3 * i + k3], 0.0, 1e-12 * N * sqrt(2.0));
    GRAN_ASSERT_REL(Th[i], 2.0 / ((1 + rate * t[i]) * (1 + rate * t[i])), 1e-14);
    /* relative to the sampled T(0) (the Maxwellian draw of N particles is off T0 by ~sqrt(1/N)): the
     * mean-field rate is about 2 % slow (README), the rest is noise of the ratio (< 1 % at N = 512) */
    GRAN_ASSERT_REL(T[i] / T[0], Th[i] / 2.0, 0.05);
  }
  assert_true(T[n - 1] < 0.7 * T[0]); /* it did cool */
  free(t), free(T), free(Th), free(ek), free(led), free(p), free(Ek), free(ma), free(sr), free(a2), free(S);
  char *eng = io_h5_attr_string(f, "engine");
  assert_string_equal(eng, "srd");
  free(eng);
  H5Fclose(f);
  GRAN_ASSERT_OK(gran_srd_destroy(&e));
}


/* ---- eps_eff clamps: counted per output interval, dt_max recorded, a warning naming it ------ */
static void test_clamps(void **state) {
  (void)state;
  const char *out = io_path("clamp.h5");
  char text[512];
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 8\nn0 = 10\ndt = 1.0\neps = 0.5\nsigma = 0.5\nsteps = 6\n"
           "[observables]\nevery = 3\n[output]\npath = \"%s\"\n", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "clamp.toml", &s));
  int64_t w0 = 0, w1 = 0;
  GRAN_ASSERT_OK(gran_warning_count(&w0));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_warning_count(&w1));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  assert_true(w1 > w0);
  char msg[512];
  GRAN_ASSERT_OK(gran_last_warning_copy(msg, sizeof msg));
  assert_non_null(strstr(msg, "dt <="));
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  int64_t cnt[3] = {-1, -1, -1};
  hid_t d = H5Dopen2(f, "clamps/count", H5P_DEFAULT);
  assert_true(d >= 0 && H5Dread(d, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, cnt) >= 0);
  H5Dclose(d);
  size_t n;
  double *dtm = rd(f, "clamps/dt_max", &n), *led = rd(f, "energy/ledger_error", NULL);
  assert_int_equal(n, 3);
  /* 1 - eps_eff = (1 - eps^2) sigma^2 n sqrt(theta) dt = 1.9 at the start: every cell of >= 2 particles clamps */
  assert_true(cnt[0] == 0 && cnt[1] > 0);
  assert_true(dtm[0] == FILLV && dtm[1] > 0 && dtm[1] < 1.0); /* no clamp: _FillValue */
  for (size_t i = 0; i < n; i++) GRAN_ASSERT_ABS(led[i], 0.0, 1e-12);
  free(dtm), free(led);
  H5Fclose(f);
}

/* ---- checkpoint / resume bit for bit ------------------------------------------------------- */
static const char *sheared_scene(const char *out, int snapshots) {
  static char text[1024];
  snprintf(text, sizeof text,
           "title = \"t610 resume\"\n[engine]\ntype = \"srd\"\ndimension = 3\ncells = [%d, %d, 4]\nn0 = 6\ndt = 0.5\n"
           "eps = 0.95\nsigma = 0.1\nsteps = 48\nseed = 9\nsort_every = 5\n"
           "[boundaries]\nlees_edwards = {shear_rate = 0.02}\n"
           "[observables]\nevery = 8\nstructure_factor = {bins = 3}\nvelocity_profile = true\n%s"
           "[output]\npath = \"%s\"\ncheckpoint_every = 2\n",
           SAN ? 4 : 6, SAN ? 4 : 6, snapshots ? "snapshots = {every = 2}\n" : "", out);
  return text;
}

static void test_resume(void **state) {
  (void)state;
  const char *full = io_path("full.h5"), *split = io_path("split.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(sheared_scene(full, 1), "resume.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, full, "", NULL, NULL));
  gran_run_control ctl;
  memset(&ctl, 0, sizeof ctl);
  ctl.stop_after_checkpoints = 1; /* stops after 2 of 7 output times */
  gran_run_result res;
  const char *ck = io_path("split.ckpt");
  GRAN_ASSERT_OK(gran_scene_run(s, split, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  assert_true(io_exists(ck));
  assert_false(io_exists(split));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  /* the second leg stops again, then a third finishes */
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, &ctl, &res));
  assert_int_equal(res.finished, 0);
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  int nd = 0;
  char first[512] = "";
  int ndiff = io_h5_compare(full, split, &nd, first, sizeof first);
  if (ndiff) fprintf(stderr, "first differing dataset: %s\n", first);
  assert_int_equal(ndiff, 0);
  assert_true(nd >= 30); /* every group, the stress, S(k), profile and snapshot datasets compared */
  hid_t f = H5Fopen(split, H5F_ACC_RDONLY, H5P_DEFAULT);
  size_t n = 0;
  double *eta = rd(f, "stress/eta", &n), *u = rd(f, "velocity_profile/u", NULL);
  assert_true(eta[0] == FILLV); /* no interval before the first output time: _FillValue */
  for (size_t i = 1; i < n; i++) assert_true(isfinite(eta[i])); /* short windows: noisy, sign not asserted */
  const int Ly = SAN ? 4 : 6;
  /* the initial profile is the linear shear profile: top layer faster than the bottom one */
  assert_true(u[3 * (Ly - 1)] - u[0] > 0.5 * 0.02 * (Ly - 1));
  free(eta), free(u);
  /* the sidecars: the final one, no partial one left */
  char xf[600], xp[600];
  snprintf(xf, sizeof xf, "%s/split.xmf", io_tmpdir);
  snprintf(xp, sizeof xp, "%s/split.partial.xmf", io_tmpdir);
  assert_true(io_exists(xf));
  assert_false(io_exists(xp));
  H5Fclose(f);
}

/* ---- replicas ---------------------------------------------------------------------------------- */
static void test_replicas(void **state) {
  (void)state;
  const char *one = io_path("one.h5"), *three = io_path("three.h5");
  const char *text = "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 8\nn0 = 5\neps = 0.8\nsigma = 0.2\nsteps = 20\nseed = 4\n"
                     "[observables]\nevery = 5\n";
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "rep.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, one, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_scene_set_replicas(s, 3, 1));
  GRAN_ASSERT_OK(gran_scene_run(s, three, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  hid_t a = H5Fopen(one, H5F_ACC_RDONLY, H5P_DEFAULT), b = H5Fopen(three, H5F_ACC_RDONLY, H5P_DEFAULT);
  size_t n;
  double *T1 = rd(a, "temperature/T", &n), *T = rd(b, "temperature/T", NULL), *se = rd(b, "temperature/T_se", NULL);
  double *Tr = rd(b, "temperature/T_replicas", NULL);
  for (size_t i = 0; i < n; i++) {
    assert_true(Tr[i] == T1[i]); /* replica 0 is the run without replicas */
    const double m = (Tr[i] + Tr[n + i] + Tr[2 * n + i]) / 3;
    GRAN_ASSERT_REL(T[i], m, 1e-15);
    if (i > 0) assert_true(se[i] > 0 && Tr[n + i] != Tr[i]);
  }
  free(T1), free(T), free(se), free(Tr);
  H5Fclose(a);
  H5Fclose(b);
}

/* ---- XDMF: a small well-formedness check (the subset granary writes: declaration, DOCTYPE,
 * elements with quoted attributes, text) and the HDF references ------------------------------- */
typedef struct {
  char names[64][64];
  int depth;
  int grids, cell_attrs, corect, refs;
} xml_state;

/* checks one HDF reference "FILE:/path" with the element's Dimensions against the HDF5 file */
static void check_ref(const char *xdir, const char *ref, const char *dims_attr) {
  char file[600], path[300];
  const char *colon = strchr(ref, ':');
  assert_non_null(colon);
  snprintf(file, sizeof file, "%s/%.*s", xdir, (int)(colon - ref), ref);
  snprintf(path, sizeof path, "%s", colon + 1);
  hid_t f = H5Fopen(file, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  hsize_t d[4];
  const int r = io_h5_dims(f, path, d);
  if (r < 0) fprintf(stderr, "XDMF references a missing dataset %s in %s\n", path, file);
  assert_true(r >= 1);
  char want[128] = "";
  for (int i = 0; i < r; i++) snprintf(want + strlen(want), sizeof want - strlen(want), "%s%llu", i ? " " : "", (unsigned long long)d[i]);
  assert_string_equal(want, dims_attr);
  H5Fclose(f);
}

static void xdmf_check(const char *xmf, const char *xdir, xml_state *st) {
  char *x = io_read_file(xmf);
  assert_non_null(x);
  memset(st, 0, sizeof *st);
  const char *p = x;
  char last_dims[256] = "", last_format[256] = "";
  int in_dataitem = 0;
  assert_true(strncmp(p, "<?xml", 5) == 0);
  while (*p) {
    if (*p != '<') {
      /* text: no bare '<'; '&' only as an entity */
      const char *q = p;
      while (*q && *q != '<') {
        if (*q == '&') assert_true(strncmp(q, "&amp;", 5) == 0 || strncmp(q, "&lt;", 4) == 0 || strncmp(q, "&gt;", 4) == 0 ||
                                   strncmp(q, "&quot;", 6) == 0);
        q++;
      }
      if (in_dataitem && !strcmp(last_format, "HDF")) {
        char ref[400];
        size_t len = (size_t)(q - p);
        assert_true(len < sizeof ref);
        memcpy(ref, p, len);
        ref[len] = '\0';
        check_ref(xdir, ref, last_dims);
        st->refs++;
      }
      p = q;
      continue;
    }
    if (!strncmp(p, "<?", 2)) {
      p = strstr(p, "?>");
      assert_non_null(p);
      p += 2;
      continue;
    }
    if (!strncmp(p, "<!DOCTYPE", 9)) {
      p = strchr(p, '>');
      assert_non_null(p);
      p++;
      continue;
    }
    if (p[1] == '/') { /* end tag */
      const char *q = p + 2;
      char name[64];
      int k = 0;
      while (*q && *q != '>' && k < 63) name[k++] = *q++;
      name[k] = '\0';
      assert_true(*q == '>');
      assert_true(st->depth > 0);
      assert_string_equal(st->names[st->depth - 1], name);
      st->depth--;
      in_dataitem = 0;
      p = q + 1;
      continue;
    }
    /* start tag: name, attributes name="value", then > or /> */
    const char *q = p + 1;
    char name[64];
    int k = 0;
    while (*q && (isalnum((unsigned char)*q) || *q == '_') && k < 63) name[k++] = *q++;
    name[k] = '\0';
    assert_true(k > 0);
    char dims[256] = "", fmt[256] = "";
    for (;;) {
      while (*q == ' ' || *q == '\n') q++;
      if (*q == '>' || (*q == '/' && q[1] == '>')) break;
      char an[64], av[256];
      int m = 0;
      while (*q && (isalnum((unsigned char)*q) || *q == '_') && m < 63) an[m++] = *q++;
      an[m] = '\0';
      assert_true(m > 0 && *q == '=' && q[1] == '"');
      q += 2;
      m = 0;
      while (*q && *q != '"' && m < 255) {
        assert_true(*q != '<');
        av[m++] = *q++;
      }
      av[m] = '\0';
      assert_true(*q == '"');
      q++;
      if (!strcmp(an, "Dimensions")) snprintf(dims, sizeof dims, "%s", av);
      if (!strcmp(an, "Format")) snprintf(fmt, sizeof fmt, "%s", av);
      if (!strcmp(an, "Center") && !strcmp(av, "Cell")) st->cell_attrs++;
      if (!strcmp(an, "TopologyType") && (!strcmp(av, "3DCORECTMesh") || !strcmp(av, "2DCORECTMesh"))) st->corect++;
      if (!strcmp(name, "Grid") && !strcmp(an, "GridType") && !strcmp(av, "Uniform")) st->grids++;
    }
    if (*q == '/') {
      p = q + 2;
      continue;
    }
    assert_true(st->depth < 64);
    snprintf(st->names[st->depth++], 64, "%s", name);
    in_dataitem = !strcmp(name, "DataItem");
    snprintf(last_dims, sizeof last_dims, "%s", dims);
    snprintf(last_format, sizeof last_format, "%s", fmt);
    p = q + 1;
  }
  assert_int_equal(st->depth, 0);
  free(x);
}

/* a numeric attribute of an object of f (NAN when missing) */
static double attr_num(hid_t f, const char *obj, const char *name) {
  double v = NAN;
  hid_t a = H5Aopen_by_name(f, obj, name, H5P_DEFAULT, H5P_DEFAULT);
  if (a < 0) {
    fprintf(stderr, "missing attribute %s of %s\n", name, obj);
    return v;
  }
  if (H5Aread(a, H5T_NATIVE_DOUBLE, &v) < 0) v = NAN;
  H5Aclose(a);
  return v;
}

static void test_snapshots(void **state) {
  (void)state;
  for (int dim = 2; dim <= 3; dim++) {
    char text[1024], leaf[32];
    snprintf(leaf, sizeof leaf, "snap%d.h5", dim);
    const char *out = io_path(leaf);
    snprintf(text, sizeof text,
             "[engine]\ntype = \"srd\"\ndimension = %d\ncells = %s\nn0 = 7\ndt = 0.5\neps = 0.9\nsigma = 0.1\nsteps = 30\nseed = 12\n"
             "[boundaries]\nlees_edwards = {shear_rate = 0.05}\n"
             "[observables]\ntimes = [0, 5, 10, 15]\nsnapshots = {times = [0, 7.5]}\n[output]\npath = \"%s\"\n",
             dim, dim == 2 ? "[10, 6]" : "[5, 4, 3]", out);
    gran_scene *s = NULL;
    GRAN_ASSERT_OK(gran_scene_parse(text, "snap.toml", &s));
    GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
    GRAN_ASSERT_OK(gran_scene_destroy(&s));
    char xmf[600];
    snprintf(xmf, sizeof xmf, "%s/snap%d.xmf", io_tmpdir, dim);
    xml_state st;
    xdmf_check(xmf, io_tmpdir, &st);
    assert_int_equal(st.grids, 2);
    assert_int_equal(st.corect, 2);
    assert_int_equal(st.cell_attrs, 8);
    assert_int_equal(st.refs, 8);
    char *x = io_read_file(xmf);
    /* nodes: cells + 1, z y x; 2-D: the plane z = 0 of a 3-D mesh (one node along z), so that
     * ParaView puts it in the x-y plane */
    assert_non_null(strstr(x, dim == 3 ? "Dimensions=\"4 5 6\"" : "Dimensions=\"1 7 11\""));
    assert_null(strstr(x, "2DCORECTMesh"));
    assert_null(strstr(x, "ORIGIN_DXDY\""));
    assert_non_null(strstr(x, "GeometryType=\"ORIGIN_DXDYDZ\""));
    /* the HDF5 file by its base name (it sits beside the sidecar), not by the path it was written to */
    char ref[64];
    snprintf(ref, sizeof ref, ">snap%d.h5:/fields/snap_000000/density<", dim);
    assert_non_null(strstr(x, ref));
    assert_null(strstr(x, io_tmpdir));
    /* the temporal collection: one Time per grid, the snapshot times */
    double xt[4];
    int nxt = 0;
    for (const char *q = strstr(x, "<Time Value=\""); q && nxt < 4; q = strstr(q + 1, "<Time Value=\""))
      xt[nxt++] = strtod(q + strlen("<Time Value=\""), NULL);
    assert_int_equal(nxt, 2);
    free(x);
    /* the fields sum to N, the momentum and twice the kinetic energy of their output time */
    hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
    const int nc = dim == 2 ? 60 : 60;
    const double N = 7.0 * nc;
    size_t n;
    double *p = rd(f, "momentum/p", NULL), *ek = rd(f, "energy/e_kin", NULL), *tt = rd(f, "time", &n);
    assert_true(n == 5 && tt[2] == 7.5); /* the snapshot time joined the output times */
    const char *snaps[2] = {"/fields/snap_000000", "/fields/snap_000002"};
    const int row[2] = {0, 2}; /* t = 7.5 joined the output times 0, 5, 10, 15 as row 2 */
    /* each snapshot's time, step (time / dt, the row of stats/steps) and output index, in its
     * group's attributes and in /fields/{time, step, output_index}, which list the snapshots */
    double *steps = rd(f, "stats/steps", NULL), *ft = rd(f, "fields/time", &n);
    assert_int_equal(n, 2);
    double *fs = rd(f, "fields/step", &n);
    assert_int_equal(n, 2);
    double *fi = rd(f, "fields/output_index", &n);
    assert_int_equal(n, 2);
    for (int j = 0; j < 2; j++) {
      const double t = tt[row[j]];
      assert_true(attr_num(f, snaps[j], "time") == t && ft[j] == t && xt[j] == t);
      assert_true(attr_num(f, snaps[j], "step") == steps[row[j]] && fs[j] == steps[row[j]]);
      assert_true(steps[row[j]] == t / 0.5);
      assert_true(attr_num(f, snaps[j], "output_index") == row[j] && fi[j] == row[j]);
    }
    assert_true(steps[2] == 15.0);
    free(tt), free(steps), free(ft), free(fs), free(fi);
    for (int j = 0; j < 2; j++) {
      char nm[128];
      snprintf(nm, sizeof nm, "%s/count", snaps[j]);
      double *c = rd(f, nm, &n);
      snprintf(nm, sizeof nm, "%s/velocity", snaps[j]);
      double *v = rd(f, nm, NULL);
      snprintf(nm, sizeof nm, "%s/temperature", snaps[j]);
      double *th = rd(f, nm, NULL);
      assert_int_equal(n, (size_t)nc);
      double sn = 0, P[3] = {0, 0, 0}, e2 = 0;
      for (int c0 = 0; c0 < nc; c0++) {
        sn += c[c0];
        double v2 = 0;
        for (int k = 0; k < 3; k++) {
          P[k] += c[c0] * v[3 * c0 + k];
          v2 += v[3 * c0 + k] * v[3 * c0 + k];
        }
        e2 += c[c0] * (dim * th[c0] + v2);
        if (dim == 2) assert_true(v[3 * c0 + 2] == 0.0);
      }
      assert_true(sn == N);
      for (int k = 0; k < 3; k++) GRAN_ASSERT_ABS(P[k], p[3 * row[j] + k], 1e-12 * N);
      GRAN_ASSERT_REL(0.5 * e2, ek[row[j]], 1e-12);
      free(c), free(v), free(th);
    }
    free(p), free(ek);
    H5Fclose(f);
  }
}

/* ---- vibrated bed: walls, gravity, a vibrating bottom ------------------------------------- */
static void test_vibrated_bed(void **state) {
  (void)state;
  const char *out = io_path("bed.h5");
  char text[1024];
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = [8, 12]\nn0 = 6\ndt = 0.2\neps = 0.95\nsigma = 0.2\nsteps = %d\n"
           "[boundaries]\nwalls = {axis = \"y\", rule = \"no-slip\"}\nvibrating_wall = {amplitude = 0.5, omega = 0.6}\n"
           "[forces]\ngravity = [0, -0.05]\n[observables]\nevery = 20\nvelocity_profile = true\n[output]\npath = \"%s\"\n",
           SAN ? 60 : 200, out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "bed.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  size_t n;
  double *led = rd(f, "energy/ledger_error", &n), *ext = rd(f, "energy/e_external", NULL);
  for (size_t i = 0; i < n; i++) GRAN_ASSERT_ABS(led[i], 0.0, 1e-10);
  assert_true(ext[n - 1] != 0.0); /* gravity and the wall do work */
  free(led), free(ext);
  H5Fclose(f);
}


/* ---- the shipped scenes: every .toml file of scenes/srd/ parses; the vibrated bed runs (shortened under
 * the sanitizers) with its energy ledger closed and its output beside its XDMF sidecar -------- */
static void test_shipped_scenes(void **state) {
  (void)state;
  char dir[4096], path[4400];
  snprintf(dir, sizeof dir, "%s/scenes/srd", gran_test_source_dir());
  DIR *d = opendir(dir);
  assert_non_null(d);
  int nscenes = 0;
  struct dirent *e;
  while ((e = readdir(d)) != NULL) {
    const size_t n = strlen(e->d_name);
    if (n < 6 || strcmp(e->d_name + n - 5, ".toml") != 0) continue;
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    gran_scene *s = NULL;
    if (gran_scene_load(path, &s) != GRAN_SUCCESS) fprintf(stderr, "%s: %s\n", path, gran_last_error_message());
    assert_non_null(s);
    int64_t nt = 0;
    double t0 = -1, t1 = -1;
    GRAN_ASSERT_OK(gran_scene_sizes(s, NULL, &nt, NULL, &t0, &t1));
    assert_true(nt >= 10 && t0 == 0.0 && t1 > 0);
    GRAN_ASSERT_OK(gran_scene_destroy(&s));
    nscenes++;
  }
  closedir(d);
  assert_true(nscenes >= 7); /* haff, clustering, four a2, vibrated bed */
  snprintf(path, sizeof path, "%s/vibrated-bed.toml", dir);
  char *text = io_read_file(path);
  assert_non_null(text);
  if (SAN) {
    char *st = strstr(text, "steps = 4000");
    assert_non_null(st);
    memcpy(st, "steps =  300", 12);
  }
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, path, &s));
  free(text);
  const char *out = io_path("bed-shipped.h5");
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
  char xmf[600];
  snprintf(xmf, sizeof xmf, "%s/bed-shipped.xmf", io_tmpdir);
  assert_true(io_exists(xmf));
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  size_t n;
  double *led = rd(f, "energy/ledger_error", &n), *T = rd(f, "temperature/T", NULL);
  for (size_t i = 0; i < n; i++) GRAN_ASSERT_ABS(led[i], 0.0, 1e-10);
  if (!SAN) {
    /* the steady state of the scene's comment: the driven bed holds T near 0.06 (second half) */
    double m = 0;
    for (size_t i = n / 2; i < n; i++) m += T[i];
    m /= (double)(n - n / 2);
    assert_true(m > 0.03 && m < 0.12);
  }
  free(led), free(T);
  H5Fclose(f);
}


/* ---- the command line: `granary run` prints the GSRD header, progress and the summary -------- */
static void test_cli(void **state) {
  (void)state;
  const char *cli = getenv("GRAN_CLI") ? getenv("GRAN_CLI") : "build/granary";
  const char *sc = io_path("cli.toml"), *out = io_path("cli.h5");
  io_write_file(sc, "title = \"t610 cli\"\n[engine]\ntype = \"srd\"\ndimension = 2\ncells = 8\nn0 = 5\neps = 0.9\n"
                    "sigma = 0.2\nsteps = 40\n[observables]\nevery = 10\n");
  char cmd[2048], buf[8192] = "";
  snprintf(cmd, sizeof cmd, "%s run %s -o %s --no-checkpoint 2>&1", cli, sc, out);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t n = fread(buf, 1, sizeof buf - 1, p);
  buf[n] = '\0';
  const int st = pclose(p);
  if (st != 0) fprintf(stderr, "%s\n", buf);
  assert_int_equal(st, 0);
  assert_non_null(strstr(buf, "t610 cli"));
  assert_non_null(strstr(buf, "engine srd (cpu), 2-D, 64 cells of a = 1, 320 particles"));
  assert_non_null(strstr(buf, "T_theory")); /* the summary: T beside Haff's law */
  assert_non_null(strstr(buf, "Mach_sim"));
  /* one species, Mach without theory: no species column, no Mach_theory, no nan anywhere */
  assert_null(strstr(buf, "Mach_theory"));
  assert_null(strstr(buf, "nan"));
  assert_null(strstr(buf, "    k |"));
  assert_non_null(strstr(buf, "        time |        T_sim"));
  assert_true(io_exists(out));
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t610");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bad_scenes), cmocka_unit_test(test_device),   cmocka_unit_test(test_against_api),
      cmocka_unit_test(test_resume),     cmocka_unit_test(test_replicas), cmocka_unit_test(test_snapshots),
      cmocka_unit_test(test_vibrated_bed), cmocka_unit_test(test_shipped_scenes), cmocka_unit_test(test_clamps),
      cmocka_unit_test(test_cli),
  };
  return cmocka_run_group_tests(tests, NULL, teardown);
}
