/* srd_cuda.h - launchers of the GSRD device algorithm (extern "C"). Two implementations with the same
 * signatures: gran_cuda_srd_* run it on the GPU (cuda/srd.cu with nvcc; cuda/stub.cpp without:
 * GRAN_ERR_UNSUPPORTED), gran_ref_srd_* run it on the host, serially, in particle order
 * (src/srd/device_cuda.cpp: the reference that the CPU tests check against the CPU engine and the
 * GPU tests check the GPU against). Internal to the library (not in include/granary.h): the srd
 * engine drives them through gran_srd_launchers_get (src/srd/device_cuda.cpp); the tests and benches
 * in tests/gpu, bench/gpu call them directly.
 *
 * Device data: positions and velocities as structure of arrays in double (precision 0) or float
 * (precision 1; the reference rounds what it stores to float the same way); cell sums in double
 * (atomicAdd on the GPU), relative to the previous mean of the same cell; one xoshiro state per cell
 * of the binning grid (stream c + 1 of the run's seed, as on the CPU); the grid shift is drawn on the
 * host (stream 0) and passed to each step. Every step is two passes over the particles with a
 * per-cell pass between, each calling the rules of src/srd/rules.h (the CPU engine's too): (1) the
 * move (srd_rule_move: stream + Lees-Edwards plane flux + wall reflect + wrap) + bin under the
 * shift + cell sums, (2) with the global thermostat the sum of the cells' thermal energies
 * (srd_rule_thermal), then per cell the collision rule (srd_rule_cell: moments, virtual particles,
 * axis, eps_eff, thermostat), then the collision of every particle (srd_rule_collide; the cell
 * index is recomputed, not stored). The energy-ledger and stress sums (SRD_ACC_*) accumulate on the device
 * until gran_*_srd_ledger reads them. Particles are sorted by the cell of the last binning with CUB
 * radix sort on request (stable: the order the CPU engine's counting sort gives); no per-cell
 * capacity. All host arrays are borrowed (copied in or out), never kept. */
#ifndef GRAN_SRD_CUDA_H
#define GRAN_SRD_CUDA_H

#include <stddef.h>
#include <stdint.h>

#include "granary.h"
#include "srd/srd_kernels.h"
#include "srd/rules.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct gran_cuda_srd gran_cuda_srd; /* opaque device state (GPU or host reference) */

typedef struct gran_cuda_srd_params {
  srd_geom geom;       /* box, grid, boundaries of the run (le_dx, wall_u_lo may change per step) */
  int64_t n;           /* particles */
  int32_t precision;   /* 0: double SoA, 1: float SoA */
  int32_t fx;          /* effects: SRD_FX_* of src/srd/rules.h (0: standard SRD; DISSIP is derived) */
  double dt;           /* time step */
  double alpha;        /* rotation angle, radians */
  double coef;         /* (1 - eps^2) sigma^2 dt of Eq. 2.1 (SRD_FX_EPS) */
  double g[3];         /* constant acceleration (SRD_FX_ACCEL) */
  double n0;           /* mean particles per cell: virtual particles fill cut cells to it (SRD_FX_WALL) */
  double wall_T;       /* temperature of the virtual particles (SRD_FX_WALL) */
  double T0;           /* thermostat temperature (SRD_FX_THERMO, SRD_FX_GTHERMO) */
  double shear_rate;   /* Lees-Edwards shear rate (SRD_FX_LE): geom.le_dv = shear_rate geom.box[1] */
} gran_cuda_srd_params;

/* the run constants of the rules (src/srd/rules.h) from the parameters: the one constructor, for
 * the CPU engine (src/srd/engine.cpp) and the devices alike */
static inline srd_rule_const srd_rule_const_of(const gran_cuda_srd_params *p) {
  srd_rule_const k;
  const double a = p->geom.a;
  k.fx = srd_rule_fx_norm(p->fx);
  k.dim = p->geom.dim;
  k.dt = p->dt;
  for (int q = 0; q < 3; ++q) k.g[q] = p->g[q];
  k.rate = p->shear_rate;
  k.coef = p->coef;
  k.inv_vol = 1.0 / (p->geom.dim == 3 ? a * a * a : a * a);
  k.n0 = p->n0;
  k.wall_T = p->wall_T;
  k.T0 = p->T0;
  k.ca = cos(p->alpha);
  k.sa = sin(p->alpha);
  return k;
}

/* Float storage of coordinate k (precision 1): the rounding may not put a particle onto a wall (on
 * the wall axis a stored position stays in [0, box); periodic axes wrap any value at the next step). */
GRAN_HD static inline float srd_dev_float_pos(const srd_geom *gm, int k, double x) {
  float f = (float)x;
  while (k == gm->wall_axis && (double)f >= gm->box[k]) f = nextafterf(f, 0.0f);
  return f;
}

/* ---- GPU (cuda/srd.cu) ---- */
/* Device bytes the state of p needs (particles, cells, sort buffers, CUB scratch estimate). */
GRAN_EXTERN int gran_cuda_srd_bytes(const gran_cuda_srd_params *p, size_t *bytes);
/* Copy a CPU state to the device. x,v: 3 host arrays of n doubles each (unused axes may be NULL in
 * 2-D); cell_rng: one state per cell of the binning grid (nc0 nc1 nc2). x, v, cell_rng all NULL:
 * a random state made on the device (uniform positions, unit-normal velocities; benches). Reference
 * velocities start at 0 (gran_cuda_srd_upload sets them). Checks cudaMemGetInfo against
 * gran_cuda_srd_bytes first: GRAN_ERR_NOMEM naming both numbers if it does not fit. */
GRAN_EXTERN int gran_cuda_srd_create(const gran_cuda_srd_params *p, const double *const x[3],
                                     const double *const v[3], const gran_rng *cell_rng,
                                     gran_cuda_srd **out);
/* One collision step with grid shift s (components in [0, a]); gm: this step's geometry (Lees-Edwards
 * offset, wall velocity). n_clamped, dt_max both NULL: no synchronisation (the clamp statistics stay
 * in the ledger). Else *n_clamped += cells whose eps_eff was clamped, *dt_max is lowered to the
 * largest dt that would have avoided the clamp, and the device clamp statistics are reset. */
GRAN_EXTERN int gran_cuda_srd_step(gran_cuda_srd *h, const srd_geom *gm, const double s[3],
                                   int64_t *n_clamped, double *dt_max);
/* How pass 1 adds to the cell sums: 0 (default) one double atomicAdd per particle and component;
 * 1 the particles of a warp that share a cell are summed with shuffles first and added once (fewer
 * and less contended atomics when the particles are sorted by cell). Same results to rounding. */
GRAN_EXTERN int gran_cuda_srd_set_sums(gran_cuda_srd *h, int mode);
/* Sort the particles by the cell of the last binning (CUB radix sort + gather of each array). */
GRAN_EXTERN int gran_cuda_srd_sort(gran_cuda_srd *h);
/* Copy in (any pointer may be NULL to skip it): positions, velocities, reference velocities (3 per
 * cell, interleaved), per-cell RNG states. */
GRAN_EXTERN int gran_cuda_srd_upload(gran_cuda_srd *h, const double *const x[3], const double *const v[3],
                                     const double *vref, const gran_rng *cell_rng);
/* Copy back (any pointer may be NULL to skip it), in the device order. */
GRAN_EXTERN int gran_cuda_srd_download(const gran_cuda_srd *h, double *const x[3], double *const v[3],
                                       double *vref, gran_rng *cell_rng);
/* Ledger and stress sums since the last call (acc[SRD_ACC_*]), eps_eff clamps (*clamped +=) and the
 * smallest dt_max (*dt_max lowered); all reset on the device. clamped, dt_max may be NULL. */
GRAN_EXTERN int gran_cuda_srd_ledger(gran_cuda_srd *h, double acc[SRD_ACC_N], int64_t *clamped, double *dt_max);
/* Particles per cell of the unshifted box lattice (L0 L1 L2 cells, x fastest), as doubles (S(k)). */
GRAN_EXTERN int gran_cuda_srd_counts(const gran_cuda_srd *h, double *counts);
/* S(k) power on the device with cuFFT: |FFT(counts - mean)|^2 / n of the r2c half spectrum
 * (L2, L1, L0/2 + 1 values, row-major, the last index fastest) copied to power. */
GRAN_EXTERN int gran_cuda_srd_sk_power(const gran_cuda_srd *h, double *power);
/* Sum of v (mom[3]) and of |v|^2 / 2 (ekin) over all particles, reduced on the device in double. */
GRAN_EXTERN int gran_cuda_srd_moments(const gran_cuda_srd *h, double mom[3], double *ekin);
/* Device-to-device memcpy bandwidth in bytes/s (read + write counted), bytes copied per repeat. */
GRAN_EXTERN int gran_cuda_copy_bandwidth(size_t bytes, int repeats, double *bytes_per_s);
/* Wall time of nsteps steps (shift drawn from *shift_rng), synchronised, in seconds. */
GRAN_EXTERN int gran_cuda_srd_time_steps(gran_cuda_srd *h, int nsteps, gran_rng *shift_rng, double *seconds);
GRAN_EXTERN int gran_cuda_srd_destroy(gran_cuda_srd **h);

/* ---- host reference (src/srd/device_cuda.cpp): same contracts ---- */
GRAN_EXTERN int gran_ref_srd_create(const gran_cuda_srd_params *p, const double *const x[3],
                                    const double *const v[3], const gran_rng *cell_rng, gran_cuda_srd **out);
GRAN_EXTERN int gran_ref_srd_step(gran_cuda_srd *h, const srd_geom *gm, const double s[3], int64_t *n_clamped,
                                  double *dt_max);
GRAN_EXTERN int gran_ref_srd_sort(gran_cuda_srd *h);
GRAN_EXTERN int gran_ref_srd_upload(gran_cuda_srd *h, const double *const x[3], const double *const v[3],
                                    const double *vref, const gran_rng *cell_rng);
GRAN_EXTERN int gran_ref_srd_download(const gran_cuda_srd *h, double *const x[3], double *const v[3], double *vref,
                                      gran_rng *cell_rng);
GRAN_EXTERN int gran_ref_srd_ledger(gran_cuda_srd *h, double acc[SRD_ACC_N], int64_t *clamped, double *dt_max);
GRAN_EXTERN int gran_ref_srd_counts(const gran_cuda_srd *h, double *counts);
GRAN_EXTERN int gran_ref_srd_destroy(gran_cuda_srd **h);

/* The launcher set of a device: GRAN_SRD_DEVICE_CUDA (gran_cuda_srd_*) or GRAN_SRD_DEVICE_REFERENCE
 * (gran_ref_srd_*). */
typedef struct gran_srd_launchers {
  const char *name;
  int (*create)(const gran_cuda_srd_params *, const double *const[3], const double *const[3], const gran_rng *,
                gran_cuda_srd **);
  int (*step)(gran_cuda_srd *, const srd_geom *, const double[3], int64_t *, double *);
  int (*sort)(gran_cuda_srd *);
  int (*upload)(gran_cuda_srd *, const double *const[3], const double *const[3], const double *, const gran_rng *);
  int (*download)(const gran_cuda_srd *, double *const[3], double *const[3], double *, gran_rng *);
  int (*ledger)(gran_cuda_srd *, double[SRD_ACC_N], int64_t *, double *);
  int (*counts)(const gran_cuda_srd *, double *);
  int (*destroy)(gran_cuda_srd **);
} gran_srd_launchers;
GRAN_EXTERN const gran_srd_launchers *gran_srd_launchers_get(int device);

#ifdef __cplusplus
}
#endif
#endif
