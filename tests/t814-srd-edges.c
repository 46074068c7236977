/* t814-srd-edges.c - the GSRD engine at its numeric edges: every
 * input the C API or a scene accepts runs without a signal, and every value it derives stays finite.
 *  - class 1 (derived values, src/srd/srd_limits.h with the rule of src/core/derived.h): T0 = 1e32 ..
 *    1e60 in 3-D, a = 1e-300 / 5e-324, sigma = 1e300 with eps < 1, dt = 1e300, a vibrating wall of
 *    amplitude and omega 1e300, gravity, body force, shear rate and wall T of 1e300, a subnormal dt
 *    (5e-324), a dt of 2e-306 under a shear of 65536 (the collisional stress overflows; dt = 1e-290
 *    with shear 1e-5 runs with a finite stress) are refused by
 *    gran_srd_create naming the option, and by the scene parser naming FILE:LINE and the key; a
 *    checksum-consistent checkpoint with sigma = 1e300 is refused naming sigma;
 *  - class 1 (kernels): srd_wrap puts 1e300 b, -1e300 b, +-DBL_MAX, 2b - ulp and -tiny into [0, b);
 *    every bin index stays in the grid for NaN, +-inf and -2.3e279 coordinates (also y below 0);
 *  - class 1 (per-step check): a NaN or inf written through gran_srd_particles makes the next
 *    advance fail with GRAN_ERR_NUMERIC naming the particle and the array, on the CPU engine and on
 *    the host reference device; a velocity of 1e266 runs without a signal and observe refuses the
 *    overflowing energy (GRAN_ERR_NUMERIC), never a row of inf;
 *  - class 2: the Sonine a2 at T0 = 1e-200 and 1e200 (dt scaled so that the run is the T0 = 1 run
 *    in other units) equals the T0 = 1 value to 1e-12, at t = 0 and after 10 steps; the energy
 *    ledger's relative error of a gas created at T0 = 1e-280 and then set to |v| = 1e16 is finite;
 *  - class 3: float storage (precision = 1, device = reference) is refused for T0 = 1e-90 and 1e77,
 *    a shear of 1e20 and gravity over the run of a scene, the message naming the key and float; a
 *    velocity beyond float written into a float run is found by the device's per-step check and the
 *    copy back (GRAN_ERR_NUMERIC naming the particle);
 *  - class 11: a gas at T = 1e-310 runs (no NaN, temperature finite), observe warns that its squared
 *    velocities are subnormal, and the engine leaves the caller's floating-point mode (MXCSR) as it
 *    found it;
 *  - class 12: threads = 5000 is refused naming 'threads' (C API, scene); 4096 on this machine runs
 *    with a warning, bit for bit as 1 thread. */
#define _POSIX_C_SOURCE 200809L
#include "io_test_util.h" /* io_edit_raw: an edit through HDF5, checksum recomputed */

#include <float.h>
#include "srd/srd_kernels.h"

#if defined(__x86_64__) || defined(__SSE__)
#include <xmmintrin.h>
#define HAVE_MXCSR 1
#endif

static gran_srd_options base(int dim, int64_t L) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = dim;
  o.cells[0] = o.cells[1] = o.cells[2] = L;
  o.n0 = 10;
  o.seed = 814;
  o.threads = 1;
  return o;
}

/* gran_srd_create refuses o with GRAN_ERR_ARG and a message naming option `key` (and `also`) */
static void refused(const gran_srd_options *o, const char *key, const char *also) {
  gran_srd *s = NULL;
  char want[64];
  snprintf(want, sizeof want, "option '%s'", key);
  gran_clear_error();
  const int st = gran_srd_create(o, &s);
  if (st != GRAN_ERR_ARG || !strstr(gran_last_error_message(), want) || (also && !strstr(gran_last_error_message(), also)))
    fail_msg("expected GRAN_ERR_ARG naming %s%s%s, got %d: '%s'", want, also ? " and " : "", also ? also : "", st,
             gran_last_error_message());
  assert_null(s);
}

/* ---- class 1: derived values refused at create ------------------------------------------------ */
static void test_create_refusals(void **state) {
  (void)state;
  gran_srd_options o;
  for (double T = 1e32; T <= 1e60; T *= 10) { /* 3-D: segfaulted */
    o = base(3, 8);
    o.T0 = T;
    refused(&o, "T0", "box lengths");
  }
  o = base(3, 8);
  o.a = 1e-300;
  refused(&o, "a", NULL);
  o.a = 5e-324;
  refused(&o, "a", NULL);
  o = base(2, 8);
  o.a = 1e-200; /* 2-D: a^2 = 0 */
  refused(&o, "a", NULL);
  o = base(3, 8);
  o.sigma = 1e300;
  o.eps = 0.5;
  refused(&o, "sigma", NULL);
  o = base(3, 8);
  o.dt = 1e300;
  refused(&o, "dt", NULL);
  o = base(3, 8);
  o.wall_axis = 2;
  o.vib_amp = 1e300;
  o.vib_omega = 1e300;
  refused(&o, "vib_amp", NULL);
  o = base(3, 8);
  o.accel[2] = -1e300; /* gravity: inf energies before */
  refused(&o, "accel", NULL);
  o = base(3, 8);
  o.shear_rate = 1e300;
  refused(&o, "shear_rate", NULL);
  o = base(3, 8);
  o.wall_axis = 2;
  o.wall_T = 1e300;
  refused(&o, "wall_T", NULL);
  o = base(3, 8);
  o.T0 = 1e-300; /* squared speeds subnormal */
  refused(&o, "T0", "subnormal");
  o = base(3, 8);
  o.dt = 5e-324; /* a subnormal step: the stress divided by multiples of it overflowed to -inf */
  refused(&o, "dt", "subnormal");
  o = base(2, 8);
  o.dt = 1.9947e-306; /* a normal but tiny step with a strong shear: the collisional stress overflowed to inf */
  o.shear_rate = 65536;
  refused(&o, "dt", "stress");
  /* what stays allowed: a fast gas with a small step, a slow one, a strongly dissipative one */
  gran_srd *s = NULL;
  o = base(3, 8);
  o.T0 = 1e32;
  o.dt = 1e-16;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 3));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  o = base(3, 8);
  o.dt = 1e-290; /* a tiny step with a weak shear: within the stress bound, a finite stress */
  o.shear_rate = 1e-5;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 3));
  {
    gran_srd_obs ob;
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    assert_true(isfinite(ob.stress_xy) && isfinite(ob.stress_kin));
  }
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  o = base(3, 8);
  o.eps = 0.1;
  o.sigma = 3; /* eps_eff clamps to 0: allowed, with a warning */
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 3));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  assert_true(ob.clamped > 0 && isfinite(ob.temperature));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* ---- class 1: the same refusals from a scene, FILE:LINE and the key ---------------------------- */
typedef struct {
  const char *text;
  const char *where;
} bad_case;

static void test_scene_refusals(void **state) {
  (void)state;
  static const bad_case cases[] = {
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\nT0 = 1e32\n", "edge.toml:5: key 'engine.T0'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\na = 1e-300\n", "edge.toml:5: key 'engine.a'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\na = 5e-324\n", "edge.toml:5: key 'engine.a'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\neps = 0.5\nsigma = 1e300\n", "edge.toml:6: key 'engine.sigma'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\ndt = 1e300\n", "edge.toml:5: key 'engine.dt'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\n[boundaries]\nwalls = {axis = \"z\"}\n"
       "vibrating_wall = {amplitude = 1e300, omega = 1e300}\n",
       "edge.toml:7: key 'boundaries.vibrating_wall.amplitude'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\n[boundaries]\nwalls = {axis = \"z\", T = 1e300}\n",
       "edge.toml:6: key 'boundaries.walls.T'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\n[boundaries]\nlees_edwards = {shear_rate = 1e300}\n",
       "edge.toml:6: key 'boundaries.lees_edwards.shear_rate'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\n[forces]\ngravity = [0, 0, -1e300]\n",
       "edge.toml:6: key 'forces.gravity'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\n[forces]\nbody_force = [1e300, 0, 0]\n",
       "edge.toml:6: key 'forces.body_force'"},
      /* every velocity scale at once (thermal, walls, shear, wall speed, three of gravity and body
       * force): the last one is the refused one (the scale table holds them all) */
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\n[boundaries]\nwalls = {axis = \"z\", T = 1.0}\n"
       "vibrating_wall = {amplitude = 0.1, omega = 1.0}\nlees_edwards = {shear_rate = 0.01}\n[forces]\n"
       "gravity = [0, 0, -0.01]\nbody_force = [1e300, 0, 0]\n",
       "key 'forces.body_force'"},
      /* free fall along a periodic axis over the run: 1e7 steps of g = 1 end at 2.5e6 boxes per step */
      {"[engine]\ntype = \"srd\"\ncells = 4\nsteps = 10000000\n[observables]\nevery = 10000000\n[forces]\n"
       "body_force = [1, 0, 0]\n",
       "edge.toml:8: key 'forces.body_force'"},
      /* class 3: float storage */
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\ndevice = \"reference\"\nprecision = \"float\"\nT0 = 1e-90\n",
       "edge.toml:7: key 'engine.T0'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\ndevice = \"reference\"\nprecision = \"float\"\nT0 = 1e77\n",
       "edge.toml:7: key 'engine.T0'"},
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 100000\ndt = 1e-9\ndevice = \"reference\"\nprecision = \"float\"\n"
       "[observables]\nevery = 100000\n[forces]\ngravity = [1e20, 0, 0]\n",
       "edge.toml:11: key 'forces.gravity'"},
      /* class 12 */
      {"[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\nthreads = 5000\n", "edge.toml:5: key 'engine.threads'"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    gran_scene *s = NULL;
    const int st = gran_scene_parse(cases[i].text, "edge.toml", &s);
    if (st != GRAN_ERR_PARSE || !strstr(gran_last_error_message(), cases[i].where))
      fail_msg("case %zu: status %d, message '%s', expected '%s'", i, st, gran_last_error_message(), cases[i].where);
    if (strstr(cases[i].text, "float") && !strstr(gran_last_error_message(), "float"))
      fail_msg("case %zu: the message does not say float: '%s'", i, gran_last_error_message());
    assert_null(s);
  }
  gran_scene *s = NULL; /* the same fast gas with a small step parses */
  GRAN_ASSERT_OK(gran_scene_parse("[engine]\ntype = \"srd\"\ncells = 8\nsteps = 5\nT0 = 1e32\ndt = 1e-16\n", "ok.toml", &s));
  GRAN_ASSERT_OK(gran_scene_destroy(&s));
}

/* ---- class 1: checkpoints that are checksum-consistent but hold an overflowing value --------- */
static void test_checkpoint_values(void **state) {
  (void)state;
  char path[256], bad[300];
  snprintf(path, sizeof path, "/tmp/granary-t814-%ld.ckp", (long)getpid());
  snprintf(bad, sizeof bad, "%s.bad", path);
  remove(path);
  gran_srd_options o = base(3, 6);
  o.eps = 0.9;
  o.sigma = 0.2;
  gran_srd *s = NULL, *t = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 2));
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(s, path, "/srd"));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  /* sigma in the stored options: a file error naming the option */
  const double big = 1e300;
  io_edit_raw(path, bad, "/srd/options/sigma", 0, &big, 1, H5T_NATIVE_DOUBLE);
  GRAN_ASSERT_ERR(gran_srd_checkpoint_read(bad, "/srd", &t), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "'sigma'"));
  assert_null(t);
  unlink(path);
  unlink(bad);
}

/* ---- class 1: the kernels --------------------------------------------------------------------- */
static void test_kernels(void **state) {
  (void)state;
  srd_geom g;
  memset(&g, 0, sizeof g);
  g.dim = 3;
  g.wall_axis = -1;
  g.a = 1.0;
  g.inv_a = 1.0;
  for (int k = 0; k < 3; ++k) g.L[k] = g.nc[k] = 16, g.box[k] = 16.0;
  const double b = 16.0;
  const double xs[] = {1e300 * b, -1e300 * b, DBL_MAX, -DBL_MAX, 2 * b - 2 * DBL_EPSILON * b, -1e-300, -b, 3 * b,
                       9007199254740993.0 * b, -9007199254740993.0 * b, 1e17, -2.3e279};
  for (size_t i = 0; i < sizeof xs / sizeof xs[0]; ++i) {
    double p[3] = {xs[i], xs[i], xs[i]}, v[3] = {1, 2, 3};
    srd_wrap(&g, p, v);
    for (int k = 0; k < 3; ++k)
      if (!(p[k] >= 0.0 && p[k] < b)) fail_msg("srd_wrap(%g) = %.17g outside [0, %g)", xs[i], p[k], b);
  }
  /* Lees-Edwards: crossing m images shifts x by m le_dx (mod Lx) and vx by m le_dv */
  g.le_on = 1;
  g.le_dx = 3.0;
  g.le_dv = 0.5;
  {
    double p[3] = {1.0, 5 * b + 2.0, 1.0}, v[3] = {0, 0, 0};
    srd_wrap(&g, p, v);
    assert_true(p[1] == 2.0 && v[0] == -2.5 && p[0] == fmod(1.0 - 15.0 + 2 * b, b));
  }
  g.le_on = 0;
  /* bins: every index inside the grid whatever the coordinate */
  const double bad[] = {NAN, INFINITY, -INFINITY, -2.3e279, 2.3e279, -1e-9, -5.0, 1e19};
  const double zero[3] = {0, 0, 0};
  for (int w = -1; w < 3; ++w) {
    g.wall_axis = w;
    for (int k = 0; k < 3; ++k) g.nc[k] = g.L[k] + (k == w ? 1 : 0);
    const int64_t ncell = g.nc[0] * g.nc[1] * g.nc[2];
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i)
      for (int k = 0; k < 3; ++k) {
        double p[3] = {1.5, 2.5, 3.5}, dvx;
        p[k] = bad[i];
        const int64_t c = srd_bin(&g, zero, p, &dvx);
        if (c < 0 || c >= ncell) fail_msg("srd_bin: coordinate %d = %g (walls %d) gives cell %lld of %lld", k, bad[i], w,
                                          (long long)c, (long long)ncell);
        const int64_t l = srd_bin_layer(&g, zero, p);
        assert_true(l >= 0 && l < g.nc[2]);
      }
  }
  /* 2-D: y below 0 had no lower clamp */
  g.dim = 2;
  g.wall_axis = -1;
  g.nc[2] = g.L[2] = 1;
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
    const double p[3] = {1.0, bad[i], 0.0};
    int wrapped;
    const int64_t cy = srd_bin_y(&g, zero, p, &wrapped);
    assert_true(cy >= 0 && cy < g.L[1]);
  }
  /* eps_eff of inf x 0 is clamped, never NaN */
  int cl;
  const double e = srd_eps_eff(INFINITY, 1.0, 0.0, &cl);
  assert_true(e == 0.0 && cl == 1);
}

/* ---- class 1: non-finite particles ------------------------------------------------------------ */
static void numeric_case(int device, int which, double value, int64_t idx) {
  gran_srd_options o = base(3, 6);
  o.device = device;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 2));
  int64_t n;
  double *a[6];
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &a[0], &a[1], &a[2], &a[3], &a[4], &a[5]));
  a[which][idx] = value;
  GRAN_ASSERT_ERR(gran_srd_advance(s, 3), GRAN_ERR_NUMERIC);
  static const char *const names[6] = {"x", "y", "z", "vx", "vy", "vz"};
  char want[64];
  snprintf(want, sizeof want, "particle %lld has a non-finite %s", (long long)idx, names[which]);
  if (!strstr(gran_last_error_message(), want))
    fail_msg("device %d: expected '%s' in '%s'", device, want, gran_last_error_message());
  GRAN_ASSERT_ERR(gran_srd_advance(s, 1), GRAN_ERR_NUMERIC); /* it stays refused */
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void test_nonfinite_particles(void **state) {
  (void)state;
  numeric_case(GRAN_SRD_DEVICE_CPU, 3, NAN, 17);
  numeric_case(GRAN_SRD_DEVICE_CPU, 1, INFINITY, 5);
  numeric_case(GRAN_SRD_DEVICE_CPU, 5, -INFINITY, 2159);
  numeric_case(GRAN_SRD_DEVICE_REFERENCE, 4, NAN, 100);
  numeric_case(GRAN_SRD_DEVICE_REFERENCE, 0, NAN, 3);
  /* observe of a NaN written after the last step: GRAN_ERR_NUMERIC, not a NaN row */
  gran_srd_options o = base(2, 12);
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  vy[9] = NAN;
  gran_srd_obs ob;
  GRAN_ASSERT_ERR(gran_srd_observe(s, &ob), GRAN_ERR_NUMERIC);
  assert_non_null(strstr(gran_last_error_message(), "particle 9 has a non-finite vy"));
  vy[9] = 0.0;
  /* a finite but overflowing velocity (a checkpoint with 1e266 did segfault): the steps run, the
   * energy overflows, observe refuses it */
  vx[3] = 1e266;
  GRAN_ASSERT_OK(gran_srd_advance(s, 5));
  GRAN_ASSERT_ERR(gran_srd_observe(s, &ob), GRAN_ERR_NUMERIC);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* ---- class 2: a2 at extreme temperatures ------------------------------------------------------ */
static void a2_run(double T0, double dt, int64_t steps, double a2[2], double *T) {
  gran_srd_options o = base(3, 8);
  o.T0 = T0;
  o.dt = dt;
  o.eps = 0.9;
  o.sigma = 0.1 / sqrt(dt * sqrt(T0)); /* the same kappa = (1 - eps^2) sigma^2 rho sqrt(T) dt */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  a2[0] = ob.a2;
  GRAN_ASSERT_OK(gran_srd_advance(s, steps));
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  a2[1] = ob.a2;
  *T = ob.temperature / T0;
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void test_a2_scaled(void **state) {
  (void)state;
  double r[2], lo[2], hi[2], Tr, Tl, Th;
  a2_run(1.0, 0.5, 10, r, &Tr);
  a2_run(1e-200, 0.5e100, 10, lo, &Tl);
  a2_run(1e200, 0.5e-100, 10, hi, &Th);
  printf("a2: T0 = 1: %.15g %.15g; 1e-200: %.15g %.15g; 1e200: %.15g %.15g\n", r[0], r[1], lo[0], lo[1], hi[0], hi[1]);
  for (int k = 0; k < 2; ++k) {
    assert_true(isfinite(r[k]));
    GRAN_ASSERT_ABS(lo[k], r[k], 1e-12);
    GRAN_ASSERT_ABS(hi[k], r[k], 1e-12);
  }
  GRAN_ASSERT_REL(Tl, Tr, 1e-12);
  GRAN_ASSERT_REL(Th, Tr, 1e-12);
}

/* class 2, the energy ledger: a gas created almost at rest (T0 = 1e-280: e_initial ~ 1e-277) whose
 * velocities are then set to 1e16 through gran_srd_particles. The ledger error relative to
 * e_initial alone overflowed to -inf (a resumed checkpoint with a tiny e_initial did the same); it
 * is relative to at least DBL_EPSILON x the largest energy exchanged: finite, and of the size the
 * ledger's miss (-E) gives, -1 / DBL_EPSILON. A gas created at rest with nothing exchanged: 0. */
static void test_ledger_finite(void **state) {
  (void)state;
  gran_srd_options o = base(3, 4);
  o.T0 = 1e-280; /* the lowest T0 gran_srd_create accepts */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  assert_true(isfinite(ob.ledger_error) && fabs(ob.ledger_error) < 1e-12);
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  for (int64_t i = 0; i < n; ++i) vx[i] = (i % 2 ? 1e16 : -1e16);
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  printf("ledger error after setting v = 1e16 at e_initial = %g: %g\n", ob.e_initial, ob.ledger_error);
  assert_true(isfinite(ob.ledger_error));
  GRAN_ASSERT_REL(ob.ledger_error, -1.0 / DBL_EPSILON, 1e-9);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* ---- class 3: float storage ------------------------------------------------------------------- */
static void test_float_storage(void **state) {
  (void)state;
  gran_srd_options o = base(3, 8);
  o.device = GRAN_SRD_DEVICE_REFERENCE;
  o.precision = 1;
  o.T0 = 1e-90; /* T off by 18 % at t = 0 before */
  refused(&o, "T0", "float");
  o.T0 = 1e77; /* NaN everywhere before */
  refused(&o, "T0", "float");
  o.T0 = 1;
  o.shear_rate = 1e20;
  refused(&o, "shear_rate", "float");
  o.shear_rate = 0;
  o.a = 1e-35;
  o.dt = 1e-36;
  refused(&o, "a", "float");
  o.a = 1;
  o.dt = 1;
  /* an ordinary float run is accepted; a velocity beyond float written into it is found by the
   * device's per-step check and the copy back */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 2));
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  vz[42] = 1e39; /* finite in double, inf in float */
  GRAN_ASSERT_ERR(gran_srd_advance(s, 2), GRAN_ERR_NUMERIC);
  assert_non_null(strstr(gran_last_error_message(), "non-finite"));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  /* the device parameters are checked once, for the GPU and the reference alike */
  o.precision = 0;
  o.T0 = 1e-90;
  o.dt = 1e40;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s)); /* double storage: fine */
  GRAN_ASSERT_OK(gran_srd_advance(s, 1));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* ---- class 11: subnormal squares -------------------------------------------------------------- */
static void test_subnormal(void **state) {
  (void)state;
  gran_srd_options o = base(3, 8);
  o.eps = 0.9;
  o.sigma = 0.1;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  int64_t n;
  double *x, *y, *z, *v[3];
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &v[0], &v[1], &v[2]));
  for (int k = 0; k < 3; ++k)
    for (int64_t i = 0; i < n; ++i) v[k][i] *= 1e-155; /* T = 1e-310: squares below DBL_MIN */
#ifdef HAVE_MXCSR
  const unsigned before = _mm_getcsr();
#endif
  GRAN_ASSERT_OK(gran_srd_advance(s, 20));
#ifdef HAVE_MXCSR
  assert_int_equal(_mm_getcsr(), before); /* flush-to-zero stays inside the engine's loops */
#endif
  volatile double tiny = 1e-310;
  assert_true(tiny * 0.5 > 0.0); /* the caller's subnormals still work */
  int64_t w0, w1;
  GRAN_ASSERT_OK(gran_warning_count(&w0));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  GRAN_ASSERT_OK(gran_warning_count(&w1));
  assert_true(isfinite(ob.temperature) && ob.temperature > 0 && ob.temperature < 1e-300);
  assert_true(isfinite(ob.a2) && isfinite(ob.energy));
  assert_true(w1 > w0);
  char msg[512];
  GRAN_ASSERT_OK(gran_last_warning_copy(msg, sizeof msg));
  assert_non_null(strstr(msg, "subnormal"));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* ---- class 12: threads ------------------------------------------------------------------------ */
static void test_threads(void **state) {
  (void)state;
  gran_srd_options o = base(3, 6);
  o.threads = 5000;
  refused(&o, "threads", NULL);
  o.threads = -1;
  refused(&o, "threads", NULL);
  double *a[2];
  int64_t n[2];
  for (int r = 0; r < 2; ++r) {
    o.threads = r == 0 ? 1 : 4096; /* more than 4 per processor: reduced, with a warning */
    int64_t w0, w1;
    GRAN_ASSERT_OK(gran_warning_count(&w0));
    gran_srd *s = NULL;
    GRAN_ASSERT_OK(gran_srd_create(&o, &s));
    GRAN_ASSERT_OK(gran_warning_count(&w1));
    if (r == 1) {
      char msg[512];
      assert_true(w1 > w0);
      GRAN_ASSERT_OK(gran_last_warning_copy(msg, sizeof msg));
      assert_non_null(strstr(msg, "threads"));
    }
    GRAN_ASSERT_OK(gran_srd_advance(s, 12));
    double *p[6];
    GRAN_ASSERT_OK(gran_srd_particles(s, &n[r], &p[0], &p[1], &p[2], &p[3], &p[4], &p[5]));
    a[r] = malloc(sizeof(double) * 6 * (size_t)n[r]);
    for (int k = 0; k < 6; ++k) memcpy(a[r] + k * n[r], p[k], sizeof(double) * (size_t)n[r]);
    GRAN_ASSERT_OK(gran_srd_destroy(&s));
  }
  assert_int_equal(n[0], n[1]);
  assert_memory_equal(a[0], a[1], sizeof(double) * 6 * (size_t)n[0]);
  free(a[0]);
  free(a[1]);
}

/* gran_srd_advance: a call of more steps than the run-length bound (1e12 steps, 1e14 updates) is
 * refused before any step, naming the argument and giving the estimate; the state is unchanged */
static void test_advance_bound(void **state) {
  (void)state;
  gran_srd_options o = base(3, 6);
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_ERR(gran_srd_advance(s, (int64_t)1e13), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "argument 'steps'"));
  assert_non_null(strstr(gran_last_error_message(), "days"));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  assert_int_equal(ob.steps, 0);
  GRAN_ASSERT_OK(gran_srd_advance(s, 2));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  /* one particle: its momentum removed, the gas has no energy; the ledger error is 0, not 0/0 */
  o = base(3, 1);
  o.cells[1] = 6;
  o.cells[2] = 4;
  o.n0 = 1.0 / 24.0;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 3));
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  assert_int_equal(ob.n, 1);
  assert_true(ob.ledger_error == 0.0);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_create_refusals),   cmocka_unit_test(test_scene_refusals),
      cmocka_unit_test(test_checkpoint_values), cmocka_unit_test(test_kernels),
      cmocka_unit_test(test_nonfinite_particles), cmocka_unit_test(test_a2_scaled),
      cmocka_unit_test(test_float_storage),     cmocka_unit_test(test_subnormal),
      cmocka_unit_test(test_threads),           cmocka_unit_test(test_advance_bound),
      cmocka_unit_test(test_ledger_finite),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
