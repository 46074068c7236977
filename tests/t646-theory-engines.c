/* t646-theory-engines.c - `granary theory SCENE` ($GRAN_CLI) for every engine:
 *  - aggregating DSMC scenes (cell selector with the monomer law, low-rank selector with the binary
 *    law): with --times scene, T_k(t) is the run driver's temperatures/T_theory of the same scene to
 *    1e-12 and n_k(t) x one volume its clusters/n_theory; n_total and T_mean are the sums of the
 *    rows; the DSMC outline's aggregation scene gives T_1(60) = 0.934 (the cooling-mixture theory: 0.777);
 *  - GSRD free cooling: T(t) = T0 / (1 + t/tau)^2 with 1/tau = (1 - eps^2) sigma^2 (n0/a^d) sqrt(T0)
 *    (x 2/3 in 3-D) computed here, equal to the run driver's temperature/T_theory; the
 *    Poisson-occupancy factor against docs/physics.md (0.98882, 0.97728 at n0 = 10); T(t) stays finite
 *    where the rate overflows (sigma = 1e154): T0 at t = 0, then the formula in long double to 1e-12;
 *  - GSRD shear viscosity: the CLI's numbers are gran_srd_viscosity_theory_'s, which is Eq. 1.48 /
 *    1.49 + collisional written out here (0.1306 at 2-D alpha = 90, n0 = 10, as the scenes say);
 *  - a scene without a theory exits 0 and says so; options without a theory exit 2 naming them.
 * Every --json output is parsed. */
#include "io_test_util.h"
#include "json_test_util.h"
#include "srd/srd_theory.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static const char *cli(void) {
  const char *c = getenv("GRAN_CLI");
  return c ? c : "build/granary";
}

static char outbuf[1 << 21];

/* `granary theory ARGS --json`, parsed into *root (exit status 0 and valid JSON required) */
static void theory_json(const char *args, jv *root) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "%s theory %s --json", cli(), args);
  int st = sh(cmd, outbuf, sizeof outbuf, 0);
  if (st) fail_msg("%s exited %d", cmd, st);
  if (!json_parse(outbuf, root)) fail_msg("%s: not valid JSON: %.600s", cmd, outbuf);
  assert_int_equal(root->type, 5);
}

static const char *jstr_of(const jv *v) {
  if (!v || v->type != 3) fail_msg("expected a JSON string");
  return v->str;
}

static void run_scene(const char *scene, const char *out) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "%s run %s -o %s --no-checkpoint --quiet", cli(), scene, out);
  int st = sh(cmd, outbuf, sizeof outbuf, 1);
  if (st) fail_msg("%s exited %d: %s", cmd, st, outbuf);
}

/* ---- aggregation ---------------------------------------------------------------------------- */

#define AGG_M 10
#define AGG_NT 12
static const char *kAggFmt =
    "title = \"aggregation, small\"\n"
    "[mixture]\nnspecies = %d\nm1 = 1.0\nsigma1 = 1.0\ndensity_law = { n1 = 0.01, theta = 400.0 }\n"
    "[restitution]\neps = 0.9\n"
    "[initial]\ntemperatures = \"equal\"\nT_mean = 1.0\n"
    "[engine]\nselector = \"%s\"\nvolume = 2e5\nseed = 7\nt_end = 60.0\n"
    "%s"
    "[observables]\ntimes = { linear = { start = 5.0, stop = 60.0, n = %d } }\ntemperatures = true\nmsd = false\n"
    "energy = true\n"
    "[output]\npath = \"unused.h5\"\n";

static void agg_case(const char *selector, const char *processes) {
  char text[4096];
  snprintf(text, sizeof text, kAggFmt, AGG_M, selector, processes, AGG_NT);
  char scene[600], out[600], leaf[64];
  snprintf(leaf, sizeof leaf, "agg-%s.toml", selector);
  snprintf(scene, sizeof scene, "%s", io_path(leaf));
  snprintf(leaf, sizeof leaf, "agg-%s.h5", selector);
  snprintf(out, sizeof out, "%s", io_path(leaf));
  io_write_file(scene, text);
  run_scene(scene, out);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t nT = 0, nn = 0;
  double *Td = io_h5_read_double(f, "temperatures/T_theory", &nT), *nd = io_h5_read_double(f, "clusters/n_theory", &nn);
  H5Fclose(f);
  assert_non_null(Td);
  assert_non_null(nd);
  assert_int_equal(nT, AGG_NT * AGG_M);
  assert_int_equal(nn, AGG_NT * AGG_M);

  char args[700];
  snprintf(args, sizeof args, "%s --times scene", scene);
  jv root;
  theory_json(args, &root);
  assert_string_equal(jstr_of(jget(&root, "theory")), "aggregation");
  assert_string_equal(jstr_of(jget(&root, "selector")), selector);
  assert_true(jnum(jget(&root, "nspecies")) == AGG_M);
  const jv *T = jget(&root, "T"), *n = jget(&root, "n"), *times = jget(&root, "times");
  assert_non_null(T);
  assert_non_null(n);
  assert_int_equal(T->n, AGG_NT);
  assert_int_equal(n->n, AGG_NT);
  GRAN_ASSERT_REL(jnum(jat(times, 0)), 5.0, 1e-15);
  GRAN_ASSERT_REL(jnum(jat(times, AGG_NT - 1)), 60.0, 1e-15);
  /* the driver's rows: T_k(t) to 1e-12; n_theory = n_k(t) x one volume for every row and size */
  const double V = nd[0] / jnum(jat(jat(n, 0), 0));
  assert_true(V > 0);
  for (int i = 0; i < AGG_NT; i++)
    for (int k = 0; k < AGG_M; k++) {
      const double Tc = jnum(jat(jat(T, i), k)), nc = jnum(jat(jat(n, i), k));
      GRAN_ASSERT_REL(Tc, Td[i * AGG_M + k], 1e-12);
      GRAN_ASSERT_REL(nc * V, nd[i * AGG_M + k], 1e-12);
    }
  /* T_1(60) of the driver, printed */
  printf("%s: T_1(60) = %.15g (CLI) %.15g (driver), volume %g\n", selector, jnum(jat(jat(T, AGG_NT - 1), 0)),
         Td[(AGG_NT - 1) * AGG_M], V);
  /* the totals: number density of the sizes 1..M and the number-weighted mean temperature */
  for (int i = 0; i < AGG_NT; i++) {
    double a = 0, b = 0;
    for (int k = 0; k < AGG_M; k++) {
      a += jnum(jat(jat(n, i), k));
      b += jnum(jat(jat(n, i), k)) * jnum(jat(jat(T, i), k));
    }
    GRAN_ASSERT_REL(jnum(jat(jget(&root, "n_total"), i)), a, 1e-14);
    GRAN_ASSERT_REL(jnum(jat(jget(&root, "T_mean"), i)), b / a, 1e-14);
  }
  /* aggregation lowers the number: n_total(60) < n_total(0) */
  assert_true(jnum(jat(jget(&root, "n_total"), AGG_NT - 1)) < jnum(jget(&root, "n_total0")));
  assert_true(jget(&root, "not_covered")->n >= 1);
  jfree(&root);
  free(Td);
  free(nd);
}

static void test_aggregation_driver(void **state) {
  (void)state;
  agg_case("cell", "[cell]\ncells = 2\ndt = 0.5\ne_agg = 1.0\ne_frag = 3.0\neps_f = 0.7\n");
  agg_case("lowrank", "[aggregation]\ne_agg = 1.0\ne_frag = 3.0\neps_f = 0.7\nfrag_law = \"binary\"\n");
}

static void test_aggregation_outline(void **state) {
  (void)state;
  char args[1024];
  snprintf(args, sizeof args, "%s/scenes/outline/aggregation.toml --times 60", gran_test_source_dir());
  jv root;
  theory_json(args, &root);
  /* the Smoluchowski kinetics: T_1(60) = 0.9338 (the cooling mixture of fixed species: 0.777) */
  const double T1 = jnum(jat(jat(jget(&root, "T"), 0), 0));
  GRAN_ASSERT_ABS(T1, 0.93379, 5e-5);
  assert_true(jget(&root, "e_frag")->type == 2);
  assert_null(jget(&root, "tau0")); /* no HCS */
  jfree(&root);
  /* the text form: the same T_1(60), the sizes of density ~1e-123 at t = 0 not listed */
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "%s theory %s", cli(), args);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  assert_non_null(strstr(outbuf, "Smoluchowski"));
  assert_non_null(strstr(outbuf, "0.933787"));
  assert_null(strstr(outbuf, "e-123"));
  assert_non_null(strstr(outbuf, "no theory here for: "));
  /* options the kinetics has no theory for: exit 2, named */
  snprintf(cmd, sizeof cmd, "%s theory %s --lags 1", cli(), args);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 2);
  assert_non_null(strstr(outbuf, "--lags"));
  snprintf(cmd, sizeof cmd, "%s theory %s --approximation sonine", cli(), args);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 2);
  assert_non_null(strstr(outbuf, "--approximation sonine"));
}

/* ---- GSRD: Haff's law ------------------------------------------------------------------------ */

static const char *kHaffFmt =
    "title = \"GSRD Haff, small\"\n"
    "[engine]\ntype = \"srd\"\ndimension = %d\ncells = %d\na = %g\nn0 = 10\ndt = %g\nalpha = 90\neps = %g\n"
    "sigma = %g\nT0 = %g\nsteps = 200\nseed = 3\nthreads = 1\n"
    "[observables]\nevery = 20\nclustering = false\n"
    "[output]\npath = \"unused.h5\"\n";

static void test_gsrd_haff(void **state) {
  (void)state;
  const double a = 0.5, dt = 0.5, eps = 0.9, sigma = 0.02, T0 = 2.0, n0 = 10;
  char text[2048], scene[600], out[600];
  snprintf(text, sizeof text, kHaffFmt, 2, 8, a, dt, eps, sigma, T0);
  snprintf(scene, sizeof scene, "%s", io_path("haff2.toml"));
  snprintf(out, sizeof out, "%s", io_path("haff2.h5"));
  io_write_file(scene, text);
  run_scene(scene, out);
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t nt = 0, nt2 = 0;
  double *Td = io_h5_read_double(f, "temperature/T_theory", &nt), *tt = io_h5_read_double(f, "time", &nt2);
  H5Fclose(f);
  assert_non_null(Td);
  assert_non_null(tt);
  assert_int_equal(nt, nt2);
  assert_true(nt >= 10);

  char args[700];
  snprintf(args, sizeof args, "%s --times scene", scene);
  jv root;
  theory_json(args, &root);
  assert_string_equal(jstr_of(jget(&root, "engine")), "srd");
  assert_string_equal(jstr_of(jget(&root, "theory")), "gsrd");
  const jv *h = jget(&root, "haff");
  assert_non_null(h);
  assert_int_equal(h->type, 5);
  /* the closed form: 1/tau = (1 - eps^2) sigma^2 (n0 / a^2) sqrt(T0) in 2-D */
  const double rate = (1 - eps * eps) * sigma * sigma * (n0 / (a * a)) * sqrt(T0);
  GRAN_ASSERT_REL(jnum(jget(h, "rate")), rate, 1e-14);
  const double pf = jnum(jget(h, "poisson_factor"));
  GRAN_ASSERT_ABS(pf, 0.98882, 5e-6); /* docs/physics.md, n0 = 10, 2-D */
  GRAN_ASSERT_REL(jnum(jget(h, "rate_poisson")), pf * rate, 1e-15);
  const jv *T = jget(&root, "T"), *Tp = jget(&root, "T_poisson"), *times = jget(&root, "times");
  assert_int_equal(T->n, (int)nt);
  for (size_t i = 0; i < nt; i++) {
    const double t = jnum(jat(times, (int)i)), x = 1 + rate * t, y = 1 + pf * rate * t;
    GRAN_ASSERT_REL(t, tt[i], 1e-15);
    GRAN_ASSERT_REL(jnum(jat(T, (int)i)), T0 / (x * x), 1e-13);
    GRAN_ASSERT_REL(jnum(jat(T, (int)i)), Td[i], 1e-15); /* the driver's temperature/T_theory */
    GRAN_ASSERT_REL(jnum(jat(Tp, (int)i)), T0 / (y * y), 1e-13);
  }
  assert_true(jnum(jat(T, (int)nt - 1)) < 0.9 * T0); /* it cools */
  assert_int_equal(jget(&root, "viscosity")->type, 0); /* no shear: null */
  jfree(&root);
  free(Td);
  free(tt);

  /* 3-D: k = 2/3; Poisson factor 0.97728 at n0 = 10 */
  snprintf(text, sizeof text, kHaffFmt, 3, 4, 1.0, 1.0, 0.8, 0.05, 1.0);
  snprintf(scene, sizeof scene, "%s", io_path("haff3.toml"));
  io_write_file(scene, text);
  snprintf(args, sizeof args, "%s --times 0,10,1000", scene);
  theory_json(args, &root);
  h = jget(&root, "haff");
  const double r3 = 2.0 / 3.0 * (1 - 0.8 * 0.8) * 0.05 * 0.05 * 10;
  GRAN_ASSERT_REL(jnum(jget(h, "rate")), r3, 1e-14);
  GRAN_ASSERT_ABS(jnum(jget(h, "poisson_factor")), 0.97728, 5e-6);
  GRAN_ASSERT_REL(jnum(jat(jget(&root, "T"), 2)), 1.0 / ((1 + 1000 * r3) * (1 + 1000 * r3)), 1e-13);
  jfree(&root);

  /* the factor: 1 - (1/2 - 3/(4 d)) / n0 for large n0, 0 for bad arguments */
  GRAN_ASSERT_ABS(gran_srd_haff_poisson_factor_(2, 1e4), 1 - 0.125e-4, 2e-7);
  GRAN_ASSERT_ABS(gran_srd_haff_poisson_factor_(3, 1e4), 1 - 0.25e-4, 2e-7);
  assert_true(gran_srd_haff_poisson_factor_(4, 10) == 0 && gran_srd_haff_poisson_factor_(2, -1) == 0);
  { /* gran_srd_haff_T_: the formula where the rate is finite; a rate that overflows (sigma = 1e154, as a fuzzed
     * scene had: 0 * inf = NaN at t = 0) gives T0 at t = 0, and finite values >= 0 after */
    gran_srd_options h;
    GRAN_ASSERT_OK(gran_srd_options_default(&h));
    h.dim = 3;
    h.eps = 0.9;
    h.sigma = 0.1;
    h.n0 = 10;
    h.T0 = 2;
    const double r = (2.0 / 3.0) * (1 - 0.81) * 0.01 * 10 * sqrt(2.0);
    for (double t = 0; t < 1e4; t = 10 * t + 1) {
      const double x = 1 + 0.97 * r * t;
      GRAN_ASSERT_REL(gran_srd_haff_T_(&h, 0.97, t), 2 / (x * x), 1e-15);
    }
    h.sigma = 1e154;
    h.T0 = 1e9;
    h.n0 = 5;
    assert_true(!isfinite(gran_srd_haff_rate_(&h)));
    assert_true(gran_srd_haff_T_(&h, 1.0, 0.0) == 1e9);
    /* against the formula in long double (its range holds the rate: about 5e-17 of 1e4932) */
    const long double rl = (2.0L / 3.0L) * (1.0L - 0.81L) * 1e154L * 1e154L * 5.0L * sqrtl(1e9L);
    const double ts[4] = {1e-300, 1e-154, 1e-150, 1e10};
    for (int i = 0; i < 4; i++) {
      const double T = gran_srd_haff_T_(&h, 1.0, ts[i]);
      const long double x = 1.0L + rl * (long double)ts[i];
      const double want = (double)(1e9L / (x * x));
      assert_true(isfinite(T) && T >= 0);
      if (want > 1e-300) GRAN_ASSERT_REL(T, want, 1e-12);
      else assert_true(T < 1e-290);
    }
  }

  /* --lags and --approximation have no GSRD theory: exit 2 */
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "%s theory %s --times 1 --lags 0.5", cli(), scene);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 2);
  assert_non_null(strstr(outbuf, "GSRD"));
  snprintf(cmd, sizeof cmd, "%s theory %s --approximation sonine", cli(), scene);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 2);
}

/* ---- GSRD: shear viscosity ------------------------------------------------------------------- */

/* Eq. 1.48 / 1.49 + collisional, written out: kinematic viscosity at temperature T */
static void nu_closed(int dim, double M, double alpha_deg, double a, double dt, double T, double *kin, double *coll) {
  const double al = alpha_deg * M_PI / 180, q = M - 1 + exp(-M);
  *kin = dim == 2 ? T * dt * (M / (q * (1 - cos(2 * al))) - 0.5)
                  : T * dt * (5 * M / (q * (4 - 2 * cos(al) - 2 * cos(2 * al))) - 0.5);
  *coll = a * a / (6.0 * dim * dt) * q / M * (1 - cos(al));
}

static const char *kShearFmt =
    "title = \"GSRD shear, small\"\n"
    "[engine]\ntype = \"srd\"\ndimension = %d\ncells = 6\na = %g\nn0 = %g\ndt = %g\nalpha = %g\nthermostat = \"global\"\n"
    "T0 = %g\nsteps = 100\nseed = 3\n"
    "[boundaries]\nlees_edwards = {shear_rate = 0.05}\n"
    "[observables]\nevery = 50\nstress = true\n"
    "[output]\npath = \"unused.h5\"\n";

static void visc_case(int dim, double a, double n0, double dt, double alpha, double T0) {
  char text[2048], scene[600];
  snprintf(text, sizeof text, kShearFmt, dim, a, n0, dt, alpha, T0);
  snprintf(scene, sizeof scene, "%s", io_path("shear.toml"));
  io_write_file(scene, text);
  jv root;
  theory_json(scene, &root);
  const jv *v = jget(&root, "viscosity");
  assert_non_null(v);
  assert_int_equal(v->type, 5);
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = dim;
  o.a = a;
  o.n0 = n0;
  o.dt = dt;
  o.alpha_deg = alpha;
  double fk, fc, ck, cc;
  GRAN_ASSERT_OK(gran_srd_viscosity_theory_(&o, T0, &fk, &fc));
  nu_closed(dim, n0, alpha, a, dt, T0, &ck, &cc);
  GRAN_ASSERT_REL(jnum(jget(v, "nu_kinetic")), fk, 1e-15);
  GRAN_ASSERT_REL(jnum(jget(v, "nu_collisional")), fc, 1e-15);
  GRAN_ASSERT_REL(fk, ck, 1e-14);
  GRAN_ASSERT_REL(fc, cc, 1e-14);
  GRAN_ASSERT_REL(jnum(jget(v, "nu")), fk + fc, 1e-15);
  GRAN_ASSERT_REL(jnum(jget(v, "eta")), n0 / pow(a, dim) * (fk + fc), 1e-14);
  GRAN_ASSERT_REL(jnum(jget(v, "theta")), T0, 1e-15);
  assert_int_equal(jget(&root, "haff")->type, 0); /* sheared: no Haff's law */
  jfree(&root);
}

static void test_gsrd_viscosity(void **state) {
  (void)state;
  visc_case(2, 1, 10, 1, 90, 1);
  visc_case(3, 2, 7, 0.5, 120, 3);
  visc_case(2, 0.7, 5, 0.2, 30, 0.5);
  /* the shipped scenes: 0.1306 (2-D, alpha 90) and 0.4759 (3-D, alpha 90) as their comments say */
  const char *names[2] = {"viscosity-2d-a090", "viscosity-3d-a090"};
  const double nu[2] = {0.1306, 0.4759};
  for (int i = 0; i < 2; i++) {
    char args[1024];
    snprintf(args, sizeof args, "%s/scenes/srd/%s.toml", gran_test_source_dir(), names[i]);
    jv root;
    theory_json(args, &root);
    GRAN_ASSERT_ABS(jnum(jget(jget(&root, "viscosity"), "nu")), nu[i], 5e-5);
    jfree(&root);
  }
  /* GSRD (eps < 1) under shear: the granular terms left out are named */
  char args[1024];
  snprintf(args, sizeof args, "%s/scenes/srd/viscosity-gsrd-a090.toml", gran_test_source_dir());
  jv root;
  theory_json(args, &root);
  const jv *nc = jget(&root, "not_covered");
  int found = 0;
  for (int i = 0; i < nc->n; i++) found |= strstr(jstr_of(jat(nc, i)), "Eq. 2.55") != NULL;
  assert_true(found);
  jfree(&root);
  /* 2-D alpha = 180: Eq. 1.48 diverges, GRAN_ERR_DOMAIN; bad options GRAN_ERR_ARG */
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 2;
  o.alpha_deg = 180;
  double k, c;
  assert_int_equal(gran_srd_viscosity_theory_(&o, 1.0, &k, &c), GRAN_ERR_DOMAIN);
  o.alpha_deg = 90;
  assert_int_equal(gran_srd_viscosity_theory_(&o, NAN, &k, &c), GRAN_ERR_ARG);
  o.n0 = 0;
  assert_int_equal(gran_srd_viscosity_theory_(&o, 1.0, &k, &c), GRAN_ERR_ARG);
}

/* ---- no theory, and the mixture's JSON ----------------------------------------------------- */

static void test_no_theory(void **state) {
  (void)state;
  char args[1024], cmd[1200];
  snprintf(args, sizeof args, "%s/scenes/srd/vibrated-bed.toml", gran_test_source_dir());
  snprintf(cmd, sizeof cmd, "%s theory %s", cli(), args);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  assert_non_null(strstr(outbuf, "no theory for this scene"));
  jv root;
  theory_json(args, &root);
  assert_string_equal(jstr_of(jget(&root, "theory")), "none");
  assert_int_equal(jget(&root, "haff")->type, 0);
  assert_int_equal(jget(&root, "viscosity")->type, 0);
  assert_true(jget(&root, "not_covered")->n >= 1);
  jfree(&root);
  /* the cooling mixture: "theory": "mixture"; --times scene are the scene's output times */
  snprintf(args, sizeof args, "%s/scenes/fig2.toml --times scene", gran_test_source_dir());
  theory_json(args, &root);
  assert_string_equal(jstr_of(jget(&root, "theory")), "mixture");
  assert_int_equal(jget(&root, "not_covered")->n, 0);
  gran_scene *s = NULL;
  char path[1024];
  snprintf(path, sizeof path, "%s/scenes/fig2.toml", gran_test_source_dir());
  GRAN_ASSERT_OK(gran_scene_load(path, &s));
  int64_t ntimes = 0;
  double t_start = 0;
  GRAN_ASSERT_OK(gran_scene_sizes(s, NULL, &ntimes, NULL, &t_start, NULL));
  gran_scene_destroy(&s);
  assert_int_equal(jget(&root, "times")->n, (int)ntimes);
  jfree(&root);
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t646");
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_aggregation_driver), cmocka_unit_test(test_aggregation_outline),
      cmocka_unit_test(test_gsrd_haff),          cmocka_unit_test(test_gsrd_viscosity),
      cmocka_unit_test(test_no_theory),
  };
  return cmocka_run_group_tests(tests, NULL, teardown);
}
