/* srd_cuda.h - CUDA launchers of the GSRD engine (extern "C"; cuda/srd.cu with nvcc, cuda/stub.cpp
 * without: GRAN_ERR_UNSUPPORTED). Internal to the library (not in include/granary.h): the srd engine
 * (src/srd/) drives them; the tests and benches in tests/gpu, bench/gpu call them directly.
 *
 * Device data: positions and velocities as structure of arrays in double (precision 0) or float
 * (precision 1); cell sums in double (atomicAdd), relative to the previous mean of the same cell;
 * one xoshiro state per cell of the binning grid (stream c + 1 of the run's seed, as on the CPU);
 * the grid shift is drawn on the host (stream 0) and passed to each step. Every step is two passes:
 * (1) stream + wall reflect + wrap + bin under the shift + cell sums, (2) per-cell moments, axis,
 * eps_eff, then rotate-and-scale of every particle (the cell index is recomputed, not stored).
 * Particles are sorted by unshifted cell with CUB radix sort on request; no per-cell capacity.
 * All host arrays are borrowed (copied in or out), never kept. */
#ifndef GRAN_SRD_CUDA_H
#define GRAN_SRD_CUDA_H

#include <stddef.h>
#include <stdint.h>

#include "granary.h"
#include "srd/srd_kernels.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gran_cuda_srd gran_cuda_srd; /* opaque device state */

typedef struct gran_cuda_srd_params {
  srd_geom geom;       /* box, grid, boundaries of the run (le_dx may change per step) */
  int64_t n;           /* particles */
  int32_t precision;   /* 0: double SoA, 1: float SoA */
  int32_t dissip;      /* 0: standard SRD (eps = 1, scaling compiled out), 1: GSRD */
  double dt;           /* time step */
  double alpha;        /* rotation angle, radians */
  double coef;         /* (1 - eps^2) sigma^2 dt of Eq. 2.1 (unused when dissip = 0) */
  double g[3];         /* constant acceleration (gravity + body force per mass); all zero: none */
} gran_cuda_srd_params;

/* Device bytes the state of p needs (particles, cells, sort buffers, CUB scratch estimate). */
GRAN_EXTERN int gran_cuda_srd_bytes(const gran_cuda_srd_params *p, size_t *bytes);
/* Copy a CPU state to the device. x,v: 3 host arrays of n doubles each (unused axes may be NULL in
 * 2-D); cell_rng: one state per cell of the binning grid (nc0 nc1 nc2). x, v, cell_rng all NULL:
 * a random state made on the device (uniform positions, unit-normal velocities; benches). Checks cudaMemGetInfo
 * against gran_cuda_srd_bytes first: GRAN_ERR_NOMEM naming both numbers if it does not fit. */
GRAN_EXTERN int gran_cuda_srd_create(const gran_cuda_srd_params *p, const double *const x[3],
                                     const double *const v[3], const gran_rng *cell_rng,
                                     gran_cuda_srd **out);
/* One collision step with grid shift s (components in [0, a)); gm: this step's geometry (Lees-Edwards
 * offset). *n_clamped (may be NULL) += cells whose eps_eff was clamped; *dt_max (may be NULL) is
 * lowered to the largest dt that would have avoided the clamp. */
GRAN_EXTERN int gran_cuda_srd_step(gran_cuda_srd *h, const srd_geom *gm, const double s[3],
                                   int64_t *n_clamped, double *dt_max);
/* Sort the particles by unshifted cell (CUB radix sort + gather of each array). */
GRAN_EXTERN int gran_cuda_srd_sort(gran_cuda_srd *h);
/* Copy back (any pointer may be NULL to skip it): positions, velocities (in the device order),
 * per-cell RNG states. Used for checkpoints and observables that need particles. */
GRAN_EXTERN int gran_cuda_srd_download(const gran_cuda_srd *h, double *const x[3], double *const v[3],
                                       gran_rng *cell_rng);
/* Sum of v (mom[3]) and of |v|^2 / 2 (ekin) over all particles, reduced on the device in double. */
GRAN_EXTERN int gran_cuda_srd_moments(const gran_cuda_srd *h, double mom[3], double *ekin);
/* Device-to-device memcpy bandwidth in bytes/s (read + write counted), bytes copied per repeat. */
GRAN_EXTERN int gran_cuda_copy_bandwidth(size_t bytes, int repeats, double *bytes_per_s);
/* Wall time of nsteps steps (shift drawn from *shift_rng), synchronised, in seconds. */
GRAN_EXTERN int gran_cuda_srd_time_steps(gran_cuda_srd *h, int nsteps, gran_rng *shift_rng, double *seconds);
GRAN_EXTERN int gran_cuda_srd_destroy(gran_cuda_srd **h);

#ifdef __cplusplus
}
#endif
#endif
