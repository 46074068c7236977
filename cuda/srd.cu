/* srd.cu - the GSRD engine on one NVIDIA GPU: kernels that iterate over particles or cells and call
 * the step rules of src/srd/rules.h (the CPU engine's), and the extern "C" launchers of
 * cuda/srd_cuda.h. */
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <vector>

#include <cub/cub.cuh>
#include <cufft.h>

#include "cuda_impl.h"
#include "srd_cuda.h"
#include "srd/device_cuda.h" /* gran_srd_dev_check_params */

namespace {

template <class T> struct Soa {
  T *x[3];
  T *v[3];
};

__device__ inline void atomic_add_f64(double *a, double v) { atomicAdd(a, v); }

/* sum of x over the warp, in lane 0 */
__device__ inline double warp_sum(double x) {
  for (int o = 16; o > 0; o >>= 1) x += __shfl_down_sync(0xffffffffu, x, o);
  return x;
}

/* the thread's ledger terms acc[q0 .. q1) into the device accumulators (one atomic per warp) */
__device__ inline void flush_acc(const double *a, int q0, int q1, double *__restrict__ acc) {
  for (int q = q0; q < q1; ++q) {
    const double x = warp_sum(a[q]);
    if ((threadIdx.x & 31) == 0 && x != 0.0) atomicAdd(&acc[q], x);
  }
}

/* sum of x over the warp, in every lane (butterfly) */
__device__ inline double warp_allsum(double x) {
  for (int o = 16; o > 0; o >>= 1) x += __shfl_xor_sync(0xffffffffu, x, o);
  return x;
}

constexpr int kAggMaxGroups = 12; /* more distinct cells in a warp: plain atomics */

/* Pass 1: the move (srd_rule_move: stream + plane flux + wall + wrap) and the per-step finiteness
 * check, bin what is stored under the shift, cell sums relative to Vref. AGG = false: every
 * particle adds itself (dim + 2 atomics). AGG = true (gran_cuda_srd_set_sums): the lanes of a warp
 * that fall in the same cell (__match_any_sync) add their sum once, when the warp holds at most
 * kAggMaxGroups cells (particles sorted by cell); the warp loop is warp-uniform so that every
 * shuffle has the full warp. */
template <class T, bool AGG>
__global__ void k_stream_bin(Soa<T> d, int64_t n, srd_rule_const K, srd_geom gm, double sx, double sy, double sz,
                             const double *__restrict__ vref, srd_cell_sum *__restrict__ sums,
                             double *__restrict__ acc) {
  const int dim = gm.dim;
  const int lane = threadIdx.x & 31;
  const double s[3] = {sx, sy, sz};
  double a[SRD_ACC_N] = {};
  const int64_t stride = (int64_t)gridDim.x * blockDim.x;
  for (int64_t base = (int64_t)blockIdx.x * blockDim.x + (threadIdx.x - lane); base < n; base += stride) {
    const int64_t i = base + lane;
    int64_t c = -1;
    double u[3] = {0, 0, 0}, q = 0.0;
    if (i < n) {
      double p[3] = {0, 0, 0}, v[3] = {0, 0, 0};
      for (int k = 0; k < dim; ++k) {
        p[k] = (double)d.x[k][i];
        v[k] = (double)d.v[k][i];
      }
      srd_rule_move(K.fx, dim, &K, &gm, p, v, a);
      if (srd_nonfinite(p, v) != 0.0) a[SRD_ACC_BAD] += 1.0; /* non-finite stays non-finite: see srd_wrap1 */
      for (int k = 0; k < dim; ++k) {
        const T xs = sizeof(T) == 4 ? (T)srd_dev_float_pos(&gm, k, p[k]) : (T)p[k], vs = (T)v[k];
        d.x[k][i] = xs;
        d.v[k][i] = vs;
        p[k] = (double)xs; /* bin what is stored (float rounding) */
        v[k] = (double)vs;
      }
      double dvx;
      c = srd_bin(&gm, s, p, &dvx);
      v[0] += dvx;
      for (int k = 0; k < dim; ++k) {
        u[k] = v[k] - vref[3 * c + k];
        q += u[k] * u[k];
      }
    }
    bool plain = !AGG;
    if (AGG) {
      /* cells < 2^32: an idle lane gets a key no cell has */
      const unsigned long long key = c >= 0 ? (unsigned long long)c : (0xffffffff00000000ull | (unsigned)lane);
      const unsigned grp = __match_any_sync(0xffffffffu, key);
      const unsigned leaders = __ballot_sync(0xffffffffu, lane == __ffs(grp) - 1);
      if (__popc(leaders) > kAggMaxGroups) {
        plain = true;
      } else {
        for (unsigned pending = leaders; pending; pending &= pending - 1) {
          const int L = __ffs(pending) - 1;
          const unsigned gmask = __shfl_sync(0xffffffffu, grp, L);
          const bool in = (gmask >> lane) & 1u;
          double t[4];
          for (int k = 0; k < 3; ++k) t[k] = warp_allsum(in ? u[k] : 0.0);
          t[3] = warp_allsum(in ? q : 0.0);
          if (lane == L && c >= 0) {
            srd_cell_sum *cs = sums + c;
            for (int k = 0; k < dim; ++k) atomic_add_f64(&cs->S[k], t[k]);
            atomic_add_f64(&cs->Q, t[3]);
            atomicAdd(reinterpret_cast<unsigned long long *>(&cs->n), (unsigned long long)__popc(gmask));
          }
        }
      }
    }
    if (plain && c >= 0) {
      srd_cell_sum *cs = sums + c;
      for (int k = 0; k < dim; ++k) atomic_add_f64(&cs->S[k], u[k]);
      atomic_add_f64(&cs->Q, q);
      atomicAdd(reinterpret_cast<unsigned long long *>(&cs->n), 1ull);
    }
  }
  if (K.fx & (SRD_FX_ACCEL | SRD_FX_WALL | SRD_FX_LE)) flush_acc(a, SRD_ACC_FLUX, SRD_ACC_IMP + 1, acc);
  flush_acc(a, SRD_ACC_BAD, SRD_ACC_BAD + 1, acc); /* non-finite moves: no atomic unless one was met */
}

/* Global thermostat (SRD_FX_GTHERMO): every cell's thermal energy and degrees of freedom
 * (srd_rule_thermal) into therm[0], therm[1] (zeroed before; one atomic per warp). */
__global__ void k_thermal(int64_t ncell, int dim, const srd_cell_sum *__restrict__ sums,
                          const double *__restrict__ vref, double *__restrict__ therm) {
  double a[2] = {0.0, 0.0};
  for (int64_t c = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; c < ncell; c += (int64_t)gridDim.x * blockDim.x) {
    const srd_cell_sum cs = sums[c];
    const double ref[3] = {vref[3 * c], vref[3 * c + 1], vref[3 * c + 2]};
    double ec, dc;
    if (!srd_rule_thermal(dim, &cs, ref, &ec, &dc)) continue;
    a[0] += ec;
    a[1] += dc;
  }
  flush_acc(a, 0, 2, therm);
}

/* Per cell (srd_rule_cell): moments, new reference, virtual particles, axis, eps_eff, thermostat
 * (therm: the sums of k_thermal, with SRD_FX_GTHERMO); sums cleared. stat[0]: clamped cells,
 * stat[1]: bits of the smallest dt_max (nonnegative doubles order as their bit patterns). */
__global__ void k_cells(int64_t ncell, srd_rule_const K, srd_geom gm, double sx, double sy, double sz,
                        srd_cell_sum *__restrict__ sums, double *__restrict__ vref, gran_rng *__restrict__ rng,
                        srd_cell_rot *__restrict__ rot, const double *__restrict__ therm,
                        unsigned long long *__restrict__ stat) {
  const double s[3] = {sx, sy, sz};
  const double gscale = (K.fx & SRD_FX_GTHERMO) ? srd_rule_gscale(therm[0], therm[1], K.T0) : 1.0;
  for (int64_t c = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; c < ncell; c += (int64_t)gridDim.x * blockDim.x) {
    const srd_cell_sum cs = sums[c];
    double ref[3] = {vref[3 * c], vref[3 * c + 1], vref[3 * c + 2]};
    gran_rng r = rng[c];
    srd_cell_rot cr;
    int cl;
    double dtm;
    srd_rule_cell(K.fx, gm.dim, &K, &gm, s, c, &cs, gscale, ref, &r, &cr, &cl, &dtm);
    for (int k = 0; k < 3; ++k) vref[3 * c + k] = ref[k];
    rng[c] = r;
    rot[c] = cr;
    if (cl) {
      atomicAdd(&stat[0], 1ull);
      atomicMin(&stat[1], (unsigned long long)__double_as_longlong(dtm));
    }
    srd_sum_clear(&sums[c]);
  }
}

/* Pass 2: the collision of each particle in its (recomputed) cell (srd_rule_collide). */
template <class T>
__global__ void k_rotate(Soa<T> d, int64_t n, srd_rule_const K, srd_geom gm, double sx, double sy, double sz,
                         const srd_cell_rot *__restrict__ rot, double *__restrict__ acc) {
  const int dim = gm.dim;
  const double s[3] = {sx, sy, sz};
  double a[SRD_ACC_N] = {};
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (int64_t)gridDim.x * blockDim.x) {
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0};
    for (int k = 0; k < dim; ++k) p[k] = (double)d.x[k][i];
    double dvx;
    const int64_t c = srd_bin(&gm, s, p, &dvx);
    const srd_cell_rot cr = rot[c];
    for (int k = 0; k < dim; ++k) v[k] = (double)d.v[k][i];
    srd_rule_collide(K.fx, dim, &K, &gm, &cr, dvx, p[1], v, a);
    for (int k = 0; k < dim; ++k) d.v[k][i] = (T)v[k];
  }
  if (K.fx & (SRD_FX_DISSIP | SRD_FX_WALL | SRD_FX_LE)) flush_acc(a, SRD_ACC_DE, SRD_ACC_LEW + 1, acc);
}

/* particles per cell of the unshifted grid (no Lees-Edwards image), as doubles */
template <class T>
__global__ void k_counts(const Soa<T> d, int64_t n, srd_geom gm, double *__restrict__ counts) {
  const double s0[3] = {0, 0, 0};
  gm.le_on = 0;
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (int64_t)gridDim.x * blockDim.x) {
    double p[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < gm.dim; ++k) p[k] = (double)d.x[k][i];
    atomicAdd(&counts[srd_bin(&gm, s0, p, &dvx)], 1.0);
  }
}

/* sort keys: the cell of the last binning (shift s, geometry gm of the last step) */
template <class T>
__global__ void k_keys(const Soa<T> d, int64_t n, srd_geom gm, double sx, double sy, double sz,
                       uint32_t *__restrict__ key, uint32_t *__restrict__ idx) {
  const double s[3] = {sx, sy, sz};
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (int64_t)gridDim.x * blockDim.x) {
    double p[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < gm.dim; ++k) p[k] = (double)d.x[k][i];
    key[i] = (uint32_t)srd_bin(&gm, s, p, &dvx);
    idx[i] = (uint32_t)i;
  }
}

template <class T>
__global__ void k_gather(const T *__restrict__ in, T *__restrict__ out, const uint32_t *__restrict__ idx, int64_t n) {
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (int64_t)gridDim.x * blockDim.x)
    out[i] = in[idx[i]];
}

template <class T>
__global__ void k_moments(const Soa<T> d, int64_t n, int dim, double *__restrict__ acc) {
  double m[4] = {0, 0, 0, 0};
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (int64_t)gridDim.x * blockDim.x)
    for (int k = 0; k < dim; ++k) {
      const double v = (double)d.v[k][i];
      m[k] += v;
      m[3] += 0.5 * v * v;
    }
  for (int j = 0; j < 4; ++j) {
    double x = m[j];
    for (int o = 16; o > 0; o >>= 1) x += __shfl_down_sync(0xffffffffu, x, o);
    if ((threadIdx.x & 31) == 0) atomicAdd(&acc[j], x);
  }
}

/* Device-side random state (x, v, cell_rng all NULL at create; benches): uniform positions, unit
 * normal velocities, per-cell states from splitmix64 of the cell index (not the CPU's streams). */
template <class T>
__global__ void k_random(Soa<T> d, int64_t n, srd_geom gm, gran_rng *__restrict__ rng, int64_t ncell) {
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n || i < ncell; i += (int64_t)gridDim.x * blockDim.x) {
    gran_rng r;
    uint64_t z = 0x9e3779b97f4a7c15ull * (uint64_t)(i + 1);
    for (int k = 0; k < 4; ++k) r.s[k] = gran::splitmix64(&z);
    if (i < ncell) {
      rng[i] = r;
      srd_rng_next(&r);
    }
    if (i < n)
      for (int k = 0; k < gm.dim; ++k) {
        double x = gm.box[k] * srd_rng_uniform(&r);
        d.x[k][i] = (T)(x < gm.box[k] ? x : 0.0);
        d.v[k][i] = (T)srd_rng_normal(&r);
      }
  }
}

__global__ void k_touch(char *p, size_t n) {
  for (size_t i = (size_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (size_t)gridDim.x * blockDim.x) p[i] = 0;
}

constexpr int kThreads = 256;
constexpr int kClamp = 0, kDtMax = 1, kMom = 2, kAcc = 6, kTherm = kAcc + SRD_ACC_N, kStat = 16;
static_assert(kTherm + 2 <= kStat, "the ledger and thermostat sums fit the stat block");
constexpr unsigned long long kInfBits = 0x7ff0000000000000ull; /* +inf */

}  // namespace

struct gran_cuda_srd {
  gran_cuda_srd_params p{};
  int64_t ncell = 0;
  size_t real = 8;
  void *x[3] = {nullptr, nullptr, nullptr}, *v[3] = {nullptr, nullptr, nullptr};
  void *tmp = nullptr;                        /* gather buffer, n reals */
  uint32_t *key[2] = {nullptr, nullptr}, *idx[2] = {nullptr, nullptr};
  void *cub_tmp = nullptr;
  size_t cub_bytes = 0;
  srd_cell_sum *sums = nullptr;
  double *vref = nullptr;
  gran_rng *rng = nullptr;
  srd_cell_rot *rot = nullptr;
  unsigned long long *stat = nullptr; /* [kClamp] clamped cells, [kDtMax] bits of the smallest dt_max,
                                         [kMom..+4) moments, [kAcc..+SRD_ACC_N) ledger sums,
                                         [kTherm..+2) the global thermostat's sums (doubles) */
  unsigned grid_p = 1, grid_c = 1;
  int key_bits = 32;
  srd_rule_const K{};
  srd_geom last_gm{};       /* geometry and shift of the last binning: the sort key */
  double last_s[3] = {0, 0, 0};
  int agg = 0;              /* cell sums: 0 one atomic per particle, 1 warp-aggregated */
};

namespace {

int64_t cells_of(const srd_geom &g) { return g.nc[0] * g.nc[1] * g.nc[2]; }

unsigned grid_for(int64_t n) {
  int dev = 0, sms = 80;
  if (cudaGetDevice(&dev) == cudaSuccess) cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, dev);
  (void)cudaGetLastError();
  const int64_t want = (n + kThreads - 1) / kThreads, cap = (int64_t)sms * 32;
  return (unsigned)(want < 1 ? 1 : want > cap ? cap : want);
}

size_t bytes_of(const gran_cuda_srd_params *p) {
  const size_t n = (size_t)p->n, nc = (size_t)cells_of(p->geom), real = p->precision ? 4 : 8;
  const size_t part = n * (2 * (size_t)p->geom.dim * real + real + 4 * sizeof(uint32_t));
  const size_t cell = nc * (sizeof(srd_cell_sum) + 3 * sizeof(double) + sizeof(gran_rng) + sizeof(srd_cell_rot));
  const size_t scratch = n / 64 + (size_t)(64u << 20); /* CUB onesweep histograms + slack */
  return part + cell + scratch;
}

template <class T> Soa<T> soa(const gran_cuda_srd *h) {
  Soa<T> s;
  for (int k = 0; k < 3; ++k) {
    s.x[k] = static_cast<T *>(h->x[k]);
    s.v[k] = static_cast<T *>(h->v[k]);
  }
  return s;
}

template <class T> int step_t(gran_cuda_srd *h, const srd_geom &gm, const double s[3]) {
  const gran_cuda_srd_params &p = h->p;
  const Soa<T> d = soa<T>(h);
  double *acc = reinterpret_cast<double *>(h->stat + kAcc);
  if (h->agg)
    k_stream_bin<T, true><<<h->grid_p, kThreads>>>(d, p.n, h->K, gm, s[0], s[1], s[2], h->vref, h->sums, acc);
  else
    k_stream_bin<T, false><<<h->grid_p, kThreads>>>(d, p.n, h->K, gm, s[0], s[1], s[2], h->vref, h->sums, acc);
  GRAN_CUDA_CALL(cudaGetLastError());
  double *therm = reinterpret_cast<double *>(h->stat + kTherm);
  if (h->K.fx & SRD_FX_GTHERMO) {
    GRAN_CUDA_CALL(cudaMemsetAsync(therm, 0, 2 * sizeof(double)));
    k_thermal<<<h->grid_c, kThreads>>>(h->ncell, gm.dim, h->sums, h->vref, therm);
    GRAN_CUDA_CALL(cudaGetLastError());
  }
  k_cells<<<h->grid_c, kThreads>>>(h->ncell, h->K, gm, s[0], s[1], s[2], h->sums, h->vref, h->rng, h->rot, therm,
                                   h->stat);
  GRAN_CUDA_CALL(cudaGetLastError());
  k_rotate<T><<<h->grid_p, kThreads>>>(d, p.n, h->K, gm, s[0], s[1], s[2], h->rot, acc);
  GRAN_CUDA_CALL(cudaGetLastError());
  return GRAN_SUCCESS;
}

template <class T> int sort_t(gran_cuda_srd *h) {
  const int64_t n = h->p.n;
  if (n < 2) return GRAN_SUCCESS;
  k_keys<T><<<h->grid_p, kThreads>>>(soa<T>(h), n, h->last_gm, h->last_s[0], h->last_s[1], h->last_s[2], h->key[0],
                                      h->idx[0]);
  GRAN_CUDA_CALL(cudaGetLastError());
  cub::DoubleBuffer<uint32_t> keys(h->key[0], h->key[1]), vals(h->idx[0], h->idx[1]);
  size_t bytes = h->cub_bytes;
  GRAN_CUDA_CALL(cub::DeviceRadixSort::SortPairs(h->cub_tmp, bytes, keys, vals, n, 0, h->key_bits));
  const uint32_t *perm = vals.Current();
  for (int k = 0; k < 2 * h->p.geom.dim; ++k) {
    void **arr = k < h->p.geom.dim ? &h->x[k] : &h->v[k - h->p.geom.dim];
    k_gather<T><<<h->grid_p, kThreads>>>(static_cast<const T *>(*arr), static_cast<T *>(h->tmp), perm, n);
    GRAN_CUDA_CALL(cudaGetLastError());
    void *t = *arr; /* swap buffers: no copy back */
    *arr = h->tmp;
    h->tmp = t;
  }
  return GRAN_SUCCESS;
}

void release(gran_cuda_srd *h) {
  if (!h) return;
  void *ptrs[] = {h->x[0], h->x[1], h->x[2], h->v[0], h->v[1], h->v[2], h->tmp, h->key[0], h->key[1], h->idx[0],
                  h->idx[1], h->cub_tmp, h->sums, h->vref, h->rng, h->rot, h->stat};
  for (void *q : ptrs)
    if (q) cudaFree(q);
  delete h;
}

struct Guard {
  gran_cuda_srd *h;
  ~Guard() { release(h); }
};

/* clamp statistics: read and reset */
int read_clamps(gran_cuda_srd *h, int64_t *n_clamped, double *dt_max) {
  unsigned long long st[2], st0[2] = {0, kInfBits};
  GRAN_CUDA_CALL(cudaMemcpy(st, h->stat + kClamp, sizeof st, cudaMemcpyDeviceToHost));
  GRAN_CUDA_CALL(cudaMemcpy(h->stat + kClamp, st0, sizeof st0, cudaMemcpyHostToDevice));
  if (n_clamped) *n_clamped += (int64_t)st[0];
  double dm;
  std::memcpy(&dm, &st[1], sizeof dm);
  if (dt_max && dm < *dt_max) *dt_max = dm;
  return GRAN_SUCCESS;
}

/* host doubles -> device reals (converted on the host in chunks); positions of the wall axis
 * (wall_box > 0) stay below the wall after rounding to float */
int upload_reals(void *dst, const double *src, size_t n, size_t real, double wall_box) {
  if (real == 8) {
    GRAN_CUDA_CALL(cudaMemcpy(dst, src, n * 8, cudaMemcpyHostToDevice));
    return GRAN_SUCCESS;
  }
  const size_t chunk = (size_t)1 << 22;
  std::vector<float> stage(n < chunk ? n : chunk);
  for (size_t i0 = 0; i0 < n; i0 += chunk) {
    const size_t m = n - i0 < chunk ? n - i0 : chunk;
    for (size_t i = 0; i < m; ++i) {
      float f = (float)src[i0 + i];
      while (wall_box > 0 && (double)f >= wall_box) f = nextafterf(f, 0.0f);
      stage[i] = f;
    }
    GRAN_CUDA_CALL(cudaMemcpy(static_cast<float *>(dst) + i0, stage.data(), m * 4, cudaMemcpyHostToDevice));
  }
  return GRAN_SUCCESS;
}

}  // namespace

GRAN_EXTERN int gran_cuda_srd_bytes(const gran_cuda_srd_params *p, size_t *bytes) {
  GRAN_CHECK_PTR(bytes);
  GRAN_CALL(gran_srd_dev_check_params(p));
  *bytes = bytes_of(p);
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_cuda_srd_create(const gran_cuda_srd_params *p, const double *const x[3], const double *const v[3],
                                     const gran_rng *cell_rng, gran_cuda_srd **out) {
  GRAN_CHECK_PTR(out);
  *out = nullptr;
  GRAN_CALL(gran_srd_dev_check_params(p));
  GRAN_CHECK((x == nullptr) == (v == nullptr) && (x == nullptr) == (cell_rng == nullptr), GRAN_ERR_ARG,
             "x, v and cell_rng must be all given or all NULL (device-side random state)");
  for (int k = 0; x && k < p->geom.dim; ++k)
    GRAN_CHECK(p->n == 0 || (x[k] && v[k]), GRAN_ERR_ARG, "x[%d] or v[%d] is NULL", k, k);
  GRAN_TRY {
    GRAN_CUDA_REQUIRE_DEVICE();
    const size_t need = bytes_of(p);
    size_t freeb = 0, total = 0;
    GRAN_CUDA_CALL(cudaMemGetInfo(&freeb, &total));
    GRAN_CHECK(need <= freeb, GRAN_ERR_NOMEM,
               "the run needs %.3g GB of device memory, %.3g GB of %.3g GB are free (use precision = float, fewer "
               "particles, or device = \"cpu\")",
               1e-9 * (double)need, 1e-9 * (double)freeb, 1e-9 * (double)total);
    Guard g{new gran_cuda_srd};
    gran_cuda_srd *h = g.h;
    h->p = *p;
    h->ncell = cells_of(p->geom);
    h->real = p->precision ? 4 : 8;
    const size_t n = (size_t)p->n, nb = (n ? n : 1) * h->real;
    const int dim = p->geom.dim;
    for (int k = 0; k < dim; ++k) {
      GRAN_CUDA_CALL(cudaMalloc(&h->x[k], nb));
      GRAN_CUDA_CALL(cudaMalloc(&h->v[k], nb));
    }
    GRAN_CUDA_CALL(cudaMalloc(&h->tmp, nb));
    for (int b = 0; b < 2; ++b) {
      GRAN_CUDA_CALL(cudaMalloc(&h->key[b], (n ? n : 1) * 4));
      GRAN_CUDA_CALL(cudaMalloc(&h->idx[b], (n ? n : 1) * 4));
    }
    h->key_bits = 1;
    while (h->key_bits < 32 && ((int64_t)1 << h->key_bits) < h->ncell) ++h->key_bits;
    {
      cub::DoubleBuffer<uint32_t> keys(h->key[0], h->key[1]), vals(h->idx[0], h->idx[1]);
      GRAN_CUDA_CALL(cub::DeviceRadixSort::SortPairs(nullptr, h->cub_bytes, keys, vals, (int64_t)n, 0, h->key_bits));
      GRAN_CUDA_CALL(cudaMalloc(&h->cub_tmp, h->cub_bytes ? h->cub_bytes : 1));
    }
    const size_t nc = (size_t)h->ncell;
    GRAN_CUDA_CALL(cudaMalloc(&h->sums, nc * sizeof(srd_cell_sum)));
    GRAN_CUDA_CALL(cudaMemset(h->sums, 0, nc * sizeof(srd_cell_sum)));
    GRAN_CUDA_CALL(cudaMalloc(&h->vref, nc * 3 * sizeof(double)));
    GRAN_CUDA_CALL(cudaMemset(h->vref, 0, nc * 3 * sizeof(double)));
    GRAN_CUDA_CALL(cudaMalloc(&h->rng, nc * sizeof(gran_rng)));
    if (cell_rng) GRAN_CUDA_CALL(cudaMemcpy(h->rng, cell_rng, nc * sizeof(gran_rng), cudaMemcpyHostToDevice));
    GRAN_CUDA_CALL(cudaMalloc(&h->rot, nc * sizeof(srd_cell_rot)));
    GRAN_CUDA_CALL(cudaMalloc(&h->stat, kStat * sizeof(unsigned long long)));
    {
      unsigned long long st0[kStat] = {0};
      st0[kDtMax] = kInfBits;
      GRAN_CUDA_CALL(cudaMemcpy(h->stat, st0, sizeof st0, cudaMemcpyHostToDevice));
    }
    h->K = srd_rule_const_of(p);
    h->last_gm = p->geom;
    for (int a = 0; x && a < 2 * dim; ++a)
      GRAN_CALL(upload_reals(a < dim ? h->x[a] : h->v[a - dim], a < dim ? x[a] : v[a - dim], n, h->real,
                             a == p->geom.wall_axis ? p->geom.box[a] : 0.0));
    h->grid_p = grid_for(p->n);
    h->grid_c = grid_for(h->ncell);
    if (!x) {
      if (h->real == 4)
        k_random<float><<<h->grid_p, kThreads>>>(soa<float>(h), p->n, p->geom, h->rng, h->ncell);
      else
        k_random<double><<<h->grid_p, kThreads>>>(soa<double>(h), p->n, p->geom, h->rng, h->ncell);
      GRAN_CUDA_CALL(cudaGetLastError());
    }
    GRAN_CUDA_CALL(cudaDeviceSynchronize());
    *out = h;
    g.h = nullptr;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_step(gran_cuda_srd *h, const srd_geom *gm, const double s[3], int64_t *n_clamped,
                                   double *dt_max) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(gm);
  GRAN_CHECK_PTR(s);
  GRAN_CHECK(gm->dim == h->p.geom.dim && gm->nc[0] == h->p.geom.nc[0] && gm->nc[1] == h->p.geom.nc[1] &&
                 gm->nc[2] == h->p.geom.nc[2] && gm->wall_axis == h->p.geom.wall_axis,
             GRAN_ERR_ARG, "gm: dimension, grid or walls differ from the state's");
  for (int k = 0; k < gm->dim; ++k)
    GRAN_CHECK(s[k] >= 0.0 && s[k] <= gm->a, GRAN_ERR_ARG, "shift s[%d] = %g outside [0, a]", k, s[k]);
  GRAN_TRY {
    h->p.geom = *gm;
    GRAN_CALL(h->real == 4 ? step_t<float>(h, *gm, s) : step_t<double>(h, *gm, s));
    h->last_gm = *gm;
    for (int k = 0; k < 3; ++k) h->last_s[k] = s[k];
    if (n_clamped || dt_max) GRAN_CALL(read_clamps(h, n_clamped, dt_max));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_set_sums(gran_cuda_srd *h, int mode) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK(mode == 0 || mode == 1, GRAN_ERR_ARG, "mode = %d: must be 0 (atomics) or 1 (warp-aggregated)", mode);
  h->agg = mode;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_cuda_srd_sort(gran_cuda_srd *h) {
  GRAN_CHECK_PTR(h);
  GRAN_TRY { return h->real == 4 ? sort_t<float>(h) : sort_t<double>(h); }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_upload(gran_cuda_srd *h, const double *const x[3], const double *const v[3],
                                     const double *vref, const gran_rng *cell_rng) {
  GRAN_CHECK_PTR(h);
  GRAN_TRY {
    const size_t n = (size_t)h->p.n;
    const int dim = h->p.geom.dim;
    for (int a = 0; a < 2 * dim; ++a) {
      const double *src = a < dim ? (x ? x[a] : nullptr) : (v ? v[a - dim] : nullptr);
      if (src && n)
        GRAN_CALL(upload_reals(a < dim ? h->x[a] : h->v[a - dim], src, n, h->real,
                               a == h->p.geom.wall_axis ? h->p.geom.box[a] : 0.0));
    }
    if (vref)
      GRAN_CUDA_CALL(cudaMemcpy(h->vref, vref, (size_t)h->ncell * 3 * sizeof(double), cudaMemcpyHostToDevice));
    if (cell_rng)
      GRAN_CUDA_CALL(cudaMemcpy(h->rng, cell_rng, (size_t)h->ncell * sizeof(gran_rng), cudaMemcpyHostToDevice));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_download(const gran_cuda_srd *h, double *const x[3], double *const v[3], double *vref,
                                       gran_rng *cell_rng) {
  GRAN_CHECK_PTR(h);
  GRAN_TRY {
    GRAN_CUDA_CALL(cudaDeviceSynchronize());
    const size_t n = (size_t)h->p.n;
    const int dim = h->p.geom.dim;
    std::vector<float> stage(h->real == 4 ? n : 0);
    for (int a = 0; a < 2 * dim; ++a) {
      double *dst = a < dim ? (x ? x[a] : nullptr) : (v ? v[a - dim] : nullptr);
      if (!dst || n == 0) continue;
      const void *src = a < dim ? h->x[a] : h->v[a - dim];
      if (h->real == 8) {
        GRAN_CUDA_CALL(cudaMemcpy(dst, src, n * 8, cudaMemcpyDeviceToHost));
      } else {
        GRAN_CUDA_CALL(cudaMemcpy(stage.data(), src, n * 4, cudaMemcpyDeviceToHost));
        for (size_t i = 0; i < n; ++i) dst[i] = (double)stage[i];
      }
    }
    if (vref)
      GRAN_CUDA_CALL(cudaMemcpy(vref, h->vref, (size_t)h->ncell * 3 * sizeof(double), cudaMemcpyDeviceToHost));
    if (cell_rng)
      GRAN_CUDA_CALL(cudaMemcpy(cell_rng, h->rng, (size_t)h->ncell * sizeof(gran_rng), cudaMemcpyDeviceToHost));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_ledger(gran_cuda_srd *h, double acc[SRD_ACC_N], int64_t *clamped, double *dt_max) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(acc);
  GRAN_TRY {
    GRAN_CUDA_CALL(cudaMemcpy(acc, h->stat + kAcc, SRD_ACC_N * sizeof(double), cudaMemcpyDeviceToHost));
    GRAN_CUDA_CALL(cudaMemset(h->stat + kAcc, 0, SRD_ACC_N * sizeof(double)));
    GRAN_CALL(read_clamps(h, clamped, dt_max));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_counts(const gran_cuda_srd *h, double *counts) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(counts);
  GRAN_TRY {
    double *dc = nullptr;
    const size_t bytes = (size_t)h->ncell * sizeof(double);
    GRAN_CUDA_CALL(cudaMalloc(&dc, bytes));
    cudaError_t e = cudaMemset(dc, 0, bytes);
    if (e == cudaSuccess) {
      if (h->real == 4)
        k_counts<float><<<h->grid_p, kThreads>>>(soa<float>(h), h->p.n, h->p.geom, dc);
      else
        k_counts<double><<<h->grid_p, kThreads>>>(soa<double>(h), h->p.n, h->p.geom, dc);
      e = cudaGetLastError();
    }
    if (e == cudaSuccess) e = cudaMemcpy(counts, dc, bytes, cudaMemcpyDeviceToHost);
    cudaFree(dc);
    GRAN_CUDA_CALL(e);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_moments(const gran_cuda_srd *h, double mom[3], double *ekin) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(mom);
  GRAN_CHECK_PTR(ekin);
  GRAN_TRY {
    double *acc = reinterpret_cast<double *>(h->stat + kMom);
    GRAN_CUDA_CALL(cudaMemset(acc, 0, 4 * sizeof(double)));
    if (h->real == 4)
      k_moments<float><<<h->grid_p, kThreads>>>(soa<float>(h), h->p.n, h->p.geom.dim, acc);
    else
      k_moments<double><<<h->grid_p, kThreads>>>(soa<double>(h), h->p.n, h->p.geom.dim, acc);
    GRAN_CUDA_CALL(cudaGetLastError());
    double r[4];
    GRAN_CUDA_CALL(cudaMemcpy(r, acc, sizeof r, cudaMemcpyDeviceToHost));
    for (int k = 0; k < 3; ++k) mom[k] = r[k];
    *ekin = r[3];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

namespace {
/* buffers and events of the timings, released on every path */
struct BwRes {
  void *a = nullptr, *b = nullptr;
  cudaEvent_t e0 = nullptr, e1 = nullptr;
  ~BwRes() {
    if (e0) cudaEventDestroy(e0);
    if (e1) cudaEventDestroy(e1);
    cudaFree(a);
    cudaFree(b);
  }
};
}  // namespace

GRAN_EXTERN int gran_cuda_srd_time_steps(gran_cuda_srd *h, int nsteps, gran_rng *shift_rng, double *seconds) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(shift_rng);
  GRAN_CHECK_PTR(seconds);
  GRAN_CHECK(nsteps >= 1, GRAN_ERR_ARG, "nsteps = %d must be >= 1", nsteps);
  GRAN_TRY {
    BwRes r;
    GRAN_CUDA_CALL(cudaEventCreate(&r.e0));
    GRAN_CUDA_CALL(cudaEventCreate(&r.e1));
    GRAN_CUDA_CALL(cudaEventRecord(r.e0));
    int rc = GRAN_SUCCESS;
    for (int t = 0; t < nsteps && rc == GRAN_SUCCESS; ++t) {
      double s[3] = {0, 0, 0};
      for (int k = 0; k < h->p.geom.dim; ++k) s[k] = h->p.geom.a * srd_rng_uniform(shift_rng);
      rc = gran_cuda_srd_step(h, &h->p.geom, s, nullptr, nullptr);
    }
    GRAN_CUDA_CALL(cudaEventRecord(r.e1));
    GRAN_CUDA_CALL(cudaEventSynchronize(r.e1));
    float ms = 0.f;
    GRAN_CUDA_CALL(cudaEventElapsedTime(&ms, r.e0, r.e1));
    *seconds = 1e-3 * (double)ms;
    return rc;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_copy_bandwidth(size_t bytes, int repeats, double *bytes_per_s) {
  GRAN_CHECK_PTR(bytes_per_s);
  GRAN_CHECK(bytes > 0 && repeats >= 1, GRAN_ERR_ARG, "bytes = %zu and repeats = %d must be positive", bytes, repeats);
  GRAN_TRY {
    GRAN_CUDA_REQUIRE_DEVICE();
    BwRes r;
    GRAN_CUDA_CALL(cudaMalloc(&r.a, bytes));
    GRAN_CUDA_CALL(cudaMalloc(&r.b, bytes));
    k_touch<<<grid_for((int64_t)bytes), kThreads>>>(static_cast<char *>(r.a), bytes);
    GRAN_CUDA_CALL(cudaGetLastError());
    GRAN_CUDA_CALL(cudaEventCreate(&r.e0));
    GRAN_CUDA_CALL(cudaEventCreate(&r.e1));
    GRAN_CUDA_CALL(cudaMemcpy(r.b, r.a, bytes, cudaMemcpyDeviceToDevice)); /* warm-up */
    GRAN_CUDA_CALL(cudaEventRecord(r.e0));
    for (int k = 0; k < repeats; ++k) GRAN_CUDA_CALL(cudaMemcpy(r.b, r.a, bytes, cudaMemcpyDeviceToDevice));
    GRAN_CUDA_CALL(cudaEventRecord(r.e1));
    GRAN_CUDA_CALL(cudaEventSynchronize(r.e1));
    float ms = 0.f;
    GRAN_CUDA_CALL(cudaEventElapsedTime(&ms, r.e0, r.e1));
    *bytes_per_s = 2.0 * (double)bytes * repeats / (1e-3 * (double)ms);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_cuda_srd_destroy(gran_cuda_srd **h) {
  if (h && *h) {
    release(*h);
    *h = nullptr;
  }
  return GRAN_SUCCESS;
}

/* ---- S(k) with cuFFT ------------------------------------------------------------------------ */
namespace {

__global__ void k_center(double *__restrict__ c, int64_t n, double mean) {
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < n; i += (int64_t)gridDim.x * blockDim.x)
    c[i] -= mean;
}

__global__ void k_power(const cufftDoubleComplex *__restrict__ z, double *__restrict__ p, int64_t m, double inv_n) {
  for (int64_t i = (int64_t)blockIdx.x * blockDim.x + threadIdx.x; i < m; i += (int64_t)gridDim.x * blockDim.x)
    p[i] = (z[i].x * z[i].x + z[i].y * z[i].y) * inv_n;
}

struct SkBuffers {
  double *cnt = nullptr, *pw = nullptr;
  cufftDoubleComplex *z = nullptr;
  cufftHandle plan = 0;
  bool planned = false;
  ~SkBuffers() {
    if (planned) cufftDestroy(plan);
    cudaFree(cnt);
    cudaFree(pw);
    cudaFree(z);
  }
};

}  // namespace

#define GRAN_CUFFT_CALL(expr)                                                                   \
  do {                                                                                          \
    cufftResult gran_fr_ = (expr);                                                              \
    if (gran_fr_ != CUFFT_SUCCESS) return GRAN_ERROR(GRAN_ERR_CUDA, "%s failed: cufftResult %d", #expr, (int)gran_fr_); \
  } while (0)

GRAN_EXTERN int gran_cuda_srd_sk_power(const gran_cuda_srd *h, double *power) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(power);
  const srd_geom &g = h->p.geom;
  GRAN_CHECK(g.wall_axis < 0, GRAN_ERR_ARG, "S(k) needs a periodic box (no walls)");
  GRAN_TRY {
    const int n0 = (int)g.L[0], n1 = (int)g.L[1], n2 = g.dim == 3 ? (int)g.L[2] : 1;
    const int64_t ncplx = (int64_t)n2 * n1 * (n0 / 2 + 1);
    SkBuffers b;
    GRAN_CUDA_CALL(cudaMalloc(&b.cnt, (size_t)h->ncell * sizeof(double)));
    GRAN_CUDA_CALL(cudaMalloc(&b.z, (size_t)ncplx * sizeof(cufftDoubleComplex)));
    GRAN_CUDA_CALL(cudaMalloc(&b.pw, (size_t)ncplx * sizeof(double)));
    GRAN_CUDA_CALL(cudaMemset(b.cnt, 0, (size_t)h->ncell * sizeof(double)));
    if (h->real == 4)
      k_counts<float><<<h->grid_p, kThreads>>>(soa<float>(h), h->p.n, g, b.cnt);
    else
      k_counts<double><<<h->grid_p, kThreads>>>(soa<double>(h), h->p.n, g, b.cnt);
    GRAN_CUDA_CALL(cudaGetLastError());
    k_center<<<h->grid_c, kThreads>>>(b.cnt, h->ncell, (double)h->p.n / (double)h->ncell);
    GRAN_CUDA_CALL(cudaGetLastError());
    if (g.dim == 3) GRAN_CUFFT_CALL(cufftPlan3d(&b.plan, n2, n1, n0, CUFFT_D2Z));
    else GRAN_CUFFT_CALL(cufftPlan2d(&b.plan, n1, n0, CUFFT_D2Z));
    b.planned = true;
    GRAN_CUFFT_CALL(cufftExecD2Z(b.plan, b.cnt, b.z));
    k_power<<<grid_for(ncplx), kThreads>>>(b.z, b.pw, ncplx, 1.0 / (double)h->p.n);
    GRAN_CUDA_CALL(cudaGetLastError());
    GRAN_CUDA_CALL(cudaMemcpy(power, b.pw, (size_t)ncplx * sizeof(double), cudaMemcpyDeviceToHost));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
