/* srd_impl.h - private state of the GSRD engine (src/srd/). */
#ifndef GRAN_SRD_IMPL_H
#define GRAN_SRD_IMPL_H

#include "granary_impl.h"
#include "srd/srd_kernels.h"
#include "core/exactsum.h"
#include "srd/device_cuda.h" /* device hook (owner: CUDA backend) */

#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <memory>
#include <utility>
#include <vector>

/* Persistent record of one cell of the CPU engine, 24 B: the reference velocity (the cell's mean
 * at its previous collision; the cell sums of the next step are taken relative to it). With the
 * cell's RNG state (32 B) this is all the engine keeps per cell between steps: the sums and the
 * collision record of a cell live only while its slab is processed (thread-local, see engine.cpp). */
struct srd_cpu_cell {
  double V[3];
};
/* Per-cell work record of one slab (thread-local, 64 B): the sums while the slab's particles are
 * binned, then the collision record in the same bytes (the sums are read into locals first). */
union srd_slab_cell {
  srd_cell_sum s;
  srd_cell_rot rot;
};

/* Allocator that leaves trivial elements uninitialised on resize: big per-cell arrays are then
 * first touched (and zeroed or filled) in parallel by the engine, not serially by std::vector. */
template <class T>
struct srd_uninit_alloc : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = srd_uninit_alloc<U>;
  };
  srd_uninit_alloc() = default;
  template <class U>
  srd_uninit_alloc(const srd_uninit_alloc<U> &) {}
  template <class U>
  void construct(U *p) noexcept {
    ::new ((void *)p) U;
  }
  template <class U, class... A>
  void construct(U *p, A &&...a) {
    ::new ((void *)p) U(std::forward<A>(a)...);
  }
};
static_assert(sizeof(srd_cpu_cell) == 24, "GSRD persistent cell record is 24 B");

struct gran_srd {
  gran_srd_options opt;
  srd_geom gm;
  int64_t n = 0;          /* particles */
  int64_t ncell = 0;      /* cells of the binning grid */
  int64_t ncell_box = 0;  /* cells of the box (unshifted lattice) */
  /* particles, SoA (48 B; the cell index is recomputed, not stored) */
  std::vector<double> x, y, z, vx, vy, vz;
  /* cells: 24 B reference velocity + 32 B RNG state (nothing else persists per cell) */
  std::vector<srd_cpu_cell, srd_uninit_alloc<srd_cpu_cell>> cell; /* zeroed by alloc_state */
  std::vector<gran_rng, srd_uninit_alloc<gran_rng>> rng; /* one stream per cell: stream c + 1 */
  /* step work space (engine.cpp): every fixed block of SRD_BLOCK particles lists its particles by
   * slab of the binning grid, as 2 B offsets inside the block (slab_list, 2 B per particle), with
   * the slab starts of each block (slab_off, nslab + 1 per block) */
  std::vector<uint16_t, srd_uninit_alloc<uint16_t>> slab_list;
  std::vector<uint16_t> slab_off;
  gran_rng shift_rng;        /* stream 0 */
  double shift[3] = {0, 0, 0};
  /* state */
  int64_t step = 0;
  double time = 0.0;
  /* energy ledger (per mass; E = sum v^2 / 2 (+ potential)) */
  double e_initial = 0.0;
  double e_coll = 0.0;    /* energy change in collisions (< 0: dissipated; thermostat adds) */
  double e_ext = 0.0;     /* work of walls, Lees-Edwards crossings, forces */
  int64_t clamped = 0;    /* eps_eff clamps since the last observe */
  double dt_max = INFINITY; /* smallest dt_max over clamped cells */
  /* stress (Lees-Edwards) */
  double flux_kin = 0.0;  /* sum over streaming moves of (vx - u(y)) dy (all planes y = const) */
  double flux_coll = 0.0; /* sum dvx * y in collisions */
  double stress_t0 = 0.0; /* time at the last stress reset */
  double wall_impulse[3] = {0, 0, 0};
  /* block partial sums (deterministic reductions independent of thread count) */
  std::vector<double> part;
  /* ---- device hook (owner: CUDA backend, src/srd/device_cuda.cpp): NULL on the CPU engine ---- */
  gran_srd_dev_holder dev;
};

/* The cells' reference velocities as 3 doubles per cell (checkpoint layout; device backends). */
inline void srd_refs_get(const gran_srd *s, std::vector<double> &out) {
  out.resize((size_t)s->ncell * 3);
  for (int64_t c = 0; c < s->ncell; ++c)
    for (int k = 0; k < 3; ++k) out[(size_t)(3 * c + k)] = s->cell[(size_t)c].V[k];
}
inline void srd_refs_set(gran_srd *s, const double *in) {
  for (int64_t c = 0; c < s->ncell; ++c)
    for (int k = 0; k < 3; ++k) s->cell[(size_t)c].V[k] = in[3 * c + k];
}

#define SRD_BLOCK 4096 /* <= 65535: slab_list / slab_off hold offsets inside a block as uint16_t */
/* slabs of the binning grid (engine.cpp): about SRD_SLAB_CELLS cells each, no thicker than
 * 1 / SRD_MIN_SLABS of the layers (rounded up), at most SRD_MAX_SLABS (slab indices fit uint8_t) */
#define SRD_SLAB_CELLS 4096
#define SRD_MIN_SLABS 8
#define SRD_MAX_SLABS 256
#define SRD_CHUNK 512 /* particles whose cells are computed ahead of their use (stack buffers) */

/* S(k) of the unshifted cell counts (engine.cpp): the half-spectrum power |FFT(n - <n>)|^2 / N
 * (FFTW) of the N = s->n particles, and its radial average in shells; the CPU engine, the devices and
 * a split gas (bricks.cpp) share them. */
int srd_sk_power(const gran_srd *s, const double *counts, std::vector<double> &power);
void srd_sk_shells(const gran_srd *s, const double *power, int64_t nbins, double *k, double *sk, int64_t *count);
/* the half spectrum's geometry (row-major n2 x n1 x nh, nh = n0 / 2 + 1; n2 = 1 in 2-D) and the
 * shells' width w = sqrt(d) pi / (a nbins) */
struct srd_sk_geom {
  int dim, n0, n1, n2, nh;
  double box[3], w;
  int64_t nbins;
};
srd_sk_geom srd_sk_geom_of(const gran_srd *s, int64_t nbins);
/* The shells' sums: exact (core/exactsum.h), so that they do not depend on the order of the modes or
 * on which process holds which: the serial engine, the devices and a split gas on any number of
 * processes add the same numbers into the same bits. */
struct srd_sk_bin {
  gran_exactsum k, s; /* sums of mult |k| and mult S over the shell's modes */
  int64_t count;      /* sum of mult */
  void merge(const srd_sk_bin &o) {
    gran_exactsum_merge_(&k, &o.k);
    gran_exactsum_merge_(&s, &o.s);
    count += o.count;
  }
};
std::vector<srd_sk_bin> srd_sk_bins(int64_t nbins);
/* adds the modes of rows [r0, r1) of the last axis (i2 in 3-D, i1 in 2-D); power holds those rows */
void srd_sk_bins_add(const srd_sk_geom &g, const double *power, int64_t r0, int64_t r1, srd_sk_bin *bins);
/* the shells' mean |k| and S (0 for an empty shell) and their mode counts */
void srd_sk_bins_out(srd_sk_bin *bins, int64_t nbins, double *k, double *sk, int64_t *count);
/* One mode of the half spectrum: its power from the transform's (re, im), and its shell b, |k| and
 * multiplicity (2 for 0 < i0 < n0 / 2: it stands for its conjugate too); false for k = 0. */
inline double srd_sk_mode_power(double re, double im, int64_t N) { return (re * re + im * im) / (double)N; }
inline bool srd_sk_mode(const srd_sk_geom &g, int i0, int i1, int i2, int64_t *b, double *kk, int *mult) {
  if (i0 == 0 && i1 == 0 && i2 == 0) return false;
  const int m1 = i1 <= g.n1 / 2 ? i1 : i1 - g.n1, m2 = i2 <= g.n2 / 2 ? i2 : i2 - g.n2;
  const double kx = 2 * M_PI * i0 / g.box[0], ky = 2 * M_PI * m1 / g.box[1],
               kz = g.dim == 3 ? 2 * M_PI * m2 / g.box[2] : 0.0;
  *kk = std::sqrt(kx * kx + ky * ky + kz * kz);
  *b = (int64_t)(*kk / g.w);
  if (*b >= g.nbins) *b = g.nbins - 1;
  *mult = (i0 == 0 || (g.n0 % 2 == 0 && i0 == g.n0 / 2)) ? 1 : 2;
  return true;
}

/* An observation's scalar inputs (the ledger, the clamps since the last observation, the stress
 * window) and its common part (engine.cpp): the ledger error, the warnings, the clamps and the
 * Lees-Edwards stress of ob, whose sums (momentum, energy, temperature) are filled already;
 * GRAN_ERR_NUMERIC when the energy or the momentum is not finite. */
struct srd_obs_scalars {
  double e_initial = 0, e_coll = 0, e_ext = 0, flux_kin = 0, flux_coll = 0, stress_t0 = 0, shear_rate = 0;
  double box[3] = {0, 0, 0};
  int dim = 3;
  int64_t clamped = 0;
  double dt_max = INFINITY;
};
int srd_obs_finish_(gran_srd_obs *ob, const srd_obs_scalars &q);
/* The sums of gran_srd_observe of the decomposable engine (creation by cells, CPU; bricks.cpp):
 * momentum, energy, temperature, e_kin, theta_cells, mach, sigma_rho and a2 as a split gas computes
 * them (srd_bricks_observe_), with one brick: every global sum exact, every cell's sums over its
 * particles in key order, so the same bits for any split; profile (NULL: none) as
 * srd_bricks_observe_profile_'s. */
int srd_observe_cells_(gran_srd *s, gran_srd_obs *ob, double *profile);
/* gran_srd_fields of the decomposable engine (bricks.cpp), as a split gas computes them
 * (srd_bricks_fields_): each cell's sums over its particles in key order, the same bits for any
 * split; any output NULL */
int srd_fields_cells_(gran_srd *s, double *count, double *velocity, double *temperature);

/* GRAN_SRD_PHASES=1 in the environment (read once): the step loops time their phases and print them
 * to stderr; srd_clock_s is their clock (seconds, monotonic). */
inline bool srd_phase_timing() {
  static const bool on = [] {
    const char *e = std::getenv("GRAN_SRD_PHASES");
    return e && e[0] == '1';
  }();
  return on;
}
inline double srd_clock_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/* Threads a run with option `threads` uses (engine.cpp): 0 the OpenMP default; at most 4 per
 * processor (the scene's memory estimate uses the same count). */
int srd_threads_used(int32_t threads);
/* GRAN_ERR_NUMERIC naming the first particle (in index order) whose position or velocity in the
 * host arrays is not finite, and `when` ("after the copy back from the device", ...); else
 * GRAN_SUCCESS (engine.cpp). */
int srd_check_finite(const gran_srd *s, const char *when);

/* engine.cpp: gran_srd_create's check of the options (GRAN_ERR_ARG naming the option), and the
 * geometry and arrays of a state from its checked options (no particles drawn); checkpoint.cpp
 * reads a state into them. */
int srd_check_options_(const gran_srd_options *o);
int srd_alloc_state_(gran_srd *s);
/* out[0 .. n) = streams first .. first + n - 1 of seed (gran_rng_stream's states): one stream
 * computed, the others by consecutive jumps through a byte table (engine.cpp) */
int srd_streams_(uint64_t seed, uint64_t first, int64_t n, gran_rng *out);
/* the geometry (gm, n, ncell, ncell_box) of a state from its checked options, without its arrays:
 * a decomposed run's process holds only its brick */
int srd_alloc_geometry_(gran_srd *s);

/* One brick's share of a split gas's state: a part of a checkpoint set (checkpoint.cpp writes and
 * reads it as the group /srd_part, format "granary-srd-part 1", of its own file; bricks.cpp makes
 * and consumes it). The brick `brick` of the split pgrid (its window of the binning grid follows
 * from them: srd_brick_cut), its particles in key order with their keys, its window's cells (V 3
 * and rng 4 words per cell, the window's own order, x fastest) and the scalar state every brick
 * holds alike; `generation` names the checkpoint that commits the set. clamped counts the clamps
 * since the start, clamped_obs and dt_max_obs those since the last observation. */
struct srd_part {
  int64_t generation = 0;
  int pgrid[3] = {1, 1, 1};
  int brick = 0;
  int64_t step = 0, clamped = 0, clamped_obs = 0;
  double time = 0, e_initial = 0, e_coll = 0, e_ext = 0, dt_max = INFINITY, dt_max_obs = INFINITY, flux_kin = 0,
         flux_coll = 0, stress_t0 = 0, wall_impulse[3] = {0, 0, 0};
  gran_rng shift_rng;
  std::vector<double> x, y, z, vx, vy, vz; /* z, vz empty in 2-D */
  std::vector<uint64_t> key;
  std::vector<double> V;
  std::vector<uint64_t> rng;
};
/* The first grid index of brick b of P along an axis of nc cells (b = P: nc): the split's bricks on
 * cell boundaries, sizes balanced (bricks.cpp cuts its grid with it). */
inline int64_t srd_brick_cut(int64_t b, int64_t nc, int64_t P) { return b * nc / P; }
/* Write part p of a gas with options opt to PATH (a state file of its own: built in memory,
 * committed with its checksum, src/io/state.h). */
int srd_part_write_(const gran_srd_options *opt, const srd_part &p, const char *path);
/* Read the part in PATH (its checksum verified first) for the gas `shell` (options, with the
 * replica's seed, and geometry: every stored physics option must equal its own): every value
 * checked as a checkpoint's are (srd_state_validate's checks on the part's share, the split and
 * the brick within the grid, the keys strictly increasing), each refusal GRAN_ERR_IO naming the
 * file and the field. */
int srd_part_read_(const char *path, const gran_srd *shell, srd_part *p);
/* The checks of a whole state's values (a checkpoint read, or the state merged from the parts of a
 * set), each refusal naming `path` and the field. */
int srd_state_check_(const char *path, const gran_srd *s);
#endif
