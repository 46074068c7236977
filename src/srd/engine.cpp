/* engine.cpp - GSRD CPU engine: set-up, the step loop, observables (checkpoints: checkpoint.cpp).
 *
 * One step: (1) draw the grid shift (stream 0); (2) stream, wall reflection, periodic/Lees-Edwards
 * wrap, kinetic momentum flux (parallel over fixed blocks of SRD_BLOCK particles), and each block
 * lists its particles by slab of the shifted binning grid (2 B per particle); (3) only with the
 * global thermostat: a pass over the slabs for its one factor; (4) per slab (parallel over slabs,
 * each slab's cells in thread-local records): the cell sums relative to the reference velocity,
 * each cell in particle order (bit for bit the same for any thread count), then per cell moments,
 * eps_eff, random axis, thermostat, virtual particles (each cell's own RNG stream), then
 * rotate-and-scale of the slab's particles. Per cell only the reference velocity (24 B) and the
 * RNG state (32 B) persist. Global sums use fixed blocks of SRD_BLOCK particles (streaming) or the
 * slabs (collisions) added in order (independent of the thread count).
 * The physics of the phases is the rules of src/srd/rules.h (srd_rule_move, srd_rule_thermal,
 * srd_rule_cell; srd_rule_collide written out in the collision loop, for the bits), the same
 * functions the devices call (cuda/srd.cu, the host reference in device_cuda.cpp); the loops here
 * iterate, store and add the partials up.
 * Templates: DIM, DISSIP (eps < 1 or thermostat), LE, WALL, ACCEL; they make the rules' effect mask
 * a compile-time constant (srd_rule_fx_fold), so an effect that is off is compiled out of the loops.
 */
#include "srd/srd_impl.h"
#include "srd/create.h"
#include "srd/bricks.h"
#include "srd/srd_limits.h"
#include "srd/rules.h"
#include "core/run_bounds.h"
#include "../cuda/srd_cuda.h" /* srd_rule_const_of: the rules' constants, as the devices make them */

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cerrno>
#include <cfloat>
#include <memory>
#include <string>
#include <unistd.h>
#include <fftw3.h>
#ifdef _OPENMP
#include <omp.h>
#endif
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>
#define SRD_HAVE_MXCSR 1
#endif

/* threads a run with option `threads` uses: 0 the OpenMP default; more than 4
 * per processor are reduced to that (results do not depend on the thread count; alloc_state warns) */
int srd_threads_used(int32_t threads) {
#ifdef _OPENMP
  if (threads <= 0) return omp_get_max_threads();
  const int cap = 4 * std::max(1, omp_get_num_procs());
  return threads > cap ? cap : threads;
#else
  (void)threads;
  return 1;
#endif
}

namespace {

int nthreads_of(const gran_srd *s) { return srd_threads_used(s->opt.threads); }

/* Subnormal arithmetic in the step: a gas cooled below T ~ 1e-305 has squared
 * velocities below the smallest normal double, which many CPUs compute 10-100x slower. Each thread's
 * share of a step's parallel loops runs with flush-to-zero and denormals-are-zero set (x86 MXCSR),
 * restored when it ends, so nothing outside the engine sees the mode. A normal run has no subnormal
 * operand or result, so its numbers are the same bit for bit; below T ~ 1e-305 the cells'
 * temperatures read 0 in the step (eps_eff = 1 there already: kappa ~ sqrt(theta) < 1e-150), and
 * gran_srd_observe (not flushed) warns. */
struct FtzScope {
#ifdef SRD_HAVE_MXCSR
  unsigned old;
  FtzScope() : old(_mm_getcsr()) { _mm_setcsr(old | 0x8040u); } /* FTZ (bit 15) | DAZ (bit 6) */
  ~FtzScope() { _mm_setcsr(old); }
#endif
};

/* ---- fast consecutive jumps: the jump polynomial as a byte-table linear map over GF(2) ----
 * jump(s) is linear in the 256 state bits: J s = XOR over set bits b of J e_b. Grouping the bits in
 * 32 bytes, t[p][v] = XOR of the columns of the bits set in v at byte p (32 x 256 x 32 B = 256 KiB,
 * in L2): one jump = 32 independent 32-byte look-ups instead of 256 xoshiro steps. */
struct JumpTab {
  uint64_t t[32][256][4];
};
const JumpTab *jump_tab() {
  static JumpTab *tab = nullptr;
  static std::once_flag once;
  std::call_once(once, [] {
    JumpTab *jt = new JumpTab;
    uint64_t col[256][4];
    for (int b = 0; b < 256; ++b) {
      gran_rng r;
      std::memset(&r, 0, sizeof r);
      r.s[b / 64] = 1ull << (b % 64);
      gran_rng_jump(&r);
      std::memcpy(col[b], r.s, sizeof r.s);
    }
    for (int p = 0; p < 32; ++p) {
      std::memset(jt->t[p][0], 0, sizeof jt->t[p][0]);
      for (int v = 1; v < 256; ++v) {
        const int low = __builtin_ctz(v);
        for (int w = 0; w < 4; ++w) jt->t[p][v][w] = jt->t[p][v & (v - 1)][w] ^ col[p * 8 + low][w];
      }
    }
    tab = jt;
  });
  return tab;
}
inline void fast_jump(const JumpTab *jt, gran_rng *r) {
  uint64_t o[4] = {0, 0, 0, 0};
  for (int p = 0; p < 32; ++p) {
    const unsigned byte = (unsigned)(r->s[p / 8] >> (8 * (p % 8))) & 255u;
    const uint64_t *e = jt->t[p][byte];
    o[0] ^= e[0];
    o[1] ^= e[1];
    o[2] ^= e[2];
    o[3] ^= e[3];
  }
  std::memcpy(r->s, o, sizeof o);
}

}  // namespace

int srd_streams_(uint64_t seed, uint64_t first, int64_t n, gran_rng *out) {
  if (n <= 0) return GRAN_SUCCESS;
  gran_rng r;
  GRAN_CALL(gran_rng_stream(seed, first, &r));
  const JumpTab *jt = jump_tab();
  for (int64_t c = 0; c < n; ++c) {
    out[c] = r;
    if (c + 1 < n) fast_jump(jt, &r);
  }
  return GRAN_SUCCESS;
}

namespace {

/* Streams 1..ncell for the cells: consecutive jumps in parallel blocks. */
int setup_streams(gran_srd *s) {
  const int64_t nc = s->ncell;
  /* the states do not depend on the blocking (each is stream c + 1 exactly); gran_rng_stream costs
   * O(log id) polynomial products, so few blocks: 4 per thread */
  const int64_t nb = std::max<int64_t>(1, std::min<int64_t>(4 * nthreads_of(s), nc / 4096));
  int err = GRAN_SUCCESS;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nthreads_of(s))
  for (int64_t b = 0; b < nb; ++b) {
    const int64_t lo = nc * b / nb, hi = nc * (b + 1) / nb;
    if (srd_streams_(s->opt.seed, (uint64_t)lo + 1, hi - lo, s->rng.data() + lo) != GRAN_SUCCESS) {
#pragma omp atomic write
      err = GRAN_ERR_INTERNAL;
      continue;
    }
    /* self-check: the block's last state is stream hi of the seed (catches a wrong table) */
    gran_rng chk;
    if (hi > lo && (gran_rng_stream(s->opt.seed, (uint64_t)hi, &chk) != GRAN_SUCCESS ||
                    std::memcmp(chk.s, s->rng[hi - 1].s, sizeof chk.s) != 0)) {
#pragma omp atomic write
      err = GRAN_ERR_INTERNAL;
    }
  }
  GRAN_CHECK(err == GRAN_SUCCESS, GRAN_ERR_INTERNAL, "cell RNG stream set-up failed");
  return gran_rng_stream(s->opt.seed, 0, &s->shift_rng);
}

/* Developer phase timers: with GRAN_SRD_PHASES=1 in the environment every gran_srd_advance of the CPU
 * engine prints to stderr the time of its phases per particle-step: the streaming pass with the
 * blocks' slab lists, the global thermostat's pass, the cell sums (binning included), the cell
 * rules, the rotation, the sort by cell. The three slab phases are thread-seconds summed over the
 * threads; on one thread the phases add up to the step. Off (the default): one test per phase and
 * step, no clock read. */
enum { PH_STREAM, PH_THERMO, PH_SUMS, PH_CELLS, PH_ROT, PH_SORT, PH_N };

/* deterministic sum of per-block partials */
inline double sum_blocks(const double *p, int64_t nb) {
  double t = 0.0;
  for (int64_t b = 0; b < nb; ++b) t += p[b];
  return t;
}
/* the same for the three partials each block keeps in part[4 b .. 4 b + 2], in block order */
inline void sum_blocks3(const double *part, int64_t nb, double t[3]) {
  t[0] = t[1] = t[2] = 0.0;
  for (int64_t b = 0; b < nb; ++b) {
    t[0] += part[4 * b];
    t[1] += part[4 * b + 1];
    t[2] += part[4 * b + 2];
  }
}

/* The first particle of [lo, hi) whose position or velocity is not finite after its move, coded
 * as i 32 + component 4 + kind (component 0..5 = x y z vx vy vz, a velocity before a position: a
 * NaN velocity makes the position NaN too; kind 0 NaN, 1 +inf, 2 -inf); -1 when none. */
double first_nonfinite(const double *px, const double *py, const double *pz, const double *vx, const double *vy,
                       const double *vz, int64_t lo, int64_t hi) {
  for (int64_t i = lo; i < hi; ++i) {
    const double a[6] = {px[i], py[i], pz ? pz[i] : 0.0, vx[i], vy[i], vz ? vz[i] : 0.0};
    static const int order[6] = {3, 4, 5, 0, 1, 2};
    for (int q : order)
      if (!std::isfinite(a[q])) return (double)(i * 32 + q * 4 + (std::isnan(a[q]) ? 0 : a[q] > 0 ? 1 : 2));
  }
  return -1.0;
}

/* GRAN_ERR_NUMERIC for the particle of first_nonfinite's code, found in step `step` + 1 */
int report_nonfinite(int64_t step, double code) {
  const int64_t c = (int64_t)code, i = c / 32, comp = (c / 4) % 8, kind = c % 4;
  static const char *const names[6] = {"x", "y", "z", "vx", "vy", "vz"};
  static const char *const kinds[3] = {"nan", "inf", "-inf"};
  return GRAN_ERROR(GRAN_ERR_NUMERIC,
                    "GSRD step %lld: particle %lld has a non-finite %s (%s) after its move (a value written through "
                    "gran_srd_particles, made by the step before, or an overflow of x += v dt); the run cannot continue",
                    (long long)step + 1, (long long)i, names[comp < 6 ? comp : 0], kinds[kind < 3 ? kind : 0]);
}

/* The particles in the order of their cell of the grid gm shifted by sh (counting sort, stable):
 * the cell sums and the rotation then read them nearly in order. Done every sort_every steps
 * under that step's shift, and once at creation under no shift (an unsorted step costs several
 * sorted ones: the particles of a cell are scattered over the whole arrays). */
void sort_by_cell(gran_srd *s, const srd_geom *gm, const double sh[3], int nth) {
  const int64_t n = s->n, ncell = s->ncell;
  const int dim = s->opt.dim;
  const double *px = s->x.data(), *py = s->y.data(), *pz = dim == 3 ? s->z.data() : nullptr;
  std::vector<uint32_t> perm((size_t)n); /* first the cell of each particle, then the order */
#pragma omp parallel for schedule(static) num_threads(nth)
  for (int64_t i = 0; i < n; ++i) {
    const double p[3] = {px[i], py[i], dim == 3 ? pz[i] : 0.0};
    double dvx;
    perm[i] = (uint32_t)srd_bin(gm, sh, p, &dvx);
  }
  std::vector<int64_t> start((size_t)ncell + 1, 0);
  for (int64_t i = 0; i < n; ++i) start[perm[i] + 1]++;
  for (int64_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
  std::vector<uint32_t> order((size_t)n);
  for (int64_t i = 0; i < n; ++i) order[start[perm[i]]++] = (uint32_t)i;
  perm.swap(order);
  std::vector<uint32_t>().swap(order); /* the cells: not needed now (peak 4 B per particle less) */
  std::vector<int64_t>().swap(start);
  std::vector<double> tmp((size_t)n);
  std::vector<double> *arr[6] = {&s->x, &s->y, &s->z, &s->vx, &s->vy, &s->vz};
  for (int q = 0; q < 6; ++q) {
    if (dim == 2 && (q == 2 || q == 5)) continue;
    std::vector<double> &A = *arr[q];
#pragma omp parallel for schedule(static) num_threads(nth)
    for (int64_t i = 0; i < n; ++i) tmp[i] = A[perm[i]];
    A.swap(tmp);
  }
}

/* srd_bin_layer with the step loop's template flags (DIM, WALL: gm->dim, gm->wall_axis >= 0) as
 * constants: the same operations on the same values, without the run-time tests of the generic form.
 * (The cell sums keep the generic srd_bin: with a templated copy there GCC fuses the multiply-adds of
 * the 3-D rotation with dissipation differently, which moved some velocities by an ulp.) */
template <bool WALL>
inline int64_t bin_axis(const srd_geom &g, int k, double x) {
  if (WALL && k == g.wall_axis) return srd_clamp_bin(x * g.inv_a, g.L[k] + 1); /* layers 0 .. L */
  return srd_clamp_bin(srd_wrap_shifted(x, g.box[k]) * g.inv_a, g.L[k]);
}
template <int DIM, bool WALL>
inline int64_t bin_layer(const srd_geom &g, const double sh[3], const double p[3]) {
  if (DIM == 2) {
    int w;
    return srd_bin_y(&g, sh, p, &w);
  }
  return bin_axis<WALL>(g, 2, p[2] + sh[2]);
}

template <int DIM, bool DISSIP, bool LE, bool WALL, bool ACCEL>
int do_steps(gran_srd *s, int64_t nsteps) {
  const int64_t n = s->n, ncell = s->ncell;
  const int nth = nthreads_of(s);
  const int64_t nb = (n + SRD_BLOCK - 1) / SRD_BLOCK;
  s->part.assign((size_t)nb * 4, 0.0);
  double *px = s->x.data(), *py = s->y.data(), *pz = DIM == 3 ? s->z.data() : nullptr;
  double *vx = s->vx.data(), *vy = s->vy.data(), *vz = DIM == 3 ? s->vz.data() : nullptr;
  srd_cpu_cell *cell = s->cell.data();
  gran_rng *rng = s->rng.data();
  const gran_srd_options &o = s->opt;
  const double dt = o.dt;
  /* the rules' constants (the devices make theirs the same way) and the effect mask, in which the
   * template flags are compile-time constants: an effect that is off folds out of the loops. The
   * mask is made inside each parallel loop and lambda (srd_rule_fx_fold of the constexpr FX_FIXED):
   * a local shared into an OpenMP region or captured is a run-time value there, and the rules'
   * branches (and the multiply-adds the compiler fuses across them) would no longer fold. */
  const gran_cuda_srd_params prm = srd_params_of(s);
  const srd_rule_const K = srd_rule_const_of(&prm);
  constexpr int32_t FX_FIXED = (ACCEL ? SRD_FX_ACCEL : 0) | (WALL ? SRD_FX_WALL : 0) | (LE ? SRD_FX_LE : 0) |
                               (DISSIP ? SRD_FX_DISSIP : 0);
  double *part = s->part.data();
  /* slabs of the binning grid: runs of whole layers along its slowest axis (z in 3-D, y in 2-D), the
   * cells of a slab a contiguous index range. A slab holds about SRD_SLAB_CELLS cells (its
   * particles are then read nearly in order from the few blocks that hold them, and its particles
   * stay in cache between the sums and the rotation), but no slab is thicker than 1 / SRD_MIN_SLABS
   * of the layers (rounded up), and there are at most SRD_MAX_SLABS. The slabs depend on the geometry
   * only, never on the thread count. */
  const int64_t nlayer = s->gm.nc[DIM - 1], layer_cells = ncell / nlayer;
  int64_t lps = std::min((SRD_SLAB_CELLS + layer_cells - 1) / layer_cells, (nlayer + SRD_MIN_SLABS - 1) / SRD_MIN_SLABS);
  lps = std::max<int64_t>({lps, 1, (nlayer + SRD_MAX_SLABS - 1) / SRD_MAX_SLABS});
  const int64_t slab_cells = lps * layer_cells, nslab = (nlayer + lps - 1) / lps;
  std::vector<uint8_t> layer_slab((size_t)nlayer); /* slab of each layer (nslab <= 256) */
  for (int64_t l = 0; l < nlayer; ++l) layer_slab[(size_t)l] = (uint8_t)(l / lps);
  const int64_t srow = nslab + 1; /* slab starts per block */
  s->slab_list.resize((size_t)n);
  s->slab_off.resize((size_t)(nb * srow));
  uint16_t *list = s->slab_list.data(), *off = s->slab_off.data();
  std::vector<double> spart((size_t)nslab * 4, 0.0); /* per-slab partials of the collisions */
  std::vector<std::vector<srd_slab_cell>> work((size_t)nth); /* per-thread slab cell records */
  /* the particles of slab sl in increasing index order (blocks in order, each block's list in
   * increasing order), handed to f in chunks of up to SRD_CHUNK indices */
  auto slab_chunks = [&](int64_t sl, auto &&f) {
    int64_t ib[SRD_CHUNK];
    int64_t m = 0;
    for (int64_t b = 0; b < nb; ++b) {
      const uint16_t *row = off + b * srow;
      const int64_t base = b * SRD_BLOCK;
      for (int64_t k = row[sl]; k < row[sl + 1]; ++k) {
        ib[m++] = base + list[base + k];
        if (m == SRD_CHUNK) {
          f(ib, m);
          m = 0;
        }
      }
    }
    if (m > 0) f(ib, m);
  };
  /* the cell sums of slab sl (cells c0 ..) into W: every cell adds its particles in increasing
   * particle order, so the sums are bit for bit those of one serial pass, for any thread count.
   * The cells of a chunk are computed first (no dependence between them), then the additions
   * (whose chain through a cell's sums is what the core waits for). */
  auto slab_sums = [&](int64_t sl, int64_t c0, int64_t mc, srd_slab_cell *W, const srd_geom *gp, const double *sh,
                       uint32_t *pc) {
    for (int64_t c = 0; c < mc; ++c) srd_sum_clear(&W[c].s);
    const srd_geom g = *gp; /* a local copy: its fields stay in registers */
    int64_t done = 0;
    slab_chunks(sl, [&](const int64_t *ib, int64_t m) {
      uint32_t cidx[SRD_CHUNK];
      double cdv[SRD_CHUNK];
      for (int64_t j = 0; j < m; ++j) {
        const int64_t i = ib[j];
        const double p[3] = {px[i], py[i], DIM == 3 ? pz[i] : 0.0};
        cidx[j] = (uint32_t)(srd_bin(&g, sh, p, &cdv[j]) - c0);
      }
      for (int64_t j = 0; j < m; ++j) {
        const int64_t i = ib[j];
        double v[3] = {vx[i], vy[i], DIM == 3 ? vz[i] : 0.0};
        if (LE) v[0] += cdv[j];
        srd_sum_add(&W[cidx[j]].s, v, cell[c0 + cidx[j]].V, DIM);
      }
      if (pc) /* the cells for the rotation; the top bit: seen across the Lees-Edwards boundary */
        for (int64_t j = 0; j < m; ++j) pc[done + j] = cidx[j] | (LE && cdv[j] != 0.0 ? 0x80000000u : 0u);
      done += m;
    });
  };
  /* particles in slab sl */
  auto slab_count = [&](int64_t sl) {
    int64_t k = 0;
    for (int64_t b = 0; b < nb; ++b) k += off[b * srow + sl + 1] - off[b * srow + sl];
    return k;
  };
  std::vector<std::vector<uint32_t>> pcell((size_t)nth); /* per thread: the slab's particles' cells */
  const bool prof = srd_phase_timing();
  double ph[PH_N] = {0, 0, 0, 0, 0, 0}, tq = prof ? srd_clock_s() : 0.0;
  auto lap = [&](int k) { /* the time since the previous lap goes to phase k */
    const double t = srd_clock_s();
    ph[k] += t - tq;
    tq = t;
  };

  for (int64_t st = 0; st < nsteps; ++st) {
    srd_geom gm = s->gm;
    if (LE) { /* offset at the end of the step: exact for a crossing at any time inside it */
      double dx = std::fmod(o.shear_rate * gm.box[1] * (s->time + dt), gm.box[0]);
      if (dx < 0) dx += gm.box[0];
      gm.le_dx = dx;
    }
    if (WALL) {
      gm.wall_u_lo = o.vib_amp * o.vib_omega * std::cos(o.vib_omega * (s->time + dt));
    }
    /* (1) grid shift of this step's collision (stream 0, which nothing else draws from: drawn
     * before the streaming so that the streaming pass can bin under it) */
    for (int k = 0; k < 3; ++k) s->shift[k] = k < DIM ? srd_rng_uniform(&s->shift_rng) * o.a : 0.0;
    const double sh[3] = {s->shift[0], s->shift[1], s->shift[2]};
    if (prof) tq = srd_clock_s();
    /* (2) stream; each fixed block of SRD_BLOCK particles then lists its particles by slab of the
     * shifted binning grid (a counting sort inside the block, increasing order in each slab) */
    {
#pragma omp parallel for schedule(static) num_threads(nth)
      for (int64_t b = 0; b < nb; ++b) {
        FtzScope ftz;
        const int32_t fx = srd_rule_fx_fold(FX_FIXED, K.fx);
        const srd_geom g = gm; /* a local copy: its fields stay in registers across the stores */
        const int64_t lo = b * SRD_BLOCK, hi = std::min(n, lo + SRD_BLOCK);
        double acc[SRD_ACC_N] = {0, 0, 0, 0, 0, 0, 0}; /* the block's kinetic flux, external work, wall impulse */
        double chk = 0.0;
        uint16_t *row = off + b * srow;
        for (int64_t k = 0; k < srow; ++k) row[k] = 0;
        uint32_t sid[SRD_BLOCK];
        for (int64_t i = lo; i < hi; ++i) {
          double p[3] = {px[i], py[i], DIM == 3 ? pz[i] : 0.0};
          double v[3] = {vx[i], vy[i], DIM == 3 ? vz[i] : 0.0};
          srd_rule_move(fx, DIM, &K, &g, p, v, acc);
          /* the per-step finiteness check, branch-free: the positions after the move are in the
           * box when finite (sum <= 3e290), and a non-finite position or velocity leaves a
           * non-finite position (x += v dt; the wrap and the walls keep it so) */
          chk += p[0] + p[1] + p[2];
          px[i] = p[0];
          py[i] = p[1];
          vx[i] = v[0];
          vy[i] = v[1];
          if (DIM == 3) {
            pz[i] = p[2];
            vz[i] = v[2];
          }
          const uint32_t sl = layer_slab[bin_layer<DIM, WALL>(g, sh, p)];
          sid[i - lo] = sl;
          row[sl + 1] += 1;
        }
        for (int64_t k = 1; k < srow; ++k) row[k] = (uint16_t)(row[k] + row[k - 1]);
        uint16_t cur[SRD_MAX_SLABS + 1];
        for (int64_t k = 0; k < nslab; ++k) cur[k] = row[k];
        for (int64_t i = lo; i < hi; ++i) list[lo + cur[sid[i - lo]]++] = (uint16_t)(i - lo);
        part[4 * b] = acc[SRD_ACC_FLUX];
        part[4 * b + 1] = acc[SRD_ACC_EXT];
        part[4 * b + 2] = acc[SRD_ACC_IMP];
        part[4 * b + 3] = chk - chk != 0.0 ? first_nonfinite(px, py, pz, vx, vy, vz, lo, hi) : -1.0;
      }
      for (int64_t b = 0; b < nb; ++b) /* the first non-finite particle, in particle order */
        if (part[4 * b + 3] >= 0.0) return report_nonfinite(s->step, part[4 * b + 3]);
      if (LE || ACCEL || WALL) {
        double t[3]; /* kinetic flux, external work, wall impulse */
        sum_blocks3(part, nb, t);
        s->flux_kin += t[0];
        s->e_ext += t[1];
        if (WALL) s->wall_impulse[gm.wall_axis] += t[2];
      }
    }
    if (prof) lap(PH_STREAM);
    s->time += dt;
    /* (3) global profile-unbiased thermostat (thermostat = 2): one factor for the thermal
     * velocities of every cell, relative to the cell means (so the shear profile is not heated or
     * cooled), that makes the thermal energy d T0 sum (n_c - 1) / 2. It needs every cell's sums
     * before any cell collides: a first pass over the slabs (only with this thermostat) sums the
     * cells and adds their thermal energies per slab; the slab partials are added in slab order
     * (the same factor for any thread count). */
    double gscale = 1.0;
    if (srd_rule_fx_fold(FX_FIXED, K.fx) & SRD_FX_GTHERMO) {
      std::vector<double> tp((size_t)nslab * 2, 0.0);
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth)
      for (int64_t sl = 0; sl < nslab; ++sl) {
        FtzScope ftz;
#ifdef _OPENMP
        std::vector<srd_slab_cell> &W = work[(size_t)omp_get_thread_num()];
#else
        std::vector<srd_slab_cell> &W = work[0];
#endif
        if ((int64_t)W.size() < slab_cells) W.resize((size_t)slab_cells);
        const int64_t c0 = sl * slab_cells, mc = std::min(ncell, c0 + slab_cells) - c0;
        slab_sums(sl, c0, mc, W.data(), &gm, sh, nullptr);
        double e = 0.0, dof = 0.0;
        for (int64_t c = 0; c < mc; ++c) {
          double ec, dc;
          if (!srd_rule_thermal(DIM, &W[c].s, cell[c0 + c].V, &ec, &dc)) continue;
          e += ec;
          dof += dc;
        }
        tp[2 * sl] = e;
        tp[2 * sl + 1] = dof;
      }
      double e = 0.0, dof = 0.0;
      for (int64_t sl = 0; sl < nslab; ++sl) {
        e += tp[2 * sl];
        dof += tp[2 * sl + 1];
      }
      gscale = srd_rule_gscale(e, dof, K.T0);
      if (prof) lap(PH_THERMO);
    }
    /* (4) collision, slab by slab (parallel over slabs): the slab's cell sums relative to the
     * reference velocities, then per cell the moments, eps_eff, random axis (the cell's own RNG
     * stream), thermostat and virtual particles into the slab's thread-local records (the new
     * mean becomes the cell's reference), then rotate-and-scale of the slab's particles. Only the
     * reference velocities and the RNG states persist per cell. */
    int64_t nclamp = 0;
    double dtmax = INFINITY;
    double ph_sums = 0.0, ph_cells = 0.0, ph_rot = 0.0;
#pragma omp parallel for schedule(dynamic, 1) num_threads(nth) reduction(+ : nclamp, ph_sums, ph_cells, ph_rot) \
    reduction(min : dtmax)
    for (int64_t sl = 0; sl < nslab; ++sl) {
      FtzScope ftz;
      double t0 = prof ? srd_clock_s() : 0.0;
#ifdef _OPENMP
      std::vector<srd_slab_cell> &Wv = work[(size_t)omp_get_thread_num()];
#else
      std::vector<srd_slab_cell> &Wv = work[0];
#endif
      if ((int64_t)Wv.size() < slab_cells) Wv.resize((size_t)slab_cells);
      srd_slab_cell *W = Wv.data();
      const int64_t c0 = sl * slab_cells, mc = std::min(ncell, c0 + slab_cells) - c0;
#ifdef _OPENMP
      std::vector<uint32_t> &pcv = pcell[(size_t)omp_get_thread_num()];
#else
      std::vector<uint32_t> &pcv = pcell[0];
#endif
      const int64_t np = slab_count(sl);
      if ((int64_t)pcv.size() < np) pcv.resize((size_t)np);
      uint32_t *pc = pcv.data();
      slab_sums(sl, c0, mc, W, &gm, sh, pc);
      if (prof) {
        const double t1 = srd_clock_s();
        ph_sums += t1 - t0;
        t0 = t1;
      }
      const int32_t fx = srd_rule_fx_fold(FX_FIXED, K.fx);
      for (int64_t lc = 0; lc < mc; ++lc) {
        /* the sums are read into locals, then the same slot receives the collision record; its
         * V (the cell mean, or the old reference in an empty cell) is next step's reference */
        const srd_cell_sum csum = W[lc].s;
        srd_cell_rot cr;
        int cl;
        double dtm;
        srd_rule_cell(fx, DIM, &K, &gm, sh, c0 + lc, &csum, gscale, cell[c0 + lc].V, &rng[c0 + lc], &cr, &cl, &dtm);
        if (cl) {
          ++nclamp;
          dtmax = std::min(dtmax, dtm);
        }
        W[lc].rot = cr;
      }
      if (prof) {
        const double t1 = srd_clock_s();
        ph_cells += t1 - t0;
        t0 = t1;
      }
      /* the collisions of the slab's particles (in the same order: their cells from slab_sums) */
      double acc[SRD_ACC_N] = {0, 0, 0, 0, 0, 0, 0}; /* the slab's energy change, virial, Lees-Edwards work */
      int64_t done = 0;
      slab_chunks(sl, [&](const int64_t *ib, int64_t m) {
        const uint32_t *pcc = pc + done;
        done += m;
        for (int64_t j = 0; j < m; ++j) {
          const int64_t i = ib[j];
          double v[3] = {vx[i], vy[i], DIM == 3 ? vz[i] : 0.0};
          const double dvx = LE && (pcc[j] & 0x80000000u) ? -gm.le_dv : 0.0;
          /* srd_rule_collide of rules.h, written out with the template flags: the compiler's
           * choice to inline srd_rotate here or not decides which multiply-adds it fuses, and that
           * choice differs when the flags reach the loop through srd_rule_collide (3-D runs with
           * dissipation then differ in the last bits from every earlier result). t890 compares this
           * loop with srd_rule_collide on the reference device (the same to rounding). */
          const srd_cell_rot &cr = W[pcc[j] & 0x7fffffffu].rot;
          if (LE) v[0] += dvx;
          const double e0 = DISSIP || WALL ? v[0] * v[0] + v[1] * v[1] + v[2] * v[2] : 0.0;
          const double vx0 = v[0];
          if (cr.r[0] != 0.0 || cr.r[1] != 0.0 || cr.r[2] != 0.0) srd_rotate(v, &cr, K.ca, K.sa, DIM, DISSIP);
          if (DISSIP || WALL) acc[SRD_ACC_DE] += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - e0);
          if (LE) {
            const double yy = (dvx != 0.0) ? py[i] - gm.box[1] : py[i];
            acc[SRD_ACC_VIR] += (v[0] - vx0) * yy;
            acc[SRD_ACC_LEW] -= dvx * (v[0] - vx0);
            v[0] -= dvx;
          }
          vx[i] = v[0];
          vy[i] = v[1];
          if (DIM == 3) vz[i] = v[2];
        }
      });
      spart[(size_t)(4 * sl)] = acc[SRD_ACC_DE];
      spart[(size_t)(4 * sl + 1)] = acc[SRD_ACC_VIR];
      spart[(size_t)(4 * sl + 2)] = acc[SRD_ACC_LEW];
      if (prof) ph_rot += srd_clock_s() - t0;
    }
    if (prof) {
      ph[PH_SUMS] += ph_sums;
      ph[PH_CELLS] += ph_cells;
      ph[PH_ROT] += ph_rot;
      tq = srd_clock_s();
    }
    s->clamped += nclamp;
    s->dt_max = std::min(s->dt_max, dtmax);
    if (DISSIP || LE || WALL) {
      double t[3]; /* collision energy, virial, Lees-Edwards work (slab partials in slab order) */
      sum_blocks3(spart.data(), nslab, t);
      s->e_coll += t[0];
      s->flux_coll += t[1];
      s->e_ext += t[2];
    }
    s->step += 1;
    if (o.sort_every > 0 && s->step % o.sort_every == 0) {
      sort_by_cell(s, &gm, sh, nth);
      px = s->x.data();
      py = s->y.data();
      pz = DIM == 3 ? s->z.data() : nullptr;
      vx = s->vx.data();
      vy = s->vy.data();
      vz = DIM == 3 ? s->vz.data() : nullptr;
      if (prof) lap(PH_SORT);
    }
  }
  if (prof && nsteps > 0) {
    const double u = 1e9 / ((double)n * (double)nsteps);
    std::fprintf(stderr,
                 "GSRD phases, ns per particle-step (%lld steps, %lld particles, %d threads): stream + slab lists %.2f, "
                 "thermostat pass %.2f, cell sums %.2f, cell rules %.2f, rotation %.2f, sort %.2f (slab phases in "
                 "thread-seconds)\n",
                 (long long)nsteps, (long long)n, nth, ph[PH_STREAM] * u, ph[PH_THERMO] * u, ph[PH_SUMS] * u,
                 ph[PH_CELLS] * u, ph[PH_ROT] * u, ph[PH_SORT] * u);
  }
  return GRAN_SUCCESS;
}

typedef int (*step_fn)(gran_srd *, int64_t);

template <int DIM, bool D, bool LE, bool W>
step_fn pick4(bool acc) {
  return acc ? do_steps<DIM, D, LE, W, true> : do_steps<DIM, D, LE, W, false>;
}
template <int DIM, bool D, bool LE>
step_fn pick3(bool w, bool acc) {
  return w ? pick4<DIM, D, LE, true>(acc) : pick4<DIM, D, LE, false>(acc);
}
template <int DIM, bool D>
step_fn pick2(bool le, bool w, bool acc) {
  return le ? pick3<DIM, D, true>(w, acc) : pick3<DIM, D, false>(w, acc);
}
template <int DIM>
step_fn pick1(bool d, bool le, bool w, bool acc) {
  return d ? pick2<DIM, true>(le, w, acc) : pick2<DIM, false>(le, w, acc);
}

int check_options(const gran_srd_options *o) {
  GRAN_CHECK(o->dim == 2 || o->dim == 3, GRAN_ERR_ARG, "option 'dim' must be 2 or 3 (got %d)", (int)o->dim);
  for (int k = 0; k < o->dim; ++k)
    GRAN_CHECK(o->cells[k] >= 1 && o->cells[k] <= (1 << 20), GRAN_ERR_ARG,
               "option 'cells[%d]' must be in [1, 2^20] (got %lld)", k, (long long)o->cells[k]);
  GRAN_CHECK(std::isfinite(o->a) && o->a > 0, GRAN_ERR_ARG, "option 'a' must be > 0 (got %g)", o->a);
  GRAN_CHECK(std::isfinite(o->n0) && o->n0 > 0, GRAN_ERR_ARG, "option 'n0' must be > 0 (got %g)", o->n0);
  GRAN_CHECK(std::isfinite(o->dt) && o->dt > 0, GRAN_ERR_ARG, "option 'dt' must be > 0 (got %g)", o->dt);
  GRAN_CHECK(o->dt >= DBL_MIN, GRAN_ERR_ARG,
             "option 'dt' must be at least %g, the smallest normal double (got the subnormal %g: the stress and the "
             "ledger divide by multiples of it)",
             DBL_MIN, o->dt);
  GRAN_CHECK(std::isfinite(o->alpha_deg) && o->alpha_deg > 0 && o->alpha_deg <= 180, GRAN_ERR_ARG,
             "option 'alpha' must be in (0, 180] degrees (got %g)", o->alpha_deg);
  GRAN_CHECK(std::isfinite(o->eps) && o->eps >= 0 && o->eps <= 1, GRAN_ERR_ARG,
             "option 'eps' must be in [0, 1] (got %g)", o->eps);
  GRAN_CHECK(std::isfinite(o->sigma) && o->sigma >= 0, GRAN_ERR_ARG, "option 'sigma' must be >= 0 (got %g)", o->sigma);
  GRAN_CHECK(std::isfinite(o->T0) && o->T0 > 0, GRAN_ERR_ARG, "option 'T0' must be > 0 (got %g)", o->T0);
  GRAN_CHECK(std::isfinite(o->shear_rate), GRAN_ERR_ARG, "option 'shear_rate' is not finite");
  GRAN_CHECK(o->shear_rate == 0 || o->dim >= 2, GRAN_ERR_ARG, "option 'shear_rate' needs dim >= 2");
  GRAN_CHECK(o->wall_axis >= -1 && o->wall_axis < o->dim, GRAN_ERR_ARG,
             "option 'wall_axis' must be -1 or an axis < dim (got %d)", (int)o->wall_axis);
  GRAN_CHECK(o->wall_axis < 0 || o->wall_rule == 1 || o->wall_rule == 2, GRAN_ERR_ARG,
             "option 'wall_rule' must be 1 (no-slip) or 2 (slip) (got %d)", (int)o->wall_rule);
  GRAN_CHECK(!(o->shear_rate != 0 && (o->wall_axis == 1 || o->wall_axis == 0)), GRAN_ERR_ARG,
             "options 'shear_rate' and 'wall_axis' = %d: walls and Lees-Edwards shear on the same axis", (int)o->wall_axis);
  for (int k = 0; k < 3; ++k) GRAN_CHECK(std::isfinite(o->accel[k]), GRAN_ERR_ARG, "option 'accel[%d]' is not finite", k);
  GRAN_CHECK(std::isfinite(o->vib_amp) && std::isfinite(o->vib_omega), GRAN_ERR_ARG, "option 'vib_amp'/'vib_omega' not finite");
  GRAN_CHECK((o->vib_amp == 0 && o->vib_omega == 0) || o->wall_axis >= 0, GRAN_ERR_ARG,
             "option 'vib_amp' (and 'vib_omega') needs walls (wall_axis >= 0; got vib_amp %g, vib_omega %g)", o->vib_amp,
             o->vib_omega);
  GRAN_CHECK(std::isfinite(o->wall_T) && o->wall_T >= 0, GRAN_ERR_ARG, "option 'wall_T' must be >= 0");
  GRAN_CHECK(o->thermostat >= 0 && o->thermostat <= 2, GRAN_ERR_ARG,
             "option 'thermostat' must be 0 (off), 1 (cell-level) or 2 (global, profile-unbiased) (got %d)",
             (int)o->thermostat);
  GRAN_CHECK(o->sort_every >= 0, GRAN_ERR_ARG, "option 'sort_every' must be >= 0");
  GRAN_CHECK(o->creation == GRAN_SRD_CREATE_SERIAL || o->creation == GRAN_SRD_CREATE_CELLS, GRAN_ERR_ARG,
             "option 'creation' must be 0 (GRAN_SRD_CREATE_SERIAL) or 1 (GRAN_SRD_CREATE_CELLS) (got %d)",
             (int)o->creation);
  GRAN_CHECK(o->threads >= 0 && o->threads <= SRD_MAX_THREADS, GRAN_ERR_ARG,
             "option 'threads' must be in 0..%d (0: all processors; got %d)", SRD_MAX_THREADS, (int)o->threads);
  /* derived values (srd_limits.h): displacements per step, energies, densities, kappa, float range */
  srd_limit_fail lf;
  GRAN_CHECK(srd_check_limits(*o, -1.0, &lf), GRAN_ERR_ARG, "option '%s': %s", lf.key, lf.why.c_str());
  return GRAN_SUCCESS;
}

/* geometry and, with arrays, the particle and cell arrays from the options (no particles drawn) */
int alloc_state(gran_srd *s, bool arrays = true) {
  const gran_srd_options &o = s->opt;
  srd_geom &g = s->gm;
  std::memset(&g, 0, sizeof g);
  g.dim = o.dim;
  g.wall_axis = o.wall_axis;
  g.wall_rule = o.wall_axis >= 0 ? o.wall_rule : SRD_WALL_NONE;
  g.le_on = o.shear_rate != 0 ? 1 : 0;
  g.a = o.a;
  g.inv_a = 1.0 / o.a;
  s->ncell_box = 1;
  s->ncell = 1;
  for (int k = 0; k < 3; ++k) {
    g.L[k] = k < o.dim ? o.cells[k] : 1;
    g.nc[k] = g.L[k] + (k == o.wall_axis ? 1 : 0);
    g.box[k] = k < o.dim ? (double)g.L[k] * o.a : o.a;
    s->ncell_box *= g.L[k];
    s->ncell *= g.nc[k];
  }
  g.le_dv = o.shear_rate * g.box[1];
  GRAN_CHECK(s->ncell < (int64_t)UINT32_MAX, GRAN_ERR_ARG, "options 'cells': %lld cells exceed 2^32",
             (long long)s->ncell);
  /* a slab's cell indices take 31 bits in the step (the top bit marks the Lees-Edwards image) */
  GRAN_CHECK(s->ncell / g.nc[o.dim - 1] < ((int64_t)1 << 30), GRAN_ERR_ARG,
             "options 'cells': a layer of %lld cells across the last axis exceeds 2^30",
             (long long)(s->ncell / g.nc[o.dim - 1]));
  const double nn = std::floor(o.n0 * (double)s->ncell_box + 0.5);
  GRAN_CHECK(nn >= 1 && nn < 4e9, GRAN_ERR_ARG, "options 'n0' x 'cells' give %g particles (need 1 .. 4e9)", nn);
  s->n = (int64_t)nn;
  if (!arrays) return GRAN_SUCCESS;
  const size_t n = (size_t)s->n;
  s->x.resize(n);
  s->y.resize(n);
  s->vx.resize(n);
  s->vy.resize(n);
  if (o.dim == 3) {
    s->z.resize(n);
    s->vz.resize(n);
  }
  s->cell.resize((size_t)s->ncell); /* uninitialised: zeroed here in parallel (first touch) */
  {
    srd_cpu_cell *ce = s->cell.data();
    const int64_t nc = s->ncell;
#pragma omp parallel for schedule(static) num_threads(nthreads_of(s))
    for (int64_t c = 0; c < nc; ++c) std::memset((void *)&ce[c], 0, sizeof(srd_cpu_cell));
  }
  s->rng.resize((size_t)s->ncell); /* uninitialised: every state is written by setup_streams or read */
  if (o.threads > 0 && srd_threads_used(o.threads) < o.threads)
    gran_warning_add("GSRD: option 'threads' = %d is more than 4 per processor; the engine uses %d (results do not "
                     "depend on the thread count)",
                     (int)o.threads, srd_threads_used(o.threads));
  return GRAN_SUCCESS;
}

double energy_of(const gran_srd *s) {
  const int64_t n = s->n, nb = (n + SRD_BLOCK - 1) / SRD_BLOCK;
  std::vector<double> p((size_t)nb);
  const bool d3 = s->opt.dim == 3;
#pragma omp parallel for schedule(static) num_threads(nthreads_of(s))
  for (int64_t b = 0; b < nb; ++b) {
    double e = 0;
    for (int64_t i = b * SRD_BLOCK; i < std::min(n, (b + 1) * SRD_BLOCK); ++i)
      e += 0.5 * (s->vx[i] * s->vx[i] + s->vy[i] * s->vy[i] + (d3 ? s->vz[i] * s->vz[i] : 0.0));
    p[b] = e;
  }
  return sum_blocks(p.data(), nb);
}

} // namespace

int srd_check_options_(const gran_srd_options *o) { return check_options(o); }
int srd_alloc_state_(gran_srd *s) { return alloc_state(s); }
int srd_alloc_geometry_(gran_srd *s) { return alloc_state(s, false); }

GRAN_EXTERN int gran_srd_options_default(gran_srd_options *opt) {
  GRAN_CHECK_PTR(opt);
  std::memset(opt, 0, sizeof *opt);
  opt->dim = 3;
  opt->wall_axis = -1;
  opt->wall_rule = 1;
  opt->cells[0] = opt->cells[1] = opt->cells[2] = 16;
  opt->a = 1.0;
  opt->n0 = 10.0;
  opt->dt = 1.0;
  opt->alpha_deg = 130.0;
  opt->eps = 1.0;
  opt->sigma = 0.0;
  opt->T0 = 1.0;
  opt->seed = 1;
  opt->sort_every = 50;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_srd_create(const gran_srd_options *opt, gran_srd **srd) {
  GRAN_TRY {
    GRAN_CHECK_PTR(opt);
    GRAN_CHECK_PTR(srd);
    *srd = nullptr;
    GRAN_CALL(check_options(opt));
    gran_srd *s = new gran_srd;
    s->opt = *opt;
    int e = alloc_state(s);
    if (e == GRAN_SUCCESS) e = setup_streams(s);
    if (e != GRAN_SUCCESS) {
      delete s;
      return e;
    }
    /* initial state (src/srd/create.cpp): serial, or by cells (then already in cell order) */
    if ((e = gran_srd_initial_state_(s)) != GRAN_SUCCESS) {
      delete s;
      return e;
    }
    if (opt->creation == GRAN_SRD_CREATE_CELLS) { /* the decomposable engine: an exact sum */
      gran_exactsum e;
      gran_exactsum_init_(&e);
      srd_kinetic_exact_(s->vx.data(), s->vy.data(), opt->dim == 3 ? s->vz.data() : nullptr, s->n, &e);
      s->e_initial = gran_exactsum_value_(&e);
    } else {
      s->e_initial = energy_of(s);
    }
    if (opt->sort_every > 0 && opt->creation == GRAN_SRD_CREATE_SERIAL) { /* in cell order from the start (the grid unshifted) */
      const double sh0[3] = {0.0, 0.0, 0.0};
      sort_by_cell(s, &s->gm, sh0, nthreads_of(s));
    }
    /* ---- device hook (owner: CUDA backend, src/srd/device_cuda.cpp) ---- */
    if ((e = gran_srd_dev_attach(s, 0)) != GRAN_SUCCESS) {
      delete s;
      return e;
    }
    /* ---- end device hook ---- */
    *srd = s;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_srd_destroy(gran_srd **srd) {
  if (srd == nullptr) return GRAN_SUCCESS;
  delete *srd;
  *srd = nullptr;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_srd_advance(gran_srd *s, int64_t steps) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    GRAN_CHECK(steps >= 0, GRAN_ERR_ARG, "argument 'steps' must be >= 0 (got %lld)", (long long)steps);
    char why[256]; /* the run-length bound of every time-stepped engine (core/run_bounds.h) */
    GRAN_CHECK(gran::gran_run_steps_ok((double)steps, (double)s->n + (double)s->ncell, why, sizeof why), GRAN_ERR_ARG,
               "argument 'steps': %s", why);
    if (s->dev.p) return gran_srd_dev_advance(s, steps); /* device hook (owner: CUDA backend) */
    /* the decomposable engine (creation by cells): the brick layer with one brick (bricks.cpp) */
    if (s->opt.creation == GRAN_SRD_CREATE_CELLS) return srd_bricks_advance_(s, steps);
    const gran_srd_options &o = s->opt;
    const int32_t fx = srd_fx_of(&o); /* the step loop's template flags: the rules' effects */
    const bool dis = fx & SRD_FX_DISSIP;
    const bool le = fx & SRD_FX_LE;
    const bool w = fx & SRD_FX_WALL;
    const bool acc = fx & SRD_FX_ACCEL;
    step_fn f = o.dim == 2 ? pick1<2>(dis, le, w, acc) : pick1<3>(dis, le, w, acc);
    return f(s, steps);
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_srd_stress_reset(gran_srd *s) {
  GRAN_CHECK_PTR_AS(s, srd);
  s->flux_kin = s->flux_coll = 0.0;
  s->stress_t0 = s->time;
  return GRAN_SUCCESS;
}

GRAN_EXTERN int gran_srd_particles(gran_srd *s, int64_t *n, double **x, double **y, double **z, double **vx,
                                   double **vy, double **vz) {
  GRAN_CHECK_PTR_AS(s, srd);
  GRAN_CHECK_PTR(n);
  if (s->dev.p) { /* device hook (owner: CUDA backend): copy back; changes go to the device at the next advance */
    GRAN_CALL(gran_srd_dev_sync(s, 0));
    gran_srd_dev_touch(s);
  }
  *n = s->n;
  const bool d3 = s->opt.dim == 3;
  if (x) *x = s->x.data();
  if (y) *y = s->y.data();
  if (z) *z = d3 ? s->z.data() : nullptr;
  if (vx) *vx = s->vx.data();
  if (vy) *vy = s->vy.data();
  if (vz) *vz = d3 ? s->vz.data() : nullptr;
  return GRAN_SUCCESS;
}

/* S(k), step 1: the power |FFT(n - <n>)|^2 / N of the unshifted cell counts of the N = s->n particles
 * (FFTW r2c; layout row-major (n2, n1, n0/2 + 1), the last index fastest). Shared by the CPU engine,
 * the host reference of the device algorithm (the GPU computes the same power with cuFFT) and a
 * split gas held in one process. */
int srd_sk_power(const gran_srd *s, const double *counts, std::vector<double> &power) {
  const int d = s->opt.dim;
  const int n0 = (int)s->gm.L[0], n1 = (int)s->gm.L[1], n2 = d == 3 ? (int)s->gm.L[2] : 1;
  const int nh = n0 / 2 + 1;
  const int64_t ncplx = (int64_t)n2 * n1 * nh;
  double *in = fftw_alloc_real((size_t)s->ncell_box);
  fftw_complex *out = fftw_alloc_complex((size_t)ncplx);
  if (!in || !out) {
    fftw_free(in);
    fftw_free(out);
    return GRAN_ERROR(GRAN_ERR_NOMEM, "out of memory for S(k)");
  }
  fftw_plan plan;
  {
    std::lock_guard<std::mutex> lk(gran_fftw_planner_mutex());
    if (d == 3) plan = fftw_plan_dft_r2c_3d(n2, n1, n0, in, out, FFTW_ESTIMATE);
    else plan = fftw_plan_dft_r2c_2d(n1, n0, in, out, FFTW_ESTIMATE);
  }
  const double mean = (double)s->n / (double)s->ncell_box;
  for (int64_t c = 0; c < s->ncell_box; ++c) in[c] = counts[c] - mean;
  fftw_execute(plan);
  power.resize((size_t)ncplx);
  for (int64_t q = 0; q < ncplx; ++q) power[(size_t)q] = srd_sk_mode_power(out[q][0], out[q][1], s->n);
  {
    std::lock_guard<std::mutex> lk(gran_fftw_planner_mutex());
    fftw_destroy_plan(plan);
  }
  fftw_free(in);
  fftw_free(out);
  return GRAN_SUCCESS;
}

srd_sk_geom srd_sk_geom_of(const gran_srd *s, int64_t nbins) {
  srd_sk_geom g;
  g.dim = s->opt.dim;
  g.n0 = (int)s->gm.L[0];
  g.n1 = (int)s->gm.L[1];
  g.n2 = g.dim == 3 ? (int)s->gm.L[2] : 1;
  g.nh = g.n0 / 2 + 1;
  for (int q = 0; q < 3; ++q) g.box[q] = s->gm.box[q];
  double kmax = 0;
  for (int q = 0; q < g.dim; ++q) kmax += std::pow(M_PI / s->opt.a, 2);
  g.w = std::sqrt(kmax) / (double)nbins;
  g.nbins = nbins;
  return g;
}

std::vector<srd_sk_bin> srd_sk_bins(int64_t nbins) {
  std::vector<srd_sk_bin> bins((size_t)nbins);
  for (srd_sk_bin &q : bins) {
    gran_exactsum_init_(&q.k);
    gran_exactsum_init_(&q.s);
    q.count = 0;
  }
  return bins;
}

void srd_sk_bins_add(const srd_sk_geom &g, const double *power, int64_t r0, int64_t r1, srd_sk_bin *bins) {
  const bool d3 = g.dim == 3;
  const int64_t inner = d3 ? g.n1 : 1;
  for (int64_t row = r0; row < r1; ++row)
    for (int64_t i1 = 0; i1 < inner; ++i1)
      for (int i0 = 0; i0 < g.nh; ++i0) {
        int64_t b;
        double kk;
        int mult;
        if (!srd_sk_mode(g, i0, d3 ? (int)i1 : (int)row, d3 ? (int)row : 0, &b, &kk, &mult)) continue;
        const double p = power[((row - r0) * inner + i1) * g.nh + i0];
        gran_exactsum_add_(&bins[b].k, mult * kk);
        gran_exactsum_add_(&bins[b].s, mult * p);
        bins[b].count += mult;
      }
}

void srd_sk_bins_out(srd_sk_bin *bins, int64_t nbins, double *k, double *sk, int64_t *count) {
  for (int64_t b = 0; b < nbins; ++b) {
    srd_sk_bin &q = bins[b];
    count[b] = q.count;
    k[b] = q.count > 0 ? gran_exactsum_value_(&q.k) / (double)q.count : 0.0;
    sk[b] = q.count > 0 ? gran_exactsum_value_(&q.s) / (double)q.count : 0.0;
  }
}

/* S(k), step 2: radial average of the half-spectrum power in nbins shells of |k| up to
 * sqrt(d) pi / a, k = 0 left out; modes 0 < i0 < n0/2 stand for two (their conjugates); the
 * shells' sums exact (srd_sk_bin). */
void srd_sk_shells(const gran_srd *s, const double *power, int64_t nbins, double *k, double *sk, int64_t *count) {
  const srd_sk_geom g = srd_sk_geom_of(s, nbins);
  std::vector<srd_sk_bin> bins = srd_sk_bins(nbins);
  srd_sk_bins_add(g, power, 0, g.dim == 3 ? g.n2 : g.n1, bins.data());
  srd_sk_bins_out(bins.data(), nbins, k, sk, count);
}

/* cell counts and mean velocities of the unshifted lattice (serial, particle order) */
static void unshifted_cells(const gran_srd *s, std::vector<int64_t> &cnt, std::vector<double> &V,
                            std::vector<double> &Q, std::vector<uint32_t> *cells = nullptr) {
  const int d = s->opt.dim;
  srd_geom g = s->gm;
  g.le_on = 0;
  cnt.assign((size_t)s->ncell, 0);
  V.assign((size_t)s->ncell * 3, 0.0);
  Q.assign((size_t)s->ncell, 0.0);
  const double zero[3] = {0, 0, 0};
  std::vector<uint32_t> c((size_t)s->n);
  for (int64_t i = 0; i < s->n; ++i) {
    const double p[3] = {s->x[i], s->y[i], d == 3 ? s->z[i] : 0.0};
    double dvx;
    c[i] = (uint32_t)srd_bin(&g, zero, p, &dvx);
    cnt[c[i]]++;
    V[3 * c[i]] += s->vx[i];
    V[3 * c[i] + 1] += s->vy[i];
    if (d == 3) V[3 * c[i] + 2] += s->vz[i];
  }
  for (int64_t k = 0; k < s->ncell; ++k)
    if (cnt[k] > 0)
      for (int j = 0; j < 3; ++j) V[3 * k + j] /= (double)cnt[k];
  /* second pass: thermal sums relative to the cell mean (two-pass: exact to rounding) */
  for (int64_t i = 0; i < s->n; ++i) {
    const double *m = &V[3 * c[i]];
    const double ux = s->vx[i] - m[0], uy = s->vy[i] - m[1], uz = d == 3 ? s->vz[i] - m[2] : 0.0;
    Q[c[i]] += ux * ux + uy * uy + uz * uz;
  }
  (void)zero;
  if (cells) cells->swap(c);
}

/* the first particle (index order) with a non-finite position or velocity, by array */
int srd_check_finite(const gran_srd *s, const char *when) {
  const bool d3 = s->opt.dim == 3;
  const double *a[6] = {s->x.data(), s->y.data(), d3 ? s->z.data() : nullptr,
                        s->vx.data(), s->vy.data(), d3 ? s->vz.data() : nullptr};
  static const char *const names[6] = {"x", "y", "z", "vx", "vy", "vz"};
  int64_t first = s->n;
  int comp = -1;
  for (int k = 0; k < 6; ++k) {
    if (!a[k]) continue;
    const double *p = a[k];
    for (int64_t i = 0; i < first; ++i)
      if (!(p[i] - p[i] == 0.0)) {
        first = i;
        comp = k;
        break;
      }
  }
  if (comp < 0) return GRAN_SUCCESS;
  return GRAN_ERROR(GRAN_ERR_NUMERIC, "GSRD: particle %lld has a non-finite %s (%g) %s; the run cannot continue",
                    (long long)first, names[comp], a[comp][first], when);
}

/* The ledger, the warnings, the clamps and the Lees-Edwards stress of an observation (ob holds
 * the sums already): one definition for the plain engine and a split gas. */
int srd_obs_finish_(gran_srd_obs *ob, const srd_obs_scalars &q) {
  const double E = ob->energy;
  GRAN_CHECK(std::isfinite(E) && std::isfinite(ob->momentum[0] + ob->momentum[1] + ob->momentum[2]), GRAN_ERR_NUMERIC,
             "GSRD: the kinetic energy (%g) or the momentum of the finite velocities overflows", E);
  ob->e_initial = q.e_initial;
  ob->e_collisions = q.e_coll;
  ob->e_external = q.e_ext;
  { /* relative to the initial energy, but never to less than the rounding of the energies
     * exchanged (a tiny e_initial beside large exchanges would turn rounding into an overflow);
     * a gas created at rest (one particle, its momentum removed) has none: then relative to
     * the largest energy exchanged, 0 when nothing was. The scale is a maximum (a sum of
     * finite energies may overflow), so the ratio is finite (at most ~3 / DBL_EPSILON). */
    const double num = q.e_initial + q.e_coll + q.e_ext - E;
    const double scale = std::max(std::max(std::fabs(q.e_coll), std::fabs(q.e_ext)), std::fabs(E));
    const double den = q.e_initial > 0 ? std::max(q.e_initial, DBL_EPSILON * scale) : scale;
    ob->ledger_error = den > 0 ? num / den : 0.0;
  }
  if (ob->temperature > 0 && ob->temperature < 1e-300)
    gran_warning_add("GSRD: the temperature %g is below 1e-300: squared velocities are subnormal doubles, flushed to "
                     "zero in the collision step (the cells' temperatures read 0 there: no dissipation, no thermostat)",
                     ob->temperature);
  ob->clamped = q.clamped;
  ob->dt_max = q.dt_max;
  if (q.clamped > 0)
    gran_warning_add("GSRD: eps_eff was clamped to [0, 1] in %lld cell collisions; dt <= %g avoids it",
                     (long long)q.clamped, q.dt_max);
  if (q.shear_rate != 0 && ob->time > q.stress_t0) {
    const double A = q.box[0] * (q.dim == 3 ? q.box[2] : 1.0);
    const double tt = ob->time - q.stress_t0;
    const double Vt = A * q.box[1];
    const double fk = q.flux_kin / tt / Vt; /* the flux per time first: Vt tt can underflow */
    const double fc = q.flux_coll / tt / Vt;
    ob->stress_kin = -fk;
    ob->stress_xy = -(fk + fc);
  }
  return GRAN_SUCCESS;
}

/* gran_srd_observe, with the decomposable engine's velocity profile when profile is not NULL */
static int observe_impl(gran_srd *s, gran_srd_obs *ob, double *profile) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    GRAN_CHECK_PTR_AS(ob, obs);
    GRAN_CALL(gran_srd_dev_sync(s, 0)); /* device hook (owner: CUDA backend): copy back (and checked) */
    if (!s->dev.p) GRAN_CALL(srd_check_finite(s, "when observed (after the last step, or written through gran_srd_particles)"));
    std::memset(ob, 0, sizeof *ob);
    const int d = s->opt.dim;
    const int64_t n = s->n;
    ob->time = s->time;
    ob->steps = s->step;
    ob->n = n;
    if (s->opt.creation == GRAN_SRD_CREATE_CELLS && !s->dev.p) {
      /* the decomposable engine: the sums of a split gas (bricks.cpp), here with one brick */
      GRAN_CALL(srd_observe_cells_(s, ob, profile));
    } else {
      double P[3] = {0, 0, 0};
      for (int64_t i = 0; i < n; ++i) {
        P[0] += s->vx[i];
        P[1] += s->vy[i];
        if (d == 3) P[2] += s->vz[i];
      }
      for (int k = 0; k < 3; ++k) ob->momentum[k] = P[k];
      ob->energy = energy_of(s);
      double th = 0;
      for (int64_t i = 0; i < n; ++i) {
        const double ux = s->vx[i] - P[0] / n, uy = s->vy[i] - P[1] / n, uz = d == 3 ? s->vz[i] - P[2] / n : 0.0;
        th += ux * ux + uy * uy + uz * uz;
      }
      ob->temperature = th / (double)(d * n);
      std::vector<int64_t> cnt;
      std::vector<double> V, Q;
      std::vector<uint32_t> cell_of;
      unshifted_cells(s, cnt, V, Q, &cell_of);
      double ek = 0, qs = 0, r1 = 0, r2 = 0;
      const double nbox = (double)s->ncell_box; /* the box cells (a wall axis's extra binning layer is no cell of the box) */
      for (int64_t c = 0; c < s->ncell; ++c) {
        const double nc = (double)cnt[c];
        ek += nc * (V[3 * c] * V[3 * c] + V[3 * c + 1] * V[3 * c + 1] + V[3 * c + 2] * V[3 * c + 2]);
        qs += Q[c];
        r1 += nc;
        r2 += nc * nc;
      }
      ob->e_kin = ek / (double)n;
      ob->theta_cells = qs / (double)(d * n);
      ob->mach = ob->theta_cells > 0 ? std::sqrt(ob->e_kin / ob->theta_cells) : 0.0;
      const double vol = d == 3 ? s->opt.a * s->opt.a * s->opt.a : s->opt.a * s->opt.a;
      const double mr = r1 / nbox;
      ob->sigma_rho = std::sqrt(std::max(0.0, r2 / nbox - mr * mr)) / vol;
      /* ---- Sonine a2 of the thermal velocities ----
       * u = v - V_cell in the unshifted cells with n >= 2. Removing the cell mean shrinks the second
       * cumulant of u by (n-1)/n and the fourth by g(n) = (n-1)(n^2-3n+3)/n^3 (cumulants are
       * multilinear), so w = u sqrt(n/(n-1)) has the population variance and a fourth cumulant
       * h(n) = (n^2-3n+3)/(n(n-1)) times the population's. Hence, for velocities drawn independently
       * in each cell about its flow velocity (any distribution, 2-D or 3-D):
       *   E sum|w|^4 = d(d+2) T^2 sum_c n_c (1 + a2 h(n_c)),
       *   a2 = [(d/(d+2)) N_in sum|w|^4 / (sum|w|^2)^2 - 1] N_in / sum_c n_c h(n_c),
       * N_in = particles in cells with n >= 2 (a Maxwellian gives 0, not +0.018 as the plain
       * (d/(d+2)) <u^4>/<u^2>^2 - 1 with N in place of N_in did at n0 = 5).
       * The fourth moment of T0 ~ 1e-154 or 1e154 under- or overflows: u is scaled
       * by the power of two 2^-e that puts the largest |component| in [0.5, 1) (exact: the same bits
       * of a2 as unscaled wherever neither under- nor overflows, any temperature otherwise). */
      {
        double umax = 0;
        for (int64_t i = 0; i < n; ++i) {
          const uint32_t cc = cell_of[(size_t)i];
          if (cnt[cc] < 2) continue;
          const double *m = &V[3 * (size_t)cc];
          umax = std::max({umax, std::fabs(s->vx[i] - m[0]), std::fabs(s->vy[i] - m[1]),
                           d == 3 ? std::fabs(s->vz[i] - m[2]) : 0.0});
        }
        int ex = 0;
        if (umax > 0) std::frexp(umax, &ex);
        const double us = std::ldexp(1.0, -ex);
        double m2 = 0, m4 = 0, nin = 0, hsum = 0;
        for (int64_t i = 0; i < n; ++i) {
          const uint32_t cc = cell_of[(size_t)i];
          const double nc = (double)cnt[cc];
          if (nc < 2) continue;
          const double *m = &V[3 * (size_t)cc];
          const double ux = (s->vx[i] - m[0]) * us, uy = (s->vy[i] - m[1]) * us, uz = d == 3 ? (s->vz[i] - m[2]) * us : 0.0;
          const double w2 = (ux * ux + uy * uy + uz * uz) * nc / (nc - 1.0);
          m2 += w2;
          m4 += w2 * w2;
          nin += 1.0;
          hsum += (nc * nc - 3.0 * nc + 3.0) / (nc * (nc - 1.0));
        }
        ob->a2 = m2 > 0 ? ((double)d / (d + 2.0) * m4 * nin / (m2 * m2) - 1.0) * nin / hsum : 0.0;
      }
      /* ---- end Sonine a2 ---- */
    }
    srd_obs_scalars q;
    q.e_initial = s->e_initial;
    q.e_coll = s->e_coll;
    q.e_ext = s->e_ext;
    q.flux_kin = s->flux_kin;
    q.flux_coll = s->flux_coll;
    q.stress_t0 = s->stress_t0;
    q.shear_rate = s->opt.shear_rate;
    for (int k = 0; k < 3; ++k) q.box[k] = s->gm.box[k];
    q.dim = d;
    q.clamped = s->clamped;
    q.dt_max = s->dt_max;
    GRAN_CALL(srd_obs_finish_(ob, q));
    s->clamped = 0; /* the clamps are counted since the last observation */
    s->dt_max = INFINITY;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_srd_observe(gran_srd *s, gran_srd_obs *ob) { return observe_impl(s, ob, nullptr); }

int srd_cells_observe_(gran_srd *s, gran_srd_obs *ob, double *profile) {
  GRAN_CHECK_PTR_AS(s, srd);
  GRAN_CHECK(s->opt.creation == GRAN_SRD_CREATE_CELLS && !s->dev.p, GRAN_ERR_ARG,
             "the decomposable engine's observables need option 'creation' = GRAN_SRD_CREATE_CELLS on the CPU");
  return observe_impl(s, ob, profile);
}

GRAN_EXTERN int gran_srd_structure_factor(gran_srd *s, int64_t nbins, double *k, double *sk, int64_t *count) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    GRAN_CHECK_PTR(k);
    GRAN_CHECK_PTR_AS(sk, s);
    GRAN_CHECK_PTR(count);
    GRAN_CHECK(nbins >= 1, GRAN_ERR_ARG, "argument 'nbins' must be >= 1");
    GRAN_CHECK(s->opt.wall_axis < 0, GRAN_ERR_ARG, "S(k) needs a periodic box (no walls)");
    if (s->dev.p) return gran_srd_dev_structure_factor(s, nbins, k, sk, count); /* device hook (CUDA backend) */
    std::vector<int64_t> cnt;
    std::vector<double> V, Q;
    unshifted_cells(s, cnt, V, Q);
    std::vector<double> counts(cnt.begin(), cnt.end()), power;
    GRAN_CALL(srd_sk_power(s, counts.data(), power));
    srd_sk_shells(s, power.data(), nbins, k, sk, count);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_srd_velocity_profile(const gran_srd *s, int32_t axis, int32_t component, int64_t nbins,
                                          double *mean, int64_t *count) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    GRAN_CHECK_PTR(mean);
    GRAN_CHECK_PTR(count);
    const int d = s->opt.dim;
    GRAN_CHECK(axis >= 0 && axis < d, GRAN_ERR_ARG, "argument 'axis' must be in [0, %d] (got %d)", d - 1, (int)axis);
    GRAN_CHECK(component >= 0 && component < d, GRAN_ERR_ARG, "argument 'component' must be in [0, %d] (got %d)", d - 1,
               (int)component);
    GRAN_CHECK(nbins >= 1, GRAN_ERR_ARG, "argument 'nbins' must be >= 1 (got %lld)", (long long)nbins);
    const double *p = axis == 0 ? s->x.data() : axis == 1 ? s->y.data() : s->z.data();
    const double *v = component == 0 ? s->vx.data() : component == 1 ? s->vy.data() : s->vz.data();
    const double w = (double)nbins / s->gm.box[axis];
    for (int64_t b = 0; b < nbins; ++b) {
      mean[b] = 0.0;
      count[b] = 0;
    }
    for (int64_t i = 0; i < s->n; ++i) { /* serial, particle order: deterministic */
      const int64_t b = srd_clamp_bin(p[i] * w, nbins);
      mean[b] += v[i];
      count[b] += 1;
    }
    for (int64_t b = 0; b < nbins; ++b)
      if (count[b] > 0) mean[b] /= (double)count[b];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
