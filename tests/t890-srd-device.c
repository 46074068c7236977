/* t890-srd-device.c - GSRD device selection ("cpu" / "cuda" / "auto") and the device test bodies
 * (tests/srd_device_body.h) on the CPU reference; tests/gpu/t850-srd-gpu.c runs them on the GPU. */
#include "srd_device_body.h"
#include "srd/device_cuda.h"

static void test_device_resolve(void **state) {
  (void)state;
  int use = -1, ndev = 0, compiled = 0;
  GRAN_ASSERT_OK(gran_cuda_compiled(&compiled));
  GRAN_ASSERT_OK(gran_cuda_device_count(&ndev));
  const int gpu = compiled && ndev > 0;
  GRAN_ASSERT_OK(gran_srd_device_resolve("cpu", &use));
  assert_int_equal(use, 0);
  GRAN_ASSERT_ERR(gran_srd_device_resolve("gpu", &use), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_device_resolve(NULL, &use), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_device_resolve("cpu", NULL), GRAN_ERR_ARG);
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

static void test_conservation_cpu(void **state) {
  (void)state;
  sdb_body_conservation(0, 3, 0, 1.0);
  sdb_body_conservation(0, 2, 0, 1.0);
  sdb_body_conservation(0, 3, 0, 0.9);
}

/* The CPU reference of the device bodies is the CPU engine's algorithm: from the engine's initial
 * state, both give the same positions and velocities to rounding (same shared functions, same
 * streams, sums in particle order; measured 2e-14 after 20 steps, the C test and the C++ engine
 * contract multiply-adds differently; tolerance 1e-9 for v ~ 1), so the GPU-versus-reference
 * comparison of t850 is a GPU-versus-engine comparison. */
static void engine_vs_reference(int dim, double eps) {
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  const int64_t L = dim == 3 ? 8 : 16;
  o.dim = dim;
  o.cells[0] = o.cells[1] = L;
  o.cells[2] = dim == 3 ? L : 1;
  o.a = 1.0;
  o.n0 = 10;
  o.dt = 0.1;
  o.alpha_deg = 130.0;
  o.eps = eps;
  o.sigma = 1.0;
  o.seed = 4242;
  o.sort_every = 0;
  o.threads = 1;
  gran_srd *e = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &e));
  sdb_state r;
  sdb_init(&r, 0, dim, L, 10, 130.0, eps, 0, 4242);
  int64_t n;
  double *x[3], *v[3];
  GRAN_ASSERT_OK(gran_srd_particles(e, &n, &x[0], &x[1], &x[2], &v[0], &v[1], &v[2]));
  assert_int_equal(n, r.p.n);
  for (int k = 0; k < dim; ++k) {
    memcpy(r.x[k], x[k], sizeof(double) * (size_t)n);
    memcpy(r.v[k], v[k], sizeof(double) * (size_t)n);
  }
  GRAN_ASSERT_OK(gran_srd_advance(e, 20));
  sdb_run(&r, 20);
  GRAN_ASSERT_OK(gran_srd_particles(e, &n, &x[0], &x[1], &x[2], &v[0], &v[1], &v[2]));
  double dmax = 0.0;
  for (int k = 0; k < dim; ++k)
    for (int64_t i = 0; i < n; ++i) {
      const double dx = fabs(r.x[k][i] - x[k][i]), dv = fabs(r.v[k][i] - v[k][i]);
      dmax = dx > dmax ? dx : dmax;
      dmax = dv > dmax ? dv : dmax;
    }
  printf("engine vs reference, dim %d eps %g: max |difference| %.3g after 20 steps\n", dim, eps, dmax);
  if (dmax > 1e-9) fail_msg("dim %d eps %g: engine and reference differ by %g", dim, eps, dmax);
  sdb_free(&r);
  GRAN_ASSERT_OK(gran_srd_destroy(&e));
}

static void test_reference_is_engine(void **state) {
  (void)state;
  engine_vs_reference(3, 1.0);
  engine_vs_reference(2, 1.0);
  engine_vs_reference(3, 0.9);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_device_resolve),
      cmocka_unit_test(test_conservation_cpu),
      cmocka_unit_test(test_reference_is_engine),
  };
  return cmocka_run_group_tests_name("t890-srd-device", tests, NULL, NULL);
}
