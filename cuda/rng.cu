/* rng.cu - xoshiro256** on the GPU: each thread holds one gran_rng by value (STYLE rule 8) and runs
 * the very same inline core as the CPU (gran::rng_uniform, __host__ __device__ through GRAN_HD),
 * so a stream gives bit-identical numbers on both. The launcher takes host arrays, converts CUDA
 * errors with cudaGetErrorName into GRAN_ERR_CUDA, and reports GRAN_ERR_UNSUPPORTED without a GPU. */
#include <cuda_runtime.h>

#include "granary_impl.h"

namespace {

__global__ void uniform_kernel(const gran_rng *__restrict__ states, int64_t nstreams, int64_t n,
                               double *__restrict__ out) {
  const int64_t k = (int64_t)blockIdx.x * blockDim.x + threadIdx.x;
  if (k >= nstreams) return;
  gran_rng g = states[k]; /* the POD lives in registers */
  double *o = out + k * n;
  for (int64_t j = 0; j < n; j++) o[j] = gran::rng_uniform(&g);
}

/* Device buffer released on every path out of the launcher. */
struct DeviceBuffer {
  void *p = nullptr;
  ~DeviceBuffer() {
    if (p) cudaFree(p);
  }
};

#define GRAN_CUDA_CALL(expr)                                                                        \
  do {                                                                                              \
    cudaError_t gran_cerr_ = (expr);                                                                \
    if (gran_cerr_ != cudaSuccess)                                                                  \
      return GRAN_ERROR(GRAN_ERR_CUDA, "%s failed: %s (%s)", #expr, cudaGetErrorName(gran_cerr_),   \
                        cudaGetErrorString(gran_cerr_));                                            \
  } while (0)

}  // namespace

/** @brief n_per_stream uniforms in [0,1) from each of nstreams states, drawn on the GPU.
 *  @param[in] states nstreams host states (not advanced)  @param[out] out nstreams*n_per_stream
 *  host doubles, stream k at out[k*n_per_stream]. */
GRAN_EXTERN int gran_cuda_rng_uniform(const gran_rng *states, int64_t nstreams, int64_t n_per_stream,
                                      double *out) {
  GRAN_CHECK(nstreams >= 0, GRAN_ERR_ARG, "argument 'nstreams' is negative (" GRAN_I64_FMT ")", nstreams);
  GRAN_CHECK(n_per_stream >= 0, GRAN_ERR_ARG, "argument 'n_per_stream' is negative (" GRAN_I64_FMT ")",
             n_per_stream);
  GRAN_CHECK(states != nullptr || nstreams == 0, GRAN_ERR_ARG, "argument 'states' is NULL");
  GRAN_CHECK(n_per_stream == 0 || nstreams <= INT64_MAX / 8 / n_per_stream, GRAN_ERR_ARG,
             "nstreams * n_per_stream = " GRAN_I64_FMT " * " GRAN_I64_FMT " overflows", nstreams, n_per_stream);
  const int64_t total = nstreams * n_per_stream;
  GRAN_CHECK(out != nullptr || total == 0, GRAN_ERR_ARG, "argument 'out' is NULL");
  GRAN_TRY {
    int ndev = 0;
    if (cudaGetDeviceCount(&ndev) != cudaSuccess) {
      (void)cudaGetLastError();
      ndev = 0;
    }
    GRAN_CHECK(ndev > 0, GRAN_ERR_UNSUPPORTED, "no CUDA device is visible (CUDA backend compiled, no GPU)");
    if (total == 0) return GRAN_SUCCESS;
    DeviceBuffer dstates, dout;
    GRAN_CUDA_CALL(cudaMalloc(&dstates.p, sizeof(gran_rng) * (size_t)nstreams));
    GRAN_CUDA_CALL(cudaMalloc(&dout.p, sizeof(double) * (size_t)total));
    GRAN_CUDA_CALL(cudaMemcpy(dstates.p, states, sizeof(gran_rng) * (size_t)nstreams, cudaMemcpyHostToDevice));
    const int threads = 128;
    const int64_t blocks = (nstreams + threads - 1) / threads;
    GRAN_CHECK(blocks <= 0x7fffffff, GRAN_ERR_ARG, "argument 'nstreams' = " GRAN_I64_FMT " is too large", nstreams);
    uniform_kernel<<<(unsigned)blocks, threads>>>(static_cast<const gran_rng *>(dstates.p), nstreams, n_per_stream,
                                                  static_cast<double *>(dout.p));
    GRAN_CUDA_CALL(cudaGetLastError());
    GRAN_CUDA_CALL(cudaMemcpy(out, dout.p, sizeof(double) * (size_t)total, cudaMemcpyDeviceToHost));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
