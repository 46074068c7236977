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

/* cuda/srd.cu: the GSRD launchers (cuda/srd_cuda.h) */
#include "../cuda/srd_cuda.h"

#define GRAN_NO_CUDA_ GRAN_ERROR(GRAN_ERR_UNSUPPORTED, "the CUDA backend was not compiled (no nvcc)")

GRAN_EXTERN int gran_cuda_srd_bytes(const gran_cuda_srd_params *, size_t *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_create(const gran_cuda_srd_params *, const double *const[3], const double *const[3],
                                     const gran_rng *, gran_cuda_srd **out) {
  if (out) *out = nullptr;
  return GRAN_NO_CUDA_;
}
GRAN_EXTERN int gran_cuda_srd_step(gran_cuda_srd *, const srd_geom *, const double[3], int64_t *, double *) {
  return GRAN_NO_CUDA_;
}
GRAN_EXTERN int gran_cuda_srd_sort(gran_cuda_srd *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_set_sums(gran_cuda_srd *, int) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_upload(gran_cuda_srd *, const double *const[3], const double *const[3], const double *,
                                     const gran_rng *) {
  return GRAN_NO_CUDA_;
}
GRAN_EXTERN int gran_cuda_srd_download(const gran_cuda_srd *, double *const[3], double *const[3], double *, gran_rng *) {
  return GRAN_NO_CUDA_;
}
GRAN_EXTERN int gran_cuda_srd_ledger(gran_cuda_srd *, double[SRD_ACC_N], int64_t *, double *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_counts(const gran_cuda_srd *, double *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_sk_power(const gran_cuda_srd *, double *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_moments(const gran_cuda_srd *, double[3], double *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_copy_bandwidth(size_t, int, double *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_time_steps(gran_cuda_srd *, int, gran_rng *, double *) { return GRAN_NO_CUDA_; }
GRAN_EXTERN int gran_cuda_srd_destroy(gran_cuda_srd **h) {
  if (h) *h = nullptr;
  return GRAN_SUCCESS;
}
