/* stub.cpp - built instead of the .cu files in cuda/ when nvcc is not found: the CUDA entry points report
 * GRAN_ERR_UNSUPPORTED (device queries report zero devices). */
#include "granary_impl.h"

GRAN_EXTERN int gran_cuda_compiled(int *compiled) {
  GRAN_CHECK_PTR(compiled);
  *compiled = 0;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_cuda_device_count(int *count) {
  GRAN_CHECK_PTR(count);
  *count = 0;
  return GRAN_SUCCESS;
}

/* cuda/rng.cu */
GRAN_EXTERN int gran_cuda_rng_uniform(const gran_rng *states, int64_t nstreams, int64_t n_per_stream,
                                      double *out) {
  (void)states;
  (void)nstreams;
  (void)n_per_stream;
  (void)out;
  return GRAN_ERROR(GRAN_ERR_UNSUPPORTED, "the CUDA backend was not compiled (no nvcc)");
}
