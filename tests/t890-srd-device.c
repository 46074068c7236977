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

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_device_resolve),
      cmocka_unit_test(test_conservation_cpu),
  };
  return cmocka_run_group_tests_name("t890-srd-device", tests, NULL, NULL);
}
