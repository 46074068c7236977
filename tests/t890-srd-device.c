/* t890-srd-device.c - GSRD devices without a GPU: the device selection ("cpu" / "cuda" / "auto" /
 * "reference", options.device, gran_srd_set_device) and its errors, and the device test bodies of
 * tests/srd_device_body.h on the host reference of the device algorithm, against the CPU engine:
 * same shared functions, same streams, sums in particle order, so every effect (walls with virtual
 * particles, thermostat, gravity, Lees-Edwards stress, clamps) agrees to rounding. The engine hooks
 * (src/srd/device_cuda.cpp) are the ones a GPU run takes; tests/gpu/t850-srd-gpu.c runs the same
 * bodies on the GPU. */
#include "io_test_util.h" /* io_edit_raw: an edit through HDF5, checksum recomputed */

#include "srd_device_body.h"
#include "srd/device_cuda.h"

static int have_gpu(void) {
  int ndev = 0, compiled = 0;
  GRAN_ASSERT_OK(gran_cuda_compiled(&compiled));
  GRAN_ASSERT_OK(gran_cuda_device_count(&ndev));
  return compiled && ndev > 0;
}

static void test_device_resolve(void **state) {
  (void)state;
  int use = -1;
  const int gpu = have_gpu();
  GRAN_ASSERT_OK(gran_srd_device_resolve("cpu", &use));
  assert_int_equal(use, 0);
  GRAN_ASSERT_OK(gran_srd_device_resolve("reference", &use));
  assert_int_equal(use, 0);
  GRAN_ASSERT_ERR(gran_srd_device_resolve("gpu", &use), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "\"gpu\""));
  GRAN_ASSERT_ERR(gran_srd_device_resolve(NULL, &use), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_device_resolve("cpu", NULL), GRAN_ERR_ARG);
  int32_t d = -1;
  GRAN_ASSERT_OK(gran_srd_device_parse("auto", &d));
  assert_int_equal(d, GRAN_SRD_DEVICE_AUTO);
  GRAN_ASSERT_OK(gran_srd_device_parse("reference", &d));
  assert_int_equal(d, GRAN_SRD_DEVICE_REFERENCE);
  GRAN_ASSERT_ERR(gran_srd_device_parse("CUDA", &d), GRAN_ERR_ARG);
  int64_t w0 = 0, w1 = 0;
  GRAN_ASSERT_OK(gran_warning_count(&w0));
  GRAN_ASSERT_OK(gran_srd_device_resolve("auto", &use));
  GRAN_ASSERT_OK(gran_warning_count(&w1));
  assert_int_equal(use, gpu);
  assert_int_equal(w1 - w0, gpu ? 0 : 1); /* the CPU fallback is announced */
  if (gpu) {
    GRAN_ASSERT_OK(gran_srd_device_resolve("cuda", &use));
    assert_int_equal(use, 1);
  } else {
    GRAN_ASSERT_ERR(gran_srd_device_resolve("cuda", &use), GRAN_ERR_UNSUPPORTED);
    /* the launchers say the same */
    gran_cuda_srd_params p;
    memset(&p, 0, sizeof p);
    gran_cuda_srd *h = (gran_cuda_srd *)&p;
    const double *xs[3] = {NULL, NULL, NULL};
    gran_rng r;
    GRAN_ASSERT_OK(gran_rng_seed(&r, 1));
    int rc = gran_cuda_srd_create(&p, xs, xs, &r, &h);
    assert_true(rc == GRAN_ERR_UNSUPPORTED || rc == GRAN_ERR_ARG); /* stub, or bad params checked first */
    assert_null(h);
  }
}

/* options.device through gran_srd_create, gran_srd_set_device / get_device: errors name what was
 * wrong, a failed move leaves the run where it was, "auto" without a GPU is the CPU engine bit for
 * bit. */
static void test_engine_device_errors(void **state) {
  (void)state;
  const int gpu = have_gpu();
  gran_srd_options o;
  sde_options(SDE_PERIODIC, &o);
  gran_srd *s = NULL;
  o.device = 7;
  GRAN_ASSERT_ERR(gran_srd_create(&o, &s), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "device"));
  assert_null(s);
  o.device = GRAN_SRD_DEVICE_REFERENCE;
  o.precision = 2;
  GRAN_ASSERT_ERR(gran_srd_create(&o, &s), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "precision"));
  o.precision = 0;
  if (!gpu) {
    o.device = GRAN_SRD_DEVICE_CUDA;
    GRAN_ASSERT_ERR(gran_srd_create(&o, &s), GRAN_ERR_UNSUPPORTED);
    const char *m = gran_last_error_message();
    assert_true(strstr(m, "not compiled") != NULL || strstr(m, "no CUDA device") != NULL);
    assert_null(s);
    /* auto: the CPU engine, with a warning, the same numbers as device = cpu */
    int64_t w0, w1;
    GRAN_ASSERT_OK(gran_warning_count(&w0));
    o.device = GRAN_SRD_DEVICE_AUTO;
    gran_srd *c = NULL;
    GRAN_ASSERT_OK(gran_srd_create(&o, &s));
    GRAN_ASSERT_OK(gran_warning_count(&w1));
    assert_int_equal(w1 - w0, 1);
    int32_t d = -1;
    GRAN_ASSERT_OK(gran_srd_get_device(s, &d));
    assert_int_equal(d, GRAN_SRD_DEVICE_CPU);
    o.device = GRAN_SRD_DEVICE_CPU;
    GRAN_ASSERT_OK(gran_srd_create(&o, &c));
    GRAN_ASSERT_OK(gran_srd_advance(s, 3));
    GRAN_ASSERT_OK(gran_srd_advance(c, 3));
    assert_true(sde_particles_diff(s, c, 3) == 0.0);
    /* a move to cuda fails and leaves the run on the CPU, intact */
    GRAN_ASSERT_ERR(gran_srd_set_device(s, GRAN_SRD_DEVICE_CUDA), GRAN_ERR_UNSUPPORTED);
    GRAN_ASSERT_OK(gran_srd_get_device(s, &d));
    assert_int_equal(d, GRAN_SRD_DEVICE_CPU);
    GRAN_ASSERT_OK(gran_srd_advance(s, 2));
    GRAN_ASSERT_OK(gran_srd_advance(c, 2));
    assert_true(sde_particles_diff(s, c, 3) == 0.0);
    GRAN_ASSERT_OK(gran_srd_destroy(&c));
  } else {
    o.device = GRAN_SRD_DEVICE_CPU;
    GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  }
  GRAN_ASSERT_ERR(gran_srd_set_device(s, -1), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_set_device(NULL, 0), GRAN_ERR_ARG);
  int32_t d;
  GRAN_ASSERT_ERR(gran_srd_get_device(s, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_get_device(NULL, &d), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* A checkpoint whose options name "cuda" is still readable without a GPU: the CPU, with a warning. */
static void test_checkpoint_cuda_without_gpu(void **state) {
  (void)state;
  if (have_gpu()) skip();
  gran_srd_options o;
  sde_options(SDE_PERIODIC, &o);
  gran_srd *s = NULL, *r = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 4));
  const char *path = "t890-cuda-ckpt.bin";
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(s, path, "/srd"));
  /* options.device in the file: CUDA */
  const int32_t cuda = GRAN_SRD_DEVICE_CUDA;
  io_edit_raw(path, path, "/srd/options/device", 0, &cuda, 1, H5T_NATIVE_INT32);
  int64_t w0, w1;
  GRAN_ASSERT_OK(gran_warning_count(&w0));
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(path, "/srd", &r));
  GRAN_ASSERT_OK(gran_warning_count(&w1));
  assert_int_equal(w1 - w0, 1);
  int32_t d = -1;
  GRAN_ASSERT_OK(gran_srd_get_device(r, &d));
  assert_int_equal(d, GRAN_SRD_DEVICE_CPU);
  GRAN_ASSERT_OK(gran_srd_advance(s, 5));
  GRAN_ASSERT_OK(gran_srd_advance(r, 5));
  assert_true(sde_particles_diff(s, r, 3) == 0.0); /* the resume is bit for bit */
  remove(path);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  GRAN_ASSERT_OK(gran_srd_destroy(&r));
}

/* launcher level on the reference: conservation, double and float storage */
static void test_conservation_reference(void **state) {
  (void)state;
  const int R = GRAN_SRD_DEVICE_REFERENCE;
  sdb_body_conservation(R, 3, 0, 1.0);
  sdb_body_conservation(R, 2, 0, 1.0);
  sdb_body_conservation(R, 3, 0, 0.9);
  sdb_body_conservation(R, 3, 1, 1.0);
  sdb_body_conservation(R, 2, 1, 0.9);
  sdb_body_cell_invariants(R, 3, 1.0);
  sdb_body_cell_invariants(R, 2, 1.0);
  sdb_body_cell_invariants(R, 3, 0.8);
}

/* engine level: every scene, CPU engine versus the reference (to rounding: 1e-9 absolute on the
 * particles, v ~ 1; 1e-9 relative on the observables) */
static void test_engine_vs_reference(void **state) {
  (void)state;
  for (int sc = 0; sc < SDE_NSCENES; ++sc)
    sde_body_devices(sc, GRAN_SRD_DEVICE_CPU, GRAN_SRD_DEVICE_REFERENCE, 1e-9, 1e-9);
}

/* velocities changed through gran_srd_particles reach the device at the next advance */
static void test_particles_write_through(void **state) {
  (void)state;
  gran_srd_options o;
  sde_options(SDE_THERMO, &o);
  gran_srd *c = NULL, *r = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &c));
  o.device = GRAN_SRD_DEVICE_REFERENCE;
  GRAN_ASSERT_OK(gran_srd_create(&o, &r));
  GRAN_ASSERT_OK(gran_srd_advance(c, 3));
  GRAN_ASSERT_OK(gran_srd_advance(r, 3));
  gran_srd *both[2] = {c, r};
  for (int q = 0; q < 2; ++q) {
    int64_t n;
    double *x, *y, *z, *vx, *vy, *vz;
    GRAN_ASSERT_OK(gran_srd_particles(both[q], &n, &x, &y, &z, &vx, &vy, &vz));
    for (int64_t i = 0; i < n; ++i) vx[i] += 0.5 * sin(2.0 * 3.14159265358979323846 * y[i] / 8.0); /* a shear wave */
  }
  GRAN_ASSERT_OK(gran_srd_advance(c, 6));
  GRAN_ASSERT_OK(gran_srd_advance(r, 6));
  const double d = sde_particles_diff(c, r, 3);
  if (!(d <= 1e-9)) fail_msg("after writing velocities: CPU and reference differ by %g", d);
  gran_srd_obs oc, orr;
  GRAN_ASSERT_OK(gran_srd_observe(c, &oc));
  GRAN_ASSERT_OK(gran_srd_observe(r, &orr));
  assert_true(oc.e_kin > 1e-3); /* the wave is there (and the same) */
  sde_compare_obs("write-through", &oc, &orr, 1e-9);
  GRAN_ASSERT_OK(gran_srd_destroy(&c));
  GRAN_ASSERT_OK(gran_srd_destroy(&r));
}

/* the physics bodies on the reference (small sizes: they are what t850 runs on the GPU, larger);
 * Haff's law also on the CPU engine itself (2-D 24^2, 12^2 under sanitizers) */
static void test_physics_reference(void **state) {
  (void)state;
  const int R = GRAN_SRD_DEVICE_REFERENCE;
#if defined(__SANITIZE_ADDRESS__)
  sde_body_haff(GRAN_SRD_DEVICE_CPU, 0, 12);
#else
  sde_body_haff(GRAN_SRD_DEVICE_CPU, 0, 24);
#endif
  sde_body_haff(R, 0, 24);
  sde_body_haff(R, 1, 24);
  sde_body_viscosity(R, 0, 2, 16, 130, 8, 100);
  sde_body_viscosity(R, 1, 3, 8, 130, 8, 50);
  sde_body_cold_flow(R, 0);
  sde_body_cold_flow(R, 1);
  sde_body_sk_ideal(R, 0, 3, 8, 12);
  sde_body_sk_ideal(R, 1, 2, 32, 12);
}

/* the global thermostat (thermostat = 2) on the reference device: under shear heating it holds the
 * temperature at T0 (within 5 % over 200 steps, removing the shear work: e_collisions < 0) where
 * the same run without it warms by more than 8 %; the CPU engine gives the same numbers (1e-9) */
static void test_global_thermostat_reference(void **state) {
  (void)state;
  double T[2];
  for (int th = 0; th < 2; ++th) {
    gran_srd_options o;
    sde_options(SDE_GTHERMO, &o);
    o.thermostat = th ? 2 : 0;
    gran_srd *c = NULL, *r = NULL;
    GRAN_ASSERT_OK(gran_srd_create(&o, &c));
    o.device = GRAN_SRD_DEVICE_REFERENCE;
    GRAN_ASSERT_OK(gran_srd_create(&o, &r));
    GRAN_ASSERT_OK(gran_srd_advance(c, 200));
    GRAN_ASSERT_OK(gran_srd_advance(r, 200));
    gran_srd_obs oc, orr;
    GRAN_ASSERT_OK(gran_srd_observe(c, &oc));
    GRAN_ASSERT_OK(gran_srd_observe(r, &orr));
    sde_compare_obs(th ? "global thermostat" : "no thermostat", &oc, &orr, 1e-9);
    T[th] = orr.temperature / o.T0;
    printf("  shear rate %g, %s: T / T0 = %.4f after 200 steps, e_collisions %.4g\n", o.shear_rate,
           th ? "global thermostat" : "no thermostat", T[th], orr.e_collisions);
    if (th && !(orr.e_collisions < 0.0)) fail_msg("the global thermostat removed no energy (%g)", orr.e_collisions);
    GRAN_ASSERT_OK(gran_srd_destroy(&c));
    GRAN_ASSERT_OK(gran_srd_destroy(&r));
  }
  if (!(T[0] > 1.08)) fail_msg("the shear did not heat the run without thermostat (T / T0 = %g)", T[0]);
  if (!(fabs(T[1] - 1.0) < 0.05)) fail_msg("the global thermostat did not hold T0 (T / T0 = %g)", T[1]);
}

/* the launchers' one parameter check (gran_srd_dev_check_params, the GPU's too) names what is wrong */
static void test_launcher_params(void **state) {
  (void)state;
  const gran_srd_launchers *L = gran_srd_launchers_get(GRAN_SRD_DEVICE_REFERENCE);
  assert_non_null(L);
  double x0[8] = {0}, *xs[3] = {x0, x0, x0};
  gran_rng r[1];
  GRAN_ASSERT_OK(gran_rng_seed(r, 1));
  gran_cuda_srd_params p;
  memset(&p, 0, sizeof p);
  p.geom.dim = 3;
  p.geom.wall_axis = -1;
  p.geom.a = p.geom.inv_a = 1.0;
  for (int k = 0; k < 3; ++k) {
    p.geom.L[k] = p.geom.nc[k] = 1;
    p.geom.box[k] = 1.0;
  }
  p.n = 8;
  p.dt = 0.1;
  p.alpha = 1.0;
  p.T0 = 1.0;
  gran_cuda_srd *h = NULL;
  GRAN_ASSERT_OK(L->create(&p, (const double *const *)xs, (const double *const *)xs, r, &h));
  GRAN_ASSERT_OK(L->destroy(&h));
  const struct {
    int32_t fx;
    double T0, shear;
    const char *word;
  } bad[] = {{SRD_FX_ALL + 1, 1.0, 0.0, "fx"},
             {SRD_FX_THERMO | SRD_FX_GTHERMO, 1.0, 0.0, "exclude"},
             {SRD_FX_GTHERMO, 0.0, 0.0, "T0"},
             {SRD_FX_LE, 1.0, 0.0, "shear_rate"}};
  for (size_t q = 0; q < sizeof bad / sizeof bad[0]; ++q) {
    gran_cuda_srd_params b = p;
    b.fx = bad[q].fx;
    b.T0 = bad[q].T0;
    b.shear_rate = bad[q].shear;
    GRAN_ASSERT_ERR(L->create(&b, (const double *const *)xs, (const double *const *)xs, r, &h), GRAN_ERR_ARG);
    assert_null(h);
    if (!strstr(gran_last_error_message(), bad[q].word))
      fail_msg("case %zu: '%s' does not name '%s'", q, gran_last_error_message(), bad[q].word);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_device_resolve),
      cmocka_unit_test(test_engine_device_errors),
      cmocka_unit_test(test_checkpoint_cuda_without_gpu),
      cmocka_unit_test(test_conservation_reference),
      cmocka_unit_test(test_engine_vs_reference),
      cmocka_unit_test(test_particles_write_through),
      cmocka_unit_test(test_physics_reference),
      cmocka_unit_test(test_global_thermostat_reference),
      cmocka_unit_test(test_launcher_params),
  };
  return cmocka_run_group_tests_name("t890-srd-device", tests, NULL, NULL);
}
