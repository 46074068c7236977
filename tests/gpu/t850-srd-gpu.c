/* t850-srd-gpu.c - the GSRD test bodies of tests/srd_device_body.h on the GPU (make test-gpu):
 *  - launcher level: conservation (double and float storage), the GPU against the host reference
 *    for one scene and seed (same shift, same per-cell streams, same rules of
 *    src/srd/rules.h; only the order of the atomic cell-sum additions differs, so in
 *    double the particles agree to ~1e-13 after 20 steps (tolerance 1e-9, v ~ 1) and the per-cell
 *    RNG states bit for bit; float storage: the temperature within 4 standard errors), sort keeps the
 *    state, bad input;
 *  - engine level: every scene (periodic, clamps, thermostat, no-slip walls + gravity + vibrating
 *    wall, slip walls, Lees-Edwards + dissipation, Lees-Edwards + body force, global thermostat)
 *    with device = cuda against device = cpu: every particle, the ledger, the stress, the clamps,
 *    S(k) (cuFFT against FFTW), checkpoints moved CPU -> GPU and GPU -> CPU; float storage against
 *    the CPU engine within the statistical noise of each quantity. Without a GPU: says so and passes (skip). */
#include "srd_device_body.h"

static int have_gpu(void) {
  int ndev = 0, compiled = 0;
  GRAN_ASSERT_OK(gran_cuda_compiled(&compiled));
  GRAN_ASSERT_OK(gran_cuda_device_count(&ndev));
  return compiled && ndev > 0;
}

static const int G = GRAN_SRD_DEVICE_CUDA, R = GRAN_SRD_DEVICE_REFERENCE;

static void test_conservation_gpu(void **state) {
  (void)state;
  sdb_body_conservation(G, 3, 0, 1.0);
  sdb_body_conservation(G, 2, 0, 1.0);
  sdb_body_conservation(G, 3, 0, 0.9);
  sdb_body_conservation(G, 3, 1, 1.0); /* float storage */
  sdb_body_conservation(G, 2, 1, 1.0);
  sdb_body_cell_invariants(G, 3, 1.0);
  sdb_body_cell_invariants(G, 2, 1.0);
  sdb_body_cell_invariants(G, 3, 0.8);
}

static double temperature(const sdb_state *st) {
  double m[3], e;
  sdb_totals(st, m, &e);
  const double n = (double)st->p.n, d = st->p.geom.dim;
  double e_flow = 0.0;
  for (int k = 0; k < d; ++k) e_flow += 0.5 * m[k] * m[k] / n;
  return 2.0 * (e - e_flow) / (d * n);
}

/* agg = 1: warp-aggregated cell sums (gran_cuda_srd_set_sums), particles sorted every 5 steps on
 * both sides (the same stable order), so that warps hold few cells and the aggregated path runs */
static void compare(int dim, double eps, int precision, int agg) {
  sdb_state c, g;
  sdb_init(&c, R, dim, dim == 3 ? 8 : 16, 10, 130.0, eps, precision, 77);
  sdb_init(&g, G, dim, dim == 3 ? 8 : 16, 10, 130.0, eps, precision, 77);
  if (agg) {
    GRAN_ASSERT_OK(gran_cuda_srd_set_sums(g.dev, 1));
    for (int r = 0; r < 4; ++r) {
      GRAN_ASSERT_OK(c.L->sort(c.dev));
      GRAN_ASSERT_OK(g.L->sort(g.dev));
      sdb_run(&c, 5);
      sdb_run(&g, 5);
    }
  } else {
    sdb_run(&c, 20);
    sdb_run(&g, 20);
  }
  const double tc = temperature(&c), tg = temperature(&g);
  if (precision == 0) {
    double dmax = 0.0;
    for (int64_t i = 0; i < c.p.n; ++i)
      for (int k = 0; k < dim; ++k) {
        const double dv = fabs(c.v[k][i] - g.v[k][i]), dx = fabs(c.x[k][i] - g.x[k][i]);
        if (!(dv <= dmax)) dmax = dv;
        if (!(dx <= dmax)) dmax = dx;
      }
    printf("  launchers dim %d eps %g%s: GPU - reference largest difference %.2g after 20 steps\n", dim, eps,
           agg ? " (warp-aggregated sums, sorted)" : "", dmax);
    if (!(dmax <= 1e-9)) fail_msg("dim %d eps %g: reference and GPU differ by %g", dim, eps, dmax);
    assert_memory_equal(c.cell_rng, g.cell_rng, sizeof(gran_rng) * (size_t)c.ncell);
    assert_int_equal(c.nclamp, g.nclamp);
    if (!gran_test_rel_ok(tg, tc, 1e-12)) fail_msg("T: reference %.17g GPU %.17g", tc, tg);
  } else {
    /* standard error of the temperature estimate from N particles: T sqrt(2 / (d N)) */
    const double se = tc * sqrt(2.0 / (dim * (double)c.p.n));
    if (fabs(tg - tc) > 4.0 * se) fail_msg("float: T reference %.9g GPU %.9g (4 se = %.3g)", tc, tg, 4 * se);
  }
  sdb_free(&c);
  sdb_free(&g);
}

static void test_reference_vs_gpu(void **state) {
  (void)state;
  compare(3, 1.0, 0, 0);
  compare(2, 1.0, 0, 0);
  compare(3, 0.9, 0, 0);
  compare(3, 1.0, 1, 0);
  compare(3, 0.9, 1, 0);
  compare(3, 1.0, 0, 1);
  compare(2, 0.9, 0, 1);
  compare(3, 0.9, 1, 1);
}

static void test_sort_keeps_state(void **state) {
  (void)state;
  sdb_state g;
  sdb_init(&g, G, 3, 8, 10, 130.0, 1.0, 0, 5);
  double m0[3], e0, m1[3], e1;
  GRAN_ASSERT_OK(gran_cuda_srd_moments(g.dev, m0, &e0));
  GRAN_ASSERT_OK(gran_cuda_srd_sort(g.dev));
  GRAN_ASSERT_OK(gran_cuda_srd_moments(g.dev, m1, &e1));
  for (int k = 0; k < 3; ++k) assert_true(gran_test_rel_ok(m1[k], m0[k], 1e-12));
  assert_true(gran_test_rel_ok(e1, e0, 1e-12));
  sdb_run(&g, 1);
  sdb_free(&g);
}

static void test_bad_input(void **state) {
  (void)state;
  sdb_state g;
  sdb_init(&g, G, 3, 4, 2, 90.0, 1.0, 0, 1);
  const double s_bad[3] = {1.5, 0, 0}; /* a = 1: outside [0, a] */
  GRAN_ASSERT_ERR(gran_cuda_srd_step(g.dev, &g.p.geom, s_bad, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_cuda_srd_step(NULL, &g.p.geom, s_bad, NULL, NULL), GRAN_ERR_ARG);
  gran_cuda_srd_params p = g.p;
  gran_cuda_srd *h = NULL;
  const double *xs[3] = {g.x[0], g.x[1], g.x[2]}, *vs[3] = {g.v[0], g.v[1], g.v[2]};
  p.precision = 2;
  GRAN_ASSERT_ERR(gran_cuda_srd_create(&p, xs, vs, g.cell_rng, &h), GRAN_ERR_ARG);
  p = g.p;
  p.n = (int64_t)1 << 40; /* 1e12 particles: refused before any allocation */
  gran_clear_error();
  int rc = gran_cuda_srd_create(&p, xs, vs, g.cell_rng, &h);
  assert_true(rc == GRAN_ERR_UNSUPPORTED || rc == GRAN_ERR_NOMEM);
  assert_null(h);
  p = g.p;
  p.n = (int64_t)3e9; /* fits the sort keys, not the memory of any GPU now: GRAN_ERR_NOMEM naming sizes */
  p.geom.L[0] = p.geom.L[1] = p.geom.L[2] = p.geom.nc[0] = p.geom.nc[1] = p.geom.nc[2] = 1024;
  rc = gran_cuda_srd_create(&p, xs, vs, g.cell_rng, &h);
  assert_int_equal(rc, GRAN_ERR_NOMEM);
  assert_non_null(strstr(gran_last_error_message(), "GB"));
  assert_null(h);
  sdb_free(&g);
}

/* engine level, double: the GPU run follows the CPU engine to rounding (1e-9 absolute on the
 * particles, 1e-9 relative on the observables) in every scene, checkpoints included */
static void test_engine_cpu_vs_gpu(void **state) {
  (void)state;
  for (int sc = 0; sc < SDE_NSCENES; ++sc) sde_body_devices(sc, GRAN_SRD_DEVICE_CPU, G, 1e-9, 1e-9);
}

/* engine level, float storage on the GPU against the CPU engine (double), 30 steps of a larger box:
 * the float run is a different trajectory after a few steps, so each quantity is compared within
 * its noise: T and theta within 5 standard errors of a sample of N particles (T sqrt(2 / (d N))),
 * the ledger error below 1e-5, momentum conserved to float rounding, the clamps within 20 %. */
static void test_engine_float(void **state) {
  (void)state;
  for (int sc = 0; sc < SDE_NSCENES; ++sc) {
    gran_srd_options o;
    sde_options(sc, &o);
    o.cells[0] = o.cells[1] = o.dim == 3 ? 24 : 96;
    if (o.dim == 3) o.cells[2] = 24;
    gran_srd *c = NULL, *g = NULL;
    GRAN_ASSERT_OK(gran_srd_create(&o, &c));
    o.device = G;
    o.precision = 1;
    GRAN_ASSERT_OK(gran_srd_create(&o, &g));
    GRAN_ASSERT_OK(gran_srd_advance(c, 30));
    GRAN_ASSERT_OK(gran_srd_advance(g, 30));
    gran_srd_obs oc, og;
    GRAN_ASSERT_OK(gran_srd_observe(c, &oc));
    GRAN_ASSERT_OK(gran_srd_observe(g, &og));
    const double se = oc.temperature * sqrt(2.0 / (o.dim * (double)oc.n));
    printf("  float %-38s T cpu %.6g gpu %.6g (se %.2g), ledger error %.2g, clamps %lld / %lld\n", sde_names[sc],
           oc.temperature, og.temperature, se, og.ledger_error, (long long)oc.clamped, (long long)og.clamped);
    if (fabs(og.temperature - oc.temperature) > 5 * se) fail_msg("%s: float T off", sde_names[sc]);
    if (fabs(og.theta_cells - oc.theta_cells) > 5 * se) fail_msg("%s: float theta off", sde_names[sc]);
    if (!(fabs(og.ledger_error) < 1e-5)) fail_msg("%s: float ledger error %g", sde_names[sc], og.ledger_error);
    if (o.wall_axis < 0 && o.shear_rate == 0 && o.accel[0] == 0 && o.accel[1] == 0 && o.accel[2] == 0)
      for (int k = 0; k < 3; ++k)
        if (!(fabs(og.momentum[k] - oc.momentum[k]) < 1e-4 * sqrt((double)oc.n)))
          fail_msg("%s: float momentum[%d] %g vs %g", sde_names[sc], k, og.momentum[k], oc.momentum[k]);
    if (oc.clamped > 100 && fabs((double)og.clamped - (double)oc.clamped) > 0.2 * (double)oc.clamped)
      fail_msg("%s: float clamps %lld vs %lld", sde_names[sc], (long long)og.clamped, (long long)oc.clamped);
    GRAN_ASSERT_OK(gran_srd_destroy(&c));
    GRAN_ASSERT_OK(gran_srd_destroy(&g));
  }
}

/* the physics bodies on the GPU, larger than on the reference (t890) */
static void test_physics_gpu(void **state) {
  (void)state;
  sde_body_haff(G, 0, 96);
  sde_body_haff(G, 1, 96);
  sde_body_viscosity(G, 0, 2, 64, 60, 10, 200);
  sde_body_viscosity(G, 0, 2, 64, 130, 10, 200);
  sde_body_viscosity(G, 1, 2, 64, 130, 10, 200);
  sde_body_viscosity(G, 0, 3, 24, 130, 10, 100);
  sde_body_viscosity(G, 1, 3, 24, 130, 10, 100);
  sde_body_cold_flow(G, 0);
  sde_body_cold_flow(G, 1);
  sde_body_sk_ideal(G, 0, 3, 32, 20);
  sde_body_sk_ideal(G, 1, 3, 64, 20);
  sde_body_sk_ideal(G, 1, 2, 256, 20);
}

static int setup(void **state) {
  (void)state;
  if (!have_gpu()) printf("t850-srd-gpu: no GPU visible; every test is skipped\n");
  return 0;
}

#define GPU_TEST(f)                \
  static void f##_(void **state) { \
    if (!have_gpu()) skip();       \
    f(state);                      \
  }
GPU_TEST(test_conservation_gpu)
GPU_TEST(test_reference_vs_gpu)
GPU_TEST(test_sort_keeps_state)
GPU_TEST(test_bad_input)
GPU_TEST(test_engine_cpu_vs_gpu)
GPU_TEST(test_engine_float)
GPU_TEST(test_physics_gpu)

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_conservation_gpu_), cmocka_unit_test(test_reference_vs_gpu_),
      cmocka_unit_test(test_sort_keeps_state_), cmocka_unit_test(test_bad_input_),
      cmocka_unit_test(test_engine_cpu_vs_gpu_), cmocka_unit_test(test_engine_float_),
      cmocka_unit_test(test_physics_gpu_),
  };
  return cmocka_run_group_tests_name("t850-srd-gpu", tests, setup, NULL);
}
