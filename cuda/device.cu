/* device.cu - CUDA backend: device discovery. Launchers convert CUDA errors into granary codes. */
#include <cuda_runtime.h>

#include "granary_impl.h"

GRAN_EXTERN int gran_cuda_compiled(int *compiled) {
  GRAN_CHECK_PTR(compiled);
  *compiled = 1;
  return GRAN_SUCCESS;
}

/** @brief Number of visible CUDA devices; 0 (not an error) when no driver or GPU is present. */
GRAN_EXTERN int gran_cuda_device_count(int *count) {
  GRAN_CHECK_PTR(count);
  int n = 0;
  cudaError_t err = cudaGetDeviceCount(&n);
  if (err != cudaSuccess) {
    (void)cudaGetLastError(); /* clear the sticky-free error: no driver / no device */
    n = 0;
  }
  *count = n;
  return GRAN_SUCCESS;
}
