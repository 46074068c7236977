/* t101-rng-gpu.c - xoshiro256** on the GPU: every stream's uniforms are bit-identical to the CPU's
 * (same inline core, GRAN_HD). Runs under `make test-gpu` on a machine with a GPU; compiles
 * everywhere. */
#include "granary_test.h"

static void compare(int64_t nstreams, int64_t n) {
  gran_rng *st = malloc(sizeof(gran_rng) * (size_t)(nstreams > 0 ? nstreams : 1));
  double *gpu = malloc(sizeof(double) * (size_t)(nstreams * n > 0 ? nstreams * n : 1));
  double *cpu = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1));
  assert_non_null(st);
  assert_non_null(gpu);
  assert_non_null(cpu);
  for (int64_t k = 0; k < nstreams; k++) GRAN_ASSERT_OK(gran_rng_stream(99, (uint64_t)k, &st[k]));
  gran_rng first = st[0];
  GRAN_ASSERT_OK(gran_cuda_rng_uniform(st, nstreams, n, gpu));
  if (nstreams > 0) assert_memory_equal(&first, &st[0], sizeof first); /* states not advanced */
  for (int64_t k = 0; k < nstreams; k++) {
    gran_rng g = st[k];
    GRAN_ASSERT_OK(gran_rng_uniform(&g, n, cpu));
    if (n > 0 && memcmp(gpu + k * n, cpu, sizeof(double) * (size_t)n) != 0)
      fail_msg("stream " GRAN_I64_FMT " differs between GPU and CPU", k);
  }
  free(st);
  free(gpu);
  free(cpu);
}

static void test_bit_identical(void **state) {
  (void)state;
  compare(1, 10);
  compare(1000, 1000);  /* several blocks of 128 threads, not a multiple of the block size */
  compare(130, 1);
  compare(0, 10);       /* nothing to do */
  compare(5, 0);
}

static void test_errors(void **state) {
  (void)state;
  gran_rng st[1];
  double out[1];
  GRAN_ASSERT_OK(gran_rng_seed(&st[0], 1));
  GRAN_ASSERT_ERR(gran_cuda_rng_uniform(NULL, 1, 1, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_cuda_rng_uniform(st, -1, 1, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_cuda_rng_uniform(st, 1, -1, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_cuda_rng_uniform(st, 1, 1, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_cuda_rng_uniform(st, INT64_MAX / 2, 16, out), GRAN_ERR_ARG); /* size overflow */
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_bit_identical),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests_name("t101-rng-gpu", tests, NULL, NULL);
}
