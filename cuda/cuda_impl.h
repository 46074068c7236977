/* cuda_impl.h - shared by the .cu files: CUDA error mapping and the device-presence check. */
#ifndef GRAN_CUDA_IMPL_H
#define GRAN_CUDA_IMPL_H
#include <cuda_runtime.h>

#include "granary_impl.h"

/* Every CUDA call goes through this: a failure returns GRAN_ERR_CUDA naming the call and the
 * CUDA error (cudaGetErrorName, cudaGetErrorString). */
#define GRAN_CUDA_CALL(expr)                                                                      \
  do {                                                                                            \
    cudaError_t gran_cerr_ = (expr);                                                              \
    if (gran_cerr_ != cudaSuccess)                                                                \
      return GRAN_ERROR(GRAN_ERR_CUDA, "%s failed: %s (%s)", #expr, cudaGetErrorName(gran_cerr_), \
                        cudaGetErrorString(gran_cerr_));                                          \
  } while (0)

/* GRAN_ERR_UNSUPPORTED when no device is visible (no driver, no GPU). */
#define GRAN_CUDA_REQUIRE_DEVICE()                                                                \
  do {                                                                                            \
    int gran_ndev_ = 0;                                                                           \
    if (cudaGetDeviceCount(&gran_ndev_) != cudaSuccess) {                                         \
      (void)cudaGetLastError();                                                                   \
      gran_ndev_ = 0;                                                                             \
    }                                                                                             \
    GRAN_CHECK(gran_ndev_ > 0, GRAN_ERR_UNSUPPORTED,                                              \
               "no CUDA device is visible (CUDA backend compiled, no GPU)");                      \
  } while (0)

#endif
