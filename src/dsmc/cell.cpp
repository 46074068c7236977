/* cell.cpp - the time-step/cell selector of the DSMC engine (GRAN_SELECTOR_CELL, the DSMC outline steps
 * 1-13): positions in a cubic periodic box of nc^3 cells; every step dt
 *   1. stream r += v dt (wrapped into [0, L)), bin the particles into cells (stable counting
 *      sort), and find per cell the largest speed and diameter;
 *   2. per cell, N_p = F_N N_c^2 (sigma g)_max dt / (2 V_c) + the fraction carried from the last
 *      step (Eq. 8) candidate pairs (j, l) drawn with replacement (j == l: no pair), accepted with
 *      sigma_jl g / (sigma g)_max (Eq. 7), sigma = pi sigma_jl^2 g2; the majorant
 *      (sigma g)_max = pi sigma_max,c^2 g2_max 2 max_c|v| bounds every pair of the cell and is
 *      raised after a collision that speeds a particle up (the candidates still to come scale with
 *      it); a collision draws e from its |g.e| law (as the event selectors' default rule; the
 *      same statistics as Eq. 7 with e uniform and |g.e|) and uses the mixture's restitution;
 *   3. (agg.cpp) merges and breakups; (thermostat) white-noise kicks.
 * Displacements for the MSD follow the event engine's lazy form R = r + v (t - t_start): a
 * collision at the step time t changes r by -dv t, so R is the unwrapped position minus the start. */
#include "cell_impl.h"
#include "core/exactsum.h"
#include "core/keyed.h"
#include "core/run_bounds.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <new>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace gran {

namespace {

const double kPi = 3.14159265358979323846;
const int64_t kMaxCells = INT64_C(1) << 30;

typedef DsmcWords Words; /* agg_impl.h */

/* cells ahead whose particles' velocities are prefetched (measured at N = 1e6, 37^3 cells) */
#ifndef GRAN_CELL_AHEAD
#define GRAN_CELL_AHEAD 2
#endif
const int64_t kAhead = GRAN_CELL_AHEAD;

/* The particles are moved into cell order every kSortEvery steps (measured at N = 1e6, 37^3 cells,
 * dt = tau/10: see README), from kReorderMin particles on: below, positions and velocities (48 B a
 * particle) stay in the caches and the moves cost more than they save (measured: 10 % slower at
 * N = 2.5e5, 6-12 % faster from 3.5e5 on, on a machine with 32 MiB of L3). */
#ifndef GRAN_CELL_SORT_EVERY
#define GRAN_CELL_SORT_EVERY 8
#endif
const int64_t kSortEvery = GRAN_CELL_SORT_EVERY;
const int64_t kReorderMin = 300000;

/* max without the NaN rules of std::fmax (a libm call in the hot loops; no NaN reaches them) */
inline double dmax(double a, double b) { return a > b ? a : b; }

/* position into [0, L) */
inline double wrap(double x, double L, double invL) {
  if (x >= 0 && x < L) return x;
  x -= L * std::floor(x * invL);
  if (x >= L || x < 0) x = 0.0; /* rounding of x just below 0 */
  return x;
}

/* The cell coordinate of x: floor(x / a) clamped to [0, nc1] before the conversion to an integer
 * (a conversion of a double outside the range of the integer is undefined; NaN goes to nc1). For
 * x in [0, L) the same value as the conversion followed by the clamp. */
inline int32_t cell_coord(double x, double inv_a, int32_t nc1) {
  double q = x * inv_a;
  q = q < (double)nc1 ? q : (double)nc1;
  q = q > 0 ? q : 0.0;
  return (int32_t)q;
}

/* the cell of a position in [0, L)^3 (a coordinate that rounds to nc goes to the last cell) */
inline int64_t cell_of(const double *xj, double inv_a, int64_t nc) {
  int64_t ci[3];
  for (int d = 0; d < 3; d++) ci[d] = cell_coord(xj[d], inv_a, (int32_t)nc - 1);
  return (ci[0] * nc + ci[1]) * nc + ci[2];
}

/* Streaming of a block of n coordinates (n = 3 x particles, x and v flat): x += v dt wrapped by one
 * add or subtract of L (while |v dt| < L the value wrap() gives, but for x + v dt within rounding of
 * 2L, where wrap() returns 0 and this x - L; runs at b503's sizes came out bit for bit the same) and
 * the cell coordinate of each, floor(x nc / L) clamped to [0, nc - 1]; written so that the compiler
 * vectorizes it. Returns false if a coordinate is still outside [0, L) (|v dt| >= L, or not finite):
 * the caller wraps those. */
inline bool stream_block(double *__restrict x, const double *__restrict v, int32_t *__restrict q, int64_t n, double dt,
                         double L, double inv_a, int32_t nc1) {
  int bad = 0;
  for (int64_t i = 0; i < n; i++) {
    double y = x[i] + v[i] * dt;
    y = y < 0 ? y + L : y;
    y = y >= L ? y - L : y;
    bad |= (int)!((y >= 0) & (y < L));
    x[i] = y;
    q[i] = cell_coord(y, inv_a, nc1);
  }
  return bad == 0;
}

/* Particles j0 .. j0 + nb streamed (stream_block, and wrap() for one that crossed the box in one
 * step), their cell coordinates into qb */
inline void stream_particles(double *x, const double *v, int32_t *qb, int64_t j0, int64_t nb, double dt, double L,
                             double invL, double inv_a, int32_t nc1) {
  if (!stream_block(x + 3 * j0, v + 3 * j0, qb, 3 * nb, dt, L, inv_a, nc1))
    for (int64_t i = 3 * j0; i < 3 * (j0 + nb); i++) {
      x[i] = wrap(x[i], L, invL);
      qb[i - 3 * j0] = cell_coord(x[i], inv_a, nc1);
    }
}

}  // namespace

/* The largest F_N (sigma g)_max dt / V_c any cell can have before the next step (global speed bound). */
static double cell_pmax_bound(const gran_dsmc *s) {
  const DsmcCell *c = s->cell;
  double smax = s->sigma_max;
  if (c->agg) smax = agg_sigma(c, c->kmax);
  return c->pfac * kPi * s->g2max * smax * smax * 2.0 * std::sqrt(c->vmax2);
}

/* The largest distance a particle streams in one step, sqrt(vmax2) dt, is at most
 * kMaxStepBoxes box lengths: beyond it the positions carry no information (and the streamed
 * coordinates leave every integer range before they are wrapped). */
constexpr double kMaxStepBoxes = 1e6;
static int check_dt(const gran_dsmc *s, const char *when) {
  const DsmcCell *c = s->cell;
  const double hop = std::sqrt(c->vmax2) * c->o.dt / c->L;
  GRAN_CHECK(std::isfinite(hop) && hop <= kMaxStepBoxes, GRAN_ERR_DOMAIN,
             "option 'dt' = %g is too large %s: the fastest particle (speed %g, from the mixture 'mass' and 'T0') "
             "streams %g box lengths per step (at most %g)",
             c->o.dt, when, std::sqrt(c->vmax2), hop, kMaxStepBoxes);
  const double p = cell_pmax_bound(s);
  GRAN_CHECK(std::isfinite(p) && p <= 2.0, GRAN_ERR_DOMAIN,
             "option 'dt' = %g is too large %s: F_N (sigma g)_max dt / V_c = %g > 2, so the expected candidate pairs "
             "of a cell exceed N_c^2 (use dt <= %g, or more cells)",
             c->o.dt, when, p, c->o.dt * 2.0 / p);
  return GRAN_SUCCESS;
}

int dsmc_cell_check_options(const gran_dsmc_cell_options *o) {
  GRAN_CHECK_PTR(o);
  GRAN_CHECK(o->cells >= 1 && o->cells <= 1024 && o->cells * o->cells * o->cells <= kMaxCells, GRAN_ERR_ARG,
             "cell option 'cells' = " GRAN_I64_FMT " must be in [1, 1024] cells per side", o->cells);
  GRAN_CHECK(std::isfinite(o->dt) && o->dt > 0, GRAN_ERR_ARG, "cell option 'dt' = %g must be finite and > 0", o->dt);
  GRAN_CHECK(std::isfinite(o->fn) && o->fn > 0, GRAN_ERR_ARG, "cell option 'fn' = %g must be finite and > 0", o->fn);
  gran_dsmc_agg_options proc = {};
  proc.e_agg = o->e_agg;
  proc.e_frag = o->e_frag;
  proc.eps_f = o->eps_f;
  proc.frag_law = o->frag_law;
  GRAN_CALL(dsmc_agg_check_options(&proc, "cell"));
  GRAN_CHECK(std::isfinite(o->heat_rate) && o->heat_rate >= 0, GRAN_ERR_ARG,
             "cell option 'heat_rate' = %g must be finite and >= 0", o->heat_rate);
  GRAN_CHECK(o->heat_rate * o->dt <= 1e280, GRAN_ERR_ARG,
             "cell option 'heat_rate' = %g: the energy a particle gains per step, heat_rate dt = %g, must be <= 1e280 "
             "(the gas's energy sums would overflow)",
             o->heat_rate, o->heat_rate * o->dt);
  GRAN_CHECK(std::isfinite(o->bath_density) && o->bath_density >= 0, GRAN_ERR_ARG,
             "cell option 'bath_density' = %g must be finite and >= 0", o->bath_density);
  GRAN_CHECK(std::isfinite(o->bath_mass) && o->bath_mass > 0, GRAN_ERR_ARG,
             "cell option 'bath_mass' = %g must be finite and > 0", o->bath_mass);
  GRAN_CHECK(std::isfinite(o->bath_T) && o->bath_T >= 0, GRAN_ERR_ARG, "cell option 'bath_T' = %g must be finite and >= 0",
             o->bath_T);
  GRAN_CHECK(std::isfinite(o->bath_sigma) && o->bath_sigma >= 0, GRAN_ERR_ARG,
             "cell option 'bath_sigma' = %g must be finite and >= 0", o->bath_sigma);
  GRAN_CHECK(o->placement == GRAN_PLACE_RANDOM || o->placement == GRAN_PLACE_COLLISION, GRAN_ERR_ARG,
             "cell option 'placement' = %d is not a gran_cell_placement", (int)o->placement);
  GRAN_CHECK(o->streams == GRAN_CELL_STREAMS_SERIAL || o->streams == GRAN_CELL_STREAMS_CELLS, GRAN_ERR_ARG,
             "cell option 'streams' = %d is not a gran_cell_streams", (int)o->streams);
  GRAN_CHECK(o->streams == GRAN_CELL_STREAMS_SERIAL || !(o->e_agg > 0 || std::isfinite(o->e_frag)), GRAN_ERR_UNSUPPORTED,
             "cell option 'streams' = GRAN_CELL_STREAMS_CELLS (\"cells\") does not take aggregation or fragmentation "
             "yet ('e_agg' = %g, 'e_frag' = %g): use the serial streams",
             o->e_agg, o->e_frag);
  return GRAN_SUCCESS;
}

static int cell_setup_impl(gran_dsmc *s, const gran_dsmc_cell_options *o);

/* Geometry and arrays from the options; positions are allocated, not drawn. */
int dsmc_cell_setup(gran_dsmc *s, const gran_dsmc_cell_options *o) {
  try {
    return cell_setup_impl(s, o);
  } catch (const std::bad_alloc &) {
    return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the cell selector's arrays (" GRAN_I64_FMT
                                      " cells per side: fewer cells?)", o->cells);
  }
}

static int cell_setup_impl(gran_dsmc *s, const gran_dsmc_cell_options *o) {
  GRAN_CALL(dsmc_cell_check_options(o));
  GRAN_CHECK(!s->has_tracers, GRAN_ERR_ARG,
             "the cell selector has no tracers: every species needs n_k > 0 in the mixture");
  /* an empty gas has no temperature (0/0): refused rather than observed as NaN */
  GRAN_CHECK(s->N >= 1, GRAN_ERR_ARG,
             "the cell selector needs at least 1 particle: 'counts' (or the rounded n_k x option 'volume' / cell option "
             "'fn' = %g) give 0", o->fn);
  GRAN_CHECK(s->N < INT32_MAX, GRAN_ERR_ARG,
             "the cell selector holds fewer than 2^31 particles (" GRAN_I64_FMT " asked for)", s->N);
  {
    const int64_t C = o->cells * o->cells * o->cells, cap = std::max<int64_t>(INT64_C(1) << 20, 16 * s->N);
    GRAN_CHECK(C <= cap, GRAN_ERR_ARG,
               "cell option 'cells' = " GRAN_I64_FMT " gives " GRAN_I64_FMT " cells for " GRAN_I64_FMT
               " particles: at most 16 cells per particle (or 2^20 cells)",
               o->cells, C, s->N);
  }
  DsmcCell *c = new DsmcCell();
  s->cell = c;
  c->o = *o;
  c->nc = o->cells;
  c->C = o->cells * o->cells * o->cells;
  c->L = std::cbrt(o->fn * s->volume);
  c->inv_a = (double)c->nc / c->L;
  c->pfac = o->dt * (double)c->C / s->volume;
  GRAN_CHECK(std::isfinite(c->L) && c->L > 0 && std::isfinite(c->inv_a) && std::isfinite(c->pfac), GRAN_ERR_ARG,
             "the box (volume %g x F_N %g) is not finite", s->volume, o->fn);
  c->rem.assign((size_t)c->C, 0.0);
  c->start.assign((size_t)c->C + 1, 0);
  c->cvm2.assign((size_t)c->C, 0.0);
  c->csg.assign((size_t)c->C, 0.0);
  c->fillpos.assign((size_t)c->C, 0);
  c->list.resize((size_t)s->N);
  c->cellof.resize((size_t)s->N);
  if (s->N > 0) {
    s->p.x = gran_alloc<double>(3 * s->p.capacity);
    GRAN_CHECK(s->p.x != nullptr, GRAN_ERR_NOMEM, "cannot allocate positions of " GRAN_I64_FMT " particles", s->N);
  }
  s->p.flags |= GRAN_PARTICLES_POSITION;
  c->agg = o->e_agg > 0 || std::isfinite(o->e_frag);
  if (c->agg) {
    c->e_agg = o->e_agg;
    c->e_frag = o->e_frag;
    c->eps_f = o->eps_f;
    c->frag_law = o->frag_law;
    GRAN_CALL(dsmc_agg_setup(s, c));
    c->where.assign((size_t)s->N, 0);
  }
  /* cell order: the particle index carries no identity then (trajectories name particles by index) */
  c->reorder = !c->agg && !(s->opt.observe & GRAN_OBSERVE_TRAJECTORIES) && s->N >= kReorderMin;
  c->by_cells = o->streams == GRAN_CELL_STREAMS_CELLS;
  if (c->by_cells) c->order.assign((size_t)s->N, 0);
  if (c->reorder) {
    double *const arr[4] = {s->p.x, s->p.v, s->p.r, s->p.t_last};
    const int64_t len[4] = {3, 3, 3, 1};
    for (int a = 0; a < 4; a++)
      if (arr[a]) {
        c->spare[a] = gran_alloc<double>(len[a] * s->p.capacity);
        GRAN_CHECK(c->spare[a] != nullptr, GRAN_ERR_NOMEM, "cannot allocate the cell order's spare arrays (" GRAN_I64_FMT
                   " particles)", s->N);
      }
    c->cursor.assign((size_t)s->M, 0);
  }
  return GRAN_SUCCESS;
}

/* Cell order: list (the stable counting sort of this step) gives the particles cell by cell; each
 * species' particles move, in that order, into the species' own range (offsets unchanged, so the
 * species array stays as it is); list is rewritten with the new indices. Positions, velocities and
 * (when present) displacements and t_last move with the particles. */
static void cell_reorder(gran_dsmc *s, DsmcCell *c) {
  const int64_t N = s->N, M = s->M;
  int64_t *const cur = c->cursor.data();
  for (int64_t k = 0; k < M; k++) cur[k] = s->offset[(size_t)k];
  int32_t *const list = c->list.data();
  const int32_t *const sp = s->p.species;
  const double *const x = s->p.x, *const v = s->p.v, *const r = s->p.r, *const tl = s->p.t_last;
  double *const xs = c->spare[0], *const vs = c->spare[1], *const rs = c->spare[2], *const ts = c->spare[3];
  for (int64_t e = 0; e < N; e++) {
    const int64_t j = list[e], d = M == 1 ? e : cur[sp[j]]++;
    list[e] = (int32_t)d;
    for (int q = 0; q < 3; q++) {
      xs[3 * d + q] = x[3 * j + q];
      vs[3 * d + q] = v[3 * j + q];
    }
    if (r)
      for (int q = 0; q < 3; q++) rs[3 * d + q] = r[3 * j + q];
    if (tl) ts[d] = tl[j];
  }
  std::swap(s->p.x, c->spare[0]);
  std::swap(s->p.v, c->spare[1]);
  if (r) std::swap(s->p.r, c->spare[2]);
  if (tl) std::swap(s->p.t_last, c->spare[3]);
}

/* Creation with the cell order on: the particles move into cell order once, so that the first step
 * does not pay a random permutation of 48 B records (and the first touch of the spare arrays): at
 * N = 1e6 that step took 146 ms against 10 ms for the others. Positions and velocities are drawn
 * independently, so the law of the initial state is unchanged. */
static void cell_initial_order(gran_dsmc *s, DsmcCell *c) {
  const int64_t N = s->N, C = c->C;
  int64_t *const start = c->start.data(), *const pos = c->fillpos.data();
  int32_t *const cellof = c->cellof.data(), *const list = c->list.data();
  std::fill(start, start + C + 1, 0);
  for (int64_t j = 0; j < N; j++) {
    const int64_t cc = cell_of(s->p.x + 3 * j, c->inv_a, c->nc);
    cellof[j] = (int32_t)cc;
    start[cc + 1]++;
  }
  for (int64_t q = 0; q < C; q++) start[q + 1] += start[q];
  std::copy(start, start + C, pos);
  for (int64_t j = 0; j < N; j++) list[pos[cellof[j]]++] = (int32_t)j;
  cell_reorder(s, c);
}

/* Creation by cells (GRAN_CELL_STREAMS_CELLS): the counts of species k over the cells are a
 * multinomial split of N_k down the binary tree over the cells (core/keyed.h, tag kTagCreateNode
 * mixed with k), and the particles of species k in cell q come from the keyed generator
 * (kTagCreateCell, k C + q): for each, a position uniform in the cell, then a Maxwellian velocity at
 * T_k. The gas's mean velocity (exact sums) is then subtracted. Within its species' range a
 * particle's place is in cell order, and its key is cell << 32 | its rank among the cell's particles,
 * species by species. So the initial state of any range of cells is the same whoever draws it. */
constexpr uint64_t kTagCreateNode = 0x63656c6c2d6e6f64ULL; /* "cell-nod" */
constexpr uint64_t kTagCreateCell = 0x63656c6c2d6e6577ULL; /* "cell-new" */

int dsmc_cell_create_by_cells(gran_dsmc *s, const double *T, double *e_initial) {
  DsmcCell *const c = s->cell;
  GRAN_CHECK(c && c->by_cells && !s->classes, GRAN_ERR_INTERNAL, "cell DSMC creation by cells: engine not set up");
  const int64_t C = c->C, M = s->M, nc = c->nc;
  const uint64_t seed = s->opt.seed;
  const double a = c->L / (double)nc;
  double *const v = dsmc_hv(s), *const x = s->p.x;
  std::vector<int64_t> rank((size_t)C + 1, 0); /* particles per cell, then the order's cursors */
  std::vector<std::pair<int64_t, int64_t>> occ;
  gran_exactsum P[3];
  for (auto &e : P) gran_exactsum_init_(&e);
  double mtot = 0;
  for (int64_t k = 0; k < M; k++) {
    const int64_t Nk = s->count[(size_t)k];
    occ.clear();
    keyed_split<true>(seed, keyed_mix64(kTagCreateNode + (uint64_t)k), 1, 0, C, Nk, 0, C,
                      [&](int64_t q, int64_t n) { occ.emplace_back(q, n); });
    const double mk = s->mix.m[(size_t)k], sd = std::sqrt(T[k] / mk);
    int64_t j = s->offset[(size_t)k];
    for (const auto &cq : occ) {
      const int64_t q = cq.first, ci[3] = {q / (nc * nc), (q / nc) % nc, q % nc};
      gran_rng r;
      keyed_rng(seed, kTagCreateCell, (uint64_t)k * (uint64_t)C + (uint64_t)q, &r);
      double pv[3] = {0, 0, 0};
      for (int64_t i = 0; i < cq.second; i++, j++) {
        for (int d = 0; d < 3; d++) { /* uniform in the cell's layer (a rounding to the next one drawn again) */
          int t = 0;
          double y;
          do {
            y = ((double)ci[d] + rng_uniform(&r)) * a;
          } while (!(y < c->L && cell_coord(y, c->inv_a, (int32_t)nc - 1) == ci[d]) && ++t < 64);
          GRAN_CHECK(t < 64, GRAN_ERR_INTERNAL, "cell DSMC creation: no position inside cell " GRAN_I64_FMT " found", q);
          x[3 * j + d] = y;
        }
        for (int d = 0; d < 3; d++) {
          v[3 * j + d] = sd * rng_normal(&r);
          pv[d] += v[3 * j + d];
        }
        rank[(size_t)q + 1]++;
      }
      for (int d = 0; d < 3; d++) gran_exactsum_add_(&P[d], mk * pv[d]);
    }
    GRAN_CHECK(j == s->offset[(size_t)k + 1], GRAN_ERR_INTERNAL, "cell DSMC creation: the counts of species " GRAN_I64_FMT
               " sum to " GRAN_I64_FMT ", not " GRAN_I64_FMT, k, j - s->offset[(size_t)k], Nk);
    mtot += mk * (double)Nk;
  }
  /* the keys' order: by cell, and within a cell species by species (the arrays' order) */
  for (int64_t q = 0; q < C; q++) rank[(size_t)q + 1] += rank[(size_t)q];
  for (int64_t j = 0; j < s->N; j++) c->order[(size_t)rank[(size_t)cell_of(x + 3 * j, c->inv_a, nc)]++] = (int32_t)j;
  double u[3] = {0, 0, 0};
  if (mtot > 0)
    for (int d = 0; d < 3; d++) u[d] = gran_exactsum_value_(&P[d]) / mtot;
  gran_exactsum e;
  gran_exactsum_init_(&e);
  for (int64_t k = 0; k < M; k++) {
    const double mk = s->mix.m[(size_t)k];
    for (int64_t j = s->offset[(size_t)k]; j < s->offset[(size_t)k + 1]; j++) {
      double *const vj = v + 3 * j;
      for (int d = 0; d < 3; d++) vj[d] -= u[d];
      gran_exactsum_add_(&e, 0.5 * mk * (vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2]));
    }
  }
  *e_initial = gran_exactsum_value_(&e);
  return GRAN_SUCCESS;
}

void dsmc_cell_keys(const gran_dsmc *s, int64_t *key) {
  const DsmcCell *const c = s->cell;
  std::vector<int64_t> rank((size_t)c->C, 0);
  for (int64_t e = 0; e < s->N; e++) {
    const int32_t j = c->order[(size_t)e];
    const int64_t q = cell_of(s->p.x + 3 * j, c->inv_a, c->nc); /* the cell it was binned into */
    key[j] = (q << 32) | rank[(size_t)q]++;
  }
}

int dsmc_cell_order_from_keys(gran_dsmc *s, const int64_t *key, const char *path) {
  DsmcCell *const c = s->cell;
  const int64_t N = s->N, C = c->C;
  std::vector<int64_t> start((size_t)C + 1, 0);
  for (int64_t j = 0; j < N; j++) start[(size_t)cell_of(s->p.x + 3 * j, c->inv_a, c->nc) + 1]++;
  for (int64_t q = 0; q < C; q++) start[(size_t)q + 1] += start[(size_t)q];
  std::fill(c->order.begin(), c->order.end(), -1);
  for (int64_t j = 0; j < N; j++) {
    const int64_t q = cell_of(s->p.x + 3 * j, c->inv_a, c->nc), r = key[j] & INT64_C(0xffffffff);
    const bool ok = key[j] >= 0 && (key[j] >> 32) == q && r < start[(size_t)q + 1] - start[(size_t)q] &&
                    c->order[(size_t)(start[(size_t)q] + r)] < 0;
    GRAN_CHECK(ok, GRAN_ERR_IO,
               "checkpoint '%s': dataset 'cell_keys' does not match the positions (particle " GRAN_I64_FMT
               " has key %lld in cell " GRAN_I64_FMT "; every cell's keys must be its cell and the ranks 0 .. n - 1: "
               "damaged or edited file?)",
               path, j, (long long)key[j], q);
    c->order[(size_t)(start[(size_t)q] + r)] = (int32_t)j;
  }
  return GRAN_SUCCESS;
}

int dsmc_cell_init(gran_dsmc *s, const gran_dsmc_cell_options *o) {
  if (!s->cell) { /* GRAN_CELL_STREAMS_SERIAL; by cells the creation drew the positions (in cell order) */
    GRAN_CALL(dsmc_cell_setup(s, o));
    DsmcCell *c = s->cell;
    /* uniform positions from the scalar stream (after the velocities) */
    for (int64_t j = 0; j < 3 * s->N; j++) s->p.x[j] = wrap(rng_uniform(&s->rng) * c->L, c->L, 1.0 / c->L);
    if (c->reorder) cell_initial_order(s, c);
  }
  DsmcCell *c = s->cell;
  double m2 = 0;
  for (int64_t j = 0; j < s->N; j++) {
    const double *v = s->p.v + 3 * j;
    m2 = std::fmax(m2, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  c->vmax2 = m2;
  if (c->agg) /* sizes: one speed bound for all (the particles stop being grouped by species) */
    for (int64_t k = 0; k < s->M; k++) {
      s->bound2[(size_t)k] = m2;
      s->bound[(size_t)k] = std::sqrt(m2);
    }
  GRAN_CALL(check_dt(s, "for the initial speeds"));
  GRAN_CALL(dsmc_cell_check_bath(s));
  return GRAN_SUCCESS;
}

/* Bath collisions of a step: a particle of speed v meets candidates at the rate
 * n_b pi sigma_kb^2 (|v| + <|w|>) (cell_bath). Their expected number per particle and step, with
 * |v| the largest speed now plus 4 thermal speeds sqrt(T_b / m) of the lightest particle (where the
 * bath takes it), is at most kBathMaxPerStep: more is a run whose steps do not end (or whose rate
 * overflows). */
constexpr double kBathMaxPerStep = 1e3;
/* running: at a step of the run (time t), after the white-noise thermostat: the speeds it raised
 * can make the bath's collisions grow without end, which the run reports (GRAN_ERR_NUMERIC) before
 * the step that would not end */
static int bath_check(const gran_dsmc *s, bool running, double t) {
  const DsmcCell *c = s->cell;
  if (!(c->o.bath_density > 0)) return GRAN_SUCCESS;
  double smax = 0, mmin = INFINITY;
  if (c->agg) {
    smax = agg_sigma(c, std::max<int64_t>(c->kmax, 1));
    mmin = c->m1;
  } else {
    for (int64_t k = 0; k < s->M; k++)
      if (s->count[(size_t)k] > 0) {
        smax = std::fmax(smax, s->mix.sigma[(size_t)k]);
        mmin = std::fmin(mmin, s->mix.m[(size_t)k]);
      }
  }
  const double mb = c->o.bath_mass, Tb = c->o.bath_T, nb = c->o.bath_density;
  const double wmean = std::sqrt(8.0 / kPi) * std::sqrt(Tb / mb);
  const double vs = std::sqrt(c->vmax2) + 4.0 * std::sqrt(Tb / mmin);
  const double sg = 0.5 * (smax + c->o.bath_sigma);
  const double per_step = nb * kPi * sg * sg * (vs + wmean) * c->o.dt;
  if (running)
    GRAN_CHECK(std::isfinite(per_step) && per_step <= kBathMaxPerStep, GRAN_ERR_NUMERIC,
               "cell DSMC at t = %g: the largest speed %g (the white-noise thermostat's 'heat_rate' = %g raised it) "
               "gives %g expected bath collisions per particle and step (at most %g): the step would not end; lower "
               "'heat_rate', the bath density or dt",
               t, std::sqrt(c->vmax2), c->o.heat_rate, per_step, kBathMaxPerStep);
  GRAN_CHECK(std::isfinite(per_step) && per_step <= kBathMaxPerStep, GRAN_ERR_ARG,
             "cell options 'bath_density' = %g, 'bath_T' = %g, 'bath_mass' = %g, 'bath_sigma' = %g with 'dt' = %g give "
             "%g expected bath collisions per particle and step (at most %g: lower the bath density or dt)",
             nb, Tb, mb, c->o.bath_sigma, c->o.dt, per_step, kBathMaxPerStep);
  return GRAN_SUCCESS;
}
int dsmc_cell_check_bath(const gran_dsmc *s) { return bath_check(s, false, 0.0); }

void dsmc_cell_free(gran_dsmc *s) {
  delete s->cell;
  s->cell = nullptr;
}

namespace {

/* White-noise thermostat (after the collisions of a step at time t): every velocity component of
 * a particle of mass m gets a Gaussian kick of variance heat_rate dt / m; then the mass-weighted
 * mean kick is subtracted from every particle (the total momentum is conserved, the heating per
 * particle is heat_rate (1 - m / sum m)). The energy added goes into the ledger (e_heat). */
/* the kick of one particle (sd = sqrt(heat_rate dt / m)): its energy and momentum into the sums */
template <bool kDisp, class W>
inline void heat_kick(double *vj, double *Rj, double m, double sd, double t, W &w, double P[3], double Pc[3], double &de,
                      double &dec) {
  double z[4];
  w.normal2(z);
  w.normal2(z + 2); /* the fourth is not used */
  for (int d = 0; d < 3; d++) {
    const double dv = sd * z[d];
    neumaier_add(de, dec, 0.5 * m * dv * (2.0 * vj[d] + dv));
    vj[d] += dv;
    neumaier_add(P[d], Pc[d], m * dv);
    if (kDisp) Rj[d] -= dv * t;
  }
}
/* the mean kick u off one particle: the energy into the sums; returns |v|^2 */
template <bool kDisp>
inline double heat_recentre(double *vj, double *Rj, double m, const double u[3], double t, double &de, double &dec) {
  neumaier_add(de, dec, m * (u[0] * (0.5 * u[0] - vj[0]) + u[1] * (0.5 * u[1] - vj[1]) + u[2] * (0.5 * u[2] - vj[2])));
  for (int d = 0; d < 3; d++) {
    vj[d] -= u[d];
    if (kDisp) Rj[d] += u[d] * t;
  }
  return vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
}

template <bool kDisp>
void cell_heat(gran_dsmc *s, double t) {
  DsmcCell *const c = s->cell;
  Words w{&s->vrng};
  const int64_t N = s->N;
  double *const v = s->p.v;
  double *const R = kDisp ? s->p.r : nullptr;
  const int32_t *const sp = s->p.species;
  const double *const mix_m = s->mix.m.data();
  const bool agg = c->agg != 0;
  auto mass_of = [&](int32_t k) { return agg ? (double)(k + 1) * c->m1 : mix_m[k]; };
  const double hd = c->o.heat_rate * c->o.dt;
  double P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0}, mt = 0, mtc = 0, de = 0, dec = 0;
  for (int64_t j = 0; j < N; j++) {
    const double m = mass_of(sp[j]), sd = std::sqrt(hd / m);
    heat_kick<kDisp>(v + 3 * j, kDisp ? R + 3 * j : nullptr, m, sd, t, w, P, Pc, de, dec);
    neumaier_add(mt, mtc, m);
  }
  const double u[3] = {(P[0] + Pc[0]) / (mt + mtc), (P[1] + Pc[1]) / (mt + mtc), (P[2] + Pc[2]) / (mt + mtc)};
  double vm2 = c->vmax2;
  double *const b2 = s->bound2.data();
  for (int64_t j = 0; j < N; j++) {
    const double q2 = heat_recentre<kDisp>(v + 3 * j, kDisp ? R + 3 * j : nullptr, mass_of(sp[j]), u, t, de, dec);
    vm2 = std::fmax(vm2, q2);
    if (!agg) b2[sp[j]] = std::fmax(b2[sp[j]], q2);
  }
  c->vmax2 = vm2;
  for (int64_t k = 0; k < s->M; k++) {
    if (agg) b2[k] = vm2; /* sizes: one bound for all */
    s->bound[(size_t)k] = std::sqrt(b2[k]);
  }
  neumaier_add(c->e_heat, c->e_heat_c, de + dec);
}

/* Molecular-gas bath (after the collisions of a step ending at time t): every particle collides
 * elastically with bath particles of velocity w ~ Maxwell(T_b, m_b) at the rate
 * n_b pi sigma_kb^2 |v - w| per unit time and bath velocity, sampled exactly over the step by
 * thinning: candidates at the rate n_b pi sigma_kb^2 (|v| + <|w|>) are, with probability
 * |v| / (|v| + <|w|>), a Maxwellian w and otherwise a speed-biased one (density ~ |w| f(w)), so
 * that the candidate intensity of a bath velocity w is n_b pi sigma^2 (|v| + |w|) f(w) >=
 * n_b pi sigma^2 |v - w| f(w); a candidate is accepted with |v - w| / (|v| + |w|), and the
 * collision draws e from its |g.e| law. Waiting times restart from the new speed after each
 * collision (memoryless). The bath does not change; the energy exchanged is booked as heat. */
struct BathLaw {
  double mb, sb, wmean, dt, nb, sigma_b;
};
inline BathLaw bath_law(const DsmcCell *c) {
  const double mb = c->o.bath_mass, sb = std::sqrt(c->o.bath_T / mb);
  return BathLaw{mb, sb, std::sqrt(8.0 / kPi) * sb, c->o.dt, c->o.bath_density, c->o.bath_sigma};
}
/* the bath's collisions of one particle of mass m and diameter sig over the step: returns |v|^2 after */
template <bool kDisp, class W>
inline double bath_particle(double *vj, double *Rj, double m, double sig, const BathLaw &b, double t, W &w, double &de,
                            double &dec) {
  const double sg = 0.5 * (sig + b.sigma_b);
  const double rate0 = b.nb * kPi * sg * sg;
  double tt = 0;
  for (;;) {
    const double sp2 = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2], vs = std::sqrt(sp2);
    const double lam = rate0 * (vs + b.wmean);
    if (!(lam > 0)) break;
    tt += -std::log(u64_uniform_pos(w.next())) / lam;
    if (tt > b.dt) break;
    double wv[3];
    if (w.uniform() * (vs + b.wmean) < vs) { /* Maxwellian */
      double z[4];
      w.normal2(z);
      w.normal2(z + 2);
      for (int d = 0; d < 3; d++) wv[d] = b.sb * z[d];
    } else { /* speed-biased: |w|^2 / (2 sb^2) ~ Gamma(2) */
      const double G = -std::log(u64_uniform_pos(w.next()) * u64_uniform_pos(w.next()));
      double e[3];
      w.unit3(e);
      const double ws = b.sb * std::sqrt(2.0 * G);
      for (int d = 0; d < 3; d++) wv[d] = ws * e[d];
    }
    const double g[3] = {vj[0] - wv[0], vj[1] - wv[1], vj[2] - wv[2]};
    const double ga = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    const double wa = std::sqrt(wv[0] * wv[0] + wv[1] * wv[1] + wv[2] * wv[2]);
    if (!(w.uniform() * (vs + wa) < ga)) continue;
    double u[3];
    w.unit3(u);
    const double a = 2.0 * b.mb / (m + b.mb);
    double dv[3];
    for (int d = 0; d < 3; d++) dv[d] = -a * 0.5 * (g[d] - ga * u[d]);
    neumaier_add(de, dec, 0.5 * m * (dv[0] * (2.0 * vj[0] + dv[0]) + dv[1] * (2.0 * vj[1] + dv[1]) + dv[2] * (2.0 * vj[2] + dv[2])));
    for (int d = 0; d < 3; d++) {
      vj[d] += dv[d];
      if (kDisp) Rj[d] -= dv[d] * t;
    }
  }
  return vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
}

template <bool kDisp>
void cell_bath(gran_dsmc *s, double t) {
  DsmcCell *const c = s->cell;
  Words w{&s->vrng};
  const int64_t N = s->N;
  double *const v = s->p.v;
  double *const R = kDisp ? s->p.r : nullptr;
  const int32_t *const sp = s->p.species;
  const bool agg = c->agg != 0;
  const BathLaw law = bath_law(c);
  double de = 0, dec = 0, vm2 = c->vmax2;
  double *const b2 = s->bound2.data();
  for (int64_t j = 0; j < N; j++) {
    const int32_t k = sp[j];
    const double m = agg ? (double)(k + 1) * c->m1 : s->mix.m[(size_t)k];
    const double sig = agg ? c->sigk[(size_t)k] : s->mix.sigma[(size_t)k];
    const double q2 = bath_particle<kDisp>(v + 3 * j, kDisp ? R + 3 * j : nullptr, m, sig, law, t, w, de, dec);
    vm2 = q2 > vm2 ? q2 : vm2;
    if (!agg) b2[k] = q2 > b2[k] ? q2 : b2[k];
  }
  c->vmax2 = vm2;
  for (int64_t k = 0; k < s->M; k++) {
    if (agg) b2[k] = vm2;
    s->bound[(size_t)k] = std::sqrt(b2[k]);
  }
  neumaier_add(c->e_heat, c->e_heat_c, de + dec);
}

/* Aggregation and fragmentation of the accepted pair (j, l) of sizes i+1, k+1 in cell segment lq[0..n)
 * (kAgg): returns 0 for a bounce (the caller collides), 1 when the pair merged (l left the cell: n
 * decreased), 2 when it shattered (j, l and K-2 appended particles are monomers). Speeds of new
 * particles raise *vmc2 (the cell's) and the engine's bound. */
struct AggCtx {
  gran_dsmc *s;
  DsmcCell *c;
  Words *w;
  int32_t *lq;
  int64_t *n;
  int status;
};

static inline void agg_place(DsmcCell *c, Words *w, double *xj) {
  for (int d = 0; d < 3; d++) xj[d] = wrap(w->uniform() * c->L, c->L, 1.0 / c->L);
}

static int agg_merge(AggCtx &a, int64_t j, int64_t l, int32_t i, int32_t k, double Eimp) {
  gran_dsmc *s = a.s;
  DsmcCell *c = a.c;
  const double mi = (double)(i + 1), mk = (double)(k + 1), inv = 1.0 / (mi + mk);
  agg_merge_velocity(s->p.v + 3 * j, s->p.v + 3 * l, mi, mk);
  const int64_t K = (int64_t)i + (int64_t)k + 2;
  agg_book_merge(c, (int64_t)i + 1, (int64_t)k + 1, Eimp);
  s->p.species[j] = (int32_t)(K - 1);
  s->p.species[l] = -1; /* dropped at the end of the step */
  c->ndead++;
  double *xj = s->p.x + 3 * j;
  if (c->o.placement == GRAN_PLACE_RANDOM) {
    agg_place(c, a.w, xj);
  } else { /* centre of mass, minimum image */
    const double *xl = s->p.x + 3 * l;
    for (int d = 0; d < 3; d++) {
      double dx = xl[d] - xj[d];
      dx -= c->L * std::nearbyint(dx / c->L);
      xj[d] = wrap(xj[d] + mk * inv * dx, c->L, 1.0 / c->L);
    }
  }
  /* l leaves the cell's list */
  const int64_t pl = c->where[(size_t)l], last = *a.n - 1;
  const int32_t moved = a.lq[last];
  a.lq[pl] = moved;
  c->where[(size_t)moved] = pl;
  *a.n = last;
  return 1;
}

static int agg_shatter(AggCtx &a, int64_t j, int64_t l, int32_t i, int32_t k, double Eimp, double g, double *vmc2) {
  gran_dsmc *s = a.s;
  DsmcCell *c = a.c;
  const int64_t kj = (int64_t)i + 1, kl = (int64_t)k + 1, K = kj + kl;
  const AggPieces pc = agg_pieces(*a.w, c->frag_law, K);
  const int64_t P = pc.P;
  /* room for P - 2 new particles: one growth at most (geometric), never one per fragment */
  gran_particles *p = &s->p;
  if (p->n + P - 2 >= INT32_MAX) { /* the cell lists hold 32-bit indices */
    a.status = GRAN_ERROR(GRAN_ERR_RANGE, "fragmentation would make more than 2^31 particles");
    return 0;
  }
  if (p->n + P - 2 > p->capacity) {
    const int64_t want = std::max(p->n + P - 2, 2 * p->capacity);
    a.status = gran_particles_reserve(p, want);
    if (a.status != GRAN_SUCCESS) return 0;
  }
  double *const v = p->v;
  const double mi = (double)kj, mk = (double)kl, inv = 1.0 / (mi + mk);
  double Vc[3];
  for (int d = 0; d < 3; d++) Vc[d] = (mi * v[3 * j + d] + mk * v[3 * l + d]) * inv;
  const double xc[3] = {p->x[3 * j], p->x[3 * j + 1], p->x[3 * j + 2]};
  const int64_t n0 = p->n;
  p->n += P - 2;
  auto target = [&](int64_t q) { return q == 0 ? j : q == 1 ? l : n0 + q - 2; };
  const double E0 = c->eps_f * c->eps_f * Eimp;
  const double m2 = agg_fragment_velocities(*a.w, pc, [&](int64_t q) { return v + 3 * target(q); }, Vc,
                                            agg_fragment_speed(kj, kl, c->eps_f, g), E0, c->m1);
  for (int64_t q = 0; q < P; q++) {
    const int64_t t = target(q);
    p->species[t] = (int32_t)(pc.size(q) - 1);
    double *xq = p->x + 3 * t;
    if (c->o.placement == GRAN_PLACE_RANDOM) {
      agg_place(c, a.w, xq);
    } else {
      xq[0] = xc[0];
      xq[1] = xc[1];
      xq[2] = xc[2];
    }
  }
  agg_book_shatter(c, kj, kl, pc, Eimp, E0);
  *vmc2 = std::fmax(*vmc2, m2);
  c->vmax2 = std::fmax(c->vmax2, m2);
  return 2;
}

void cell_step_time(gran_dsmc *s);

/* 1. Stream and bin: positions advanced and wrapped, the particles counted into their cells (a stable
 * counting sort: list holds each cell's particles in index order), the per-cell largest speed and
 * diameter, the exact speed bounds; every kSortEvery steps the particles move into cell order. Then
 * the step count and the time (trajectory samples within the step recorded on the way). */
template <bool kAgg>
void cell_stream_bin(gran_dsmc *s) {
  DsmcCell *const c = s->cell;
  const int64_t N = s->N, C = c->C, M = s->M;
  const double dt = c->o.dt, L = c->L, invL = 1.0 / L, inv_a = c->inv_a;
  const int64_t nc = c->nc;
  double *x = s->p.x, *v = s->p.v;
  const int32_t *sp = s->p.species;
  const double *sig = kAgg ? c->sigk.data() : s->mix.sigma.data();
  if (kAgg && (int64_t)c->list.size() < N) {
    c->list.resize((size_t)N);
    c->cellof.resize((size_t)N);
  }
  if (kAgg && (int64_t)c->where.size() < N) c->where.resize((size_t)N);
  int64_t *const start = c->start.data();
  int32_t *const cellof = c->cellof.data();
  double *const cvm2 = c->cvm2.data(), *const csg = c->csg.data();
  std::fill(start, start + C + 1, 0);
  std::fill(cvm2, cvm2 + C, 0.0);
  std::fill(csg, csg + C, 0.0);
  double *const b2 = s->bound2.data(); /* per-species speed bounds, exact after streaming */
  std::fill(b2, b2 + M, 0.0);
  double vm2 = 0;
  constexpr int64_t kBlock = 512; /* particles streamed per vector pass (x, v and cells of a block in L1) */
  alignas(64) int32_t qb[3 * kBlock];
  for (int64_t j0 = 0; j0 < N; j0 += kBlock) {
    const int64_t nb = std::min(kBlock, N - j0);
    stream_particles(x, v, qb, j0, nb, dt, L, invL, inv_a, (int32_t)nc - 1);
    for (int64_t j = j0; j < j0 + nb; j++) {
      const int32_t *const qj = qb + 3 * (j - j0);
      const double *vj = v + 3 * j;
      const int64_t cc = ((int64_t)qj[0] * nc + qj[1]) * nc + qj[2];
      cellof[j] = (int32_t)cc;
      start[cc + 1]++;
      const double q2 = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
      cvm2[cc] = dmax(cvm2[cc], q2);
      if (M > 1 || kAgg) {
        csg[cc] = dmax(csg[cc], sig[sp[j]]);
        if (!kAgg) b2[sp[j]] = dmax(b2[sp[j]], q2);
      }
      vm2 = dmax(vm2, q2);
    }
  }
  if (M == 1 && !kAgg) { /* one diameter, one bound: no per-particle updates */
    std::fill(csg, csg + C, sig[0]);
    b2[0] = vm2;
  }
  for (int64_t q = 0; q < C; q++) start[q + 1] += start[q];
  /* creation sorted the particles: the first move is kSortEvery steps later */
  const bool reorder = !kAgg && c->reorder && c->step % kSortEvery == kSortEvery - 1;
  if (reorder && M == 1) { /* one species: the counting sort moves the particles themselves */
    int32_t *const fill = c->list.data();
    int64_t *const pos = c->fillpos.data();
    std::copy(start, start + C, pos);
    double *const xs = c->spare[0], *const vs = c->spare[1], *const rs = c->spare[2], *const ts = c->spare[3];
    const double *const r = s->p.r, *const tl = s->p.t_last;
    for (int64_t j = 0; j < N; j++) {
      const int64_t at = pos[cellof[j]]++;
      for (int q = 0; q < 3; q++) {
        xs[3 * at + q] = x[3 * j + q];
        vs[3 * at + q] = v[3 * j + q];
      }
      if (r)
        for (int q = 0; q < 3; q++) rs[3 * at + q] = r[3 * j + q];
      if (tl) ts[at] = tl[j];
    }
    for (int64_t e = 0; e < N; e++) fill[e] = (int32_t)e;
    std::swap(s->p.x, c->spare[0]);
    std::swap(s->p.v, c->spare[1]);
    if (r) std::swap(s->p.r, c->spare[2]);
    if (tl) std::swap(s->p.t_last, c->spare[3]);
  } else {
    int32_t *const fill = c->list.data(); /* stable within a cell */
    int64_t *const pos = c->fillpos.data();
    std::copy(start, start + C, pos);
    for (int64_t j = 0; j < N; j++) {
      const int64_t at = pos[cellof[j]]++;
      fill[at] = (int32_t)j;
      if (kAgg) c->where[(size_t)j] = at - start[cellof[j]];
    }
    if (reorder) cell_reorder(s, c);
  }
  c->vmax2 = vm2;
  cell_step_time(s);
}

/* The step count and the time after the streaming (trajectory samples within the step recorded on the way). */
void cell_step_time(gran_dsmc *s) {
  DsmcCell *const c = s->cell;
  c->step++;
  const double t = (double)c->step * c->o.dt; /* elapsed since t_start */
  s->t = dmax(s->t, t);
  if (s->opt.observe & GRAN_OBSERVE_TRAJECTORIES) /* grid times within the step: free flight */
    while (s->traj_next < s->opt.traj_samples && (double)s->traj_next * s->opt.traj_dt <= t) {
      const double keep = s->t;
      s->t = (double)s->traj_next * s->opt.traj_dt;
      dsmc_record_trajectories(s);
      s->t = keep;
    }
  s->t = t;
}

/* What the collisions of a step read and write (the particle arrays move when fragments grow them). */
struct CellStepCtx {
  gran_dsmc *s;
  DsmcCell *c;
  double *x, *v;
  int32_t *sp;
  const double *sig, *mass;
  const DsmcPair *pair;
  double *R;     /* displacements (kDisp) */
  int64_t *cnt;  /* collision counts per pair of species (kCount) */
  double kfac;   /* N_p = kfac N_c^2 sigma_max^2 2 vmax */
  double e_agg, e_frag, m1, t;
  int64_t M;
};
/* The running sums of the collisions: counters, dissipated energy (Neumaier), largest majorant,
 * the speed bounds (the largest |v|^2 of all particles, and of each species). */
struct CellAcc {
  int64_t coll, trials;
  double ed, edc, pmax;
  double *vmax2, *b2;
};

/* 2. The collisions of cell q, whose particles are lq[0 .. n): candidates drawn from w; the carried
 * fraction written back. kAtomic: the collision counts are shared between threads. */
template <int kRest, bool kDisp, bool kCount, bool kAgg, bool kAtomic, class W>
inline __attribute__((always_inline)) int collide_cell(CellStepCtx &k, int64_t q, int32_t *lq, int64_t n, W &w,
                                                       CellAcc &a, AggCtx *actx) {
  gran_dsmc *const s = k.s;
  DsmcCell *const c = k.c;
  const int64_t M = k.M;
  double *const csg = c->csg.data();
  double B = csg[q] * csg[q] * 2.0 * std::sqrt(c->cvm2[(size_t)q]); /* bound of sigma_jl^2 g2r |g| */
  double vmc2 = c->cvm2[(size_t)q];
  double want = k.kfac * (double)n * (double)n * B + c->rem[(size_t)q];
  a.pmax = dmax(a.pmax, 2.0 * k.kfac * B);
  if (kAgg) {
    actx->lq = lq;
    actx->n = &n;
  }
  while (want >= 1.0) {
    want -= 1.0;
    ++a.trials;
    const int64_t j = lq[w.below(n)], l = lq[w.below(n)];
    const double ub = w.uniform() * B;
    if (j == l) continue;
    const int32_t i = (M > 1 || kAgg) ? k.sp[j] : 0, kk = (M > 1 || kAgg) ? k.sp[l] : 0; /* one species: no load */
    double *vj = k.v + 3 * j, *vl = k.v + 3 * l;
    const double g[3] = {vj[0] - vl[0], vj[1] - vl[1], vj[2] - vl[2]};
    const double g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    const double sjl = 0.5 * (k.sig[i] + k.sig[kk]);
    double wgt = sjl * sjl;
    const size_t pik = (size_t)i * (size_t)M + (size_t)kk;
    if (kRest != kRestConst && k.pair) wgt *= k.pair[pik].g2r;
    if (!(ub * ub < wgt * wgt * g2)) continue; /* ub < wgt |g| (ub >= 0) without a root for the rejected */
    const double ga = std::sqrt(g2);
    double mi, mk;
    if (kAgg) {
      mi = (double)(i + 1) * k.m1;
      mk = (double)(kk + 1) * k.m1;
    } else {
      mi = k.mass[i];
      mk = k.mass[kk];
    }
    const double inv = 1.0 / (mi + mk);
    if constexpr (kAgg) {
      const double Eimp = 0.5 * mi * mk * inv * g2;
      if (Eimp < k.e_agg) { /* step 10b: merge */
        const int64_t n0 = n;
        agg_merge(*actx, j, l, i, kk, Eimp);
        k.sig = c->sigk.data();
        const double Bn = dmax(csg[q], k.sig[k.sp[j]]);
        csg[q] = Bn;
        const double Bnew = Bn * Bn * 2.0 * std::sqrt(vmc2);
        want *= ((double)n * (double)n * Bnew) / ((double)n0 * (double)n0 * B);
        B = Bnew;
        a.pmax = dmax(a.pmax, 2.0 * k.kfac * B);
        ++a.coll;
        continue;
      }
    }
    /* collision: e from the |g.e| law, (g.e) e = (g - |g| u)/2 */
    double u[3];
    w.unit3(u);
    const double gn[3] = {0.5 * (g[0] - ga * u[0]), 0.5 * (g[1] - ga * u[1]), 0.5 * (g[2] - ga * u[2])};
    const double gn2 = gn[0] * gn[0] + gn[1] * gn[1] + gn[2] * gn[2];
    if constexpr (kAgg) {
      if (0.5 * mi * mk * inv * gn2 > k.e_frag) { /* step 10d: shatter into monomers */
        const double vold = vmc2;
        agg_shatter(*actx, j, l, i, kk, 0.5 * mi * mk * inv * g2, ga, &vmc2);
        if (actx->status != GRAN_SUCCESS) return actx->status;
        k.x = s->p.x; /* the arrays may have moved */
        k.v = s->p.v;
        k.sp = s->p.species;
        k.sig = c->sigk.data();
        ++a.coll;
        const double sg = dmax(csg[q], dmax(k.sig[k.sp[j]], k.sig[k.sp[l]])); /* binary pieces may be larger */
        if (vmc2 > vold || sg > csg[q]) {
          csg[q] = sg;
          const double Bn = sg * sg * 2.0 * std::sqrt(vmc2);
          want *= Bn / B;
          B = Bn;
          a.pmax = dmax(a.pmax, 2.0 * k.kfac * B);
        }
        continue;
      }
    }
    const double eps = dsmc_pair_eps<kRest>(s, k.pair, pik, i, kk, gn2);
    const double al0 = (1.0 + eps) * inv;
    const double aj = al0 * mk, al = al0 * mi;
    for (int d = 0; d < 3; d++) {
      vj[d] -= aj * gn[d];
      vl[d] += al * gn[d];
    }
    if (kDisp) {
      double *const rj = k.R + 3 * j, *const rl = k.R + 3 * l;
      for (int d = 0; d < 3; d++) {
        rj[d] += aj * k.t * gn[d];
        rl[d] -= al * k.t * gn[d];
      }
    }
    neumaier_add(a.ed, a.edc, 0.5 * (1.0 - eps * eps) * mi * mk * inv * gn2);
    if (kCount) {
      int64_t *const ct = &k.cnt[(i < kk ? i : kk) * M + (i < kk ? kk : i)];
      if (kAtomic)
        __atomic_fetch_add(ct, 1, __ATOMIC_RELAXED);
      else
        ++*ct;
    }
    if (kAgg) c->bounces++;
    ++a.coll;
    const double sj = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
    const double sl = vl[0] * vl[0] + vl[1] * vl[1] + vl[2] * vl[2];
    if (!kAgg) {
      a.b2[i] = dmax(a.b2[i], sj);
      a.b2[kk] = dmax(a.b2[kk], sl);
    }
    const double s2 = dmax(sj, sl);
    if (s2 > vmc2) { /* the majorant rises: so do the candidates still to come */
      vmc2 = s2;
      const double Bn = csg[q] * csg[q] * 2.0 * std::sqrt(vmc2);
      want *= Bn / B;
      B = Bn;
      a.pmax = dmax(a.pmax, 2.0 * k.kfac * B);
      *a.vmax2 = dmax(*a.vmax2, s2);
    }
  }
  c->rem[(size_t)q] = want;
  return GRAN_SUCCESS;
}

/* the velocities (and species) of cell q's particles, which its candidates load at random; always inlined: out
 * of line, GCC takes a function of nothing but prefetches for one without effects and drops its calls */
inline __attribute__((always_inline)) void prefetch_cell(const int32_t *list, const int64_t *start, int64_t q,
                                                         const double *v, const int32_t *sp, bool species) {
  for (int64_t e = start[q]; e < start[q + 1]; e++) {
    __builtin_prefetch(v + 3 * list[e]);
    __builtin_prefetch(v + 3 * list[e] + 2);
    if (species) __builtin_prefetch(sp + list[e]);
  }
}

CellStepCtx step_ctx(gran_dsmc *s, bool agg) {
  DsmcCell *const c = s->cell;
  CellStepCtx k;
  k.s = s;
  k.c = c;
  k.x = s->p.x;
  k.v = s->p.v;
  k.sp = s->p.species;
  k.sig = agg ? c->sigk.data() : s->mix.sigma.data(); /* agg: moves when the sizes grow */
  k.mass = s->mix.m.data();
  k.pair = s->pair.empty() ? nullptr : s->pair.data();
  k.R = s->p.r;
  k.cnt = s->ccount.empty() ? nullptr : s->ccount.data();
  k.kfac = 0.5 * c->pfac * kPi * s->g2max;
  k.e_agg = c->o.e_agg;
  k.e_frag = c->o.e_frag;
  k.m1 = c->m1;
  k.t = (double)c->step * c->o.dt;
  k.M = s->M;
  return k;
}

/* 3. After the collisions: per-species bounds, the thermostat, the bath. */
template <bool kDisp, bool kAgg>
int cell_after_collisions(gran_dsmc *s, double t) {
  DsmcCell *const c = s->cell;
  if (kAgg) {
    dsmc_agg_end_step(s);
  } else {
    for (int64_t k = 0; k < s->M; k++) s->bound[(size_t)k] = std::sqrt(s->bound2[(size_t)k]);
  }
  if (c->o.heat_rate > 0) cell_heat<kDisp>(s, t);
  if (c->o.bath_density > 0) {
    GRAN_CALL(bath_check(s, true, t));
    cell_bath<kDisp>(s, t);
  }
  return GRAN_SUCCESS;
}

/* One step of GRAN_CELL_STREAMS_SERIAL: every draw from the engine's buffered streams, cell after cell. */
template <int kRest, bool kDisp, bool kCount, bool kAgg>
int cell_step(gran_dsmc *s) {
  DsmcCell *const c = s->cell;
  cell_stream_bin<kAgg>(s);
  const int64_t C = c->C, M = s->M, N = s->N;
  CellStepCtx k = step_ctx(s, kAgg);
  Words w{&s->vrng};
  int32_t *const list = c->list.data();
  const int64_t *const start = c->start.data();
  CellAcc acc{s->collisions, s->trials, s->e_diss, s->e_diss_c, 0.0, &c->vmax2, s->bound2.data()};
  AggCtx actx{s, c, &w, nullptr, nullptr, GRAN_SUCCESS};
  /* the prefetches pay where the particles do not fit the caches (the cell order's threshold): b503's
   * gas at N = 1e5 ran in 0.035 s without them against 0.036-0.037 s with, at 2e5 the same, at 3e5
   * in 0.145 s with them against 0.183 s without (min of 5-9 alternated runs) */
  const bool prefetch = kAgg || N >= kReorderMin;
  for (int64_t q = 0; q < C; q++) {
    if (prefetch && q + kAhead < C) prefetch_cell(list, start, q + kAhead, k.v, k.sp, M > 1 || kAgg);
    const int st =
        collide_cell<kRest, kDisp, kCount, kAgg, false>(k, q, list + start[q], start[q + 1] - start[q], w, acc, &actx);
    if (st != GRAN_SUCCESS) return st;
  }
  c->pmax_last = acc.pmax;
  s->collisions = acc.coll;
  s->trials = acc.trials;
  s->e_diss = acc.ed;
  s->e_diss_c = acc.edc;
  return cell_after_collisions<kDisp, kAgg>(s, k.t);
}

/* ---- GRAN_CELL_STREAMS_CELLS: streams by cell ----
 * Every draw of a step comes from the generator of its cell and step, keyed (core/keyed.h) by
 * id = step x C + cell with a tag per use: the collisions and then the thermostat's kicks of the
 * cell's particles (kTagCollide), the bath's collisions of its particles (kTagBath). A cell's
 * particles are taken in the order of their keys (cell << 32 | place in the cell's list at the end of
 * the last step), whatever their places in the arrays; the dissipated energy and the thermostat's
 * sums are summed per cell and then exactly (gran_exactsum) over the cells, counters are integers and
 * bounds maxima. So the step's result does not depend on the order in which the cells are done, nor
 * on who does them: the cells are spread over OpenMP threads, and the state is the same, bit for bit,
 * for any number of threads (and, with the same keys, for any split of the cells). */
constexpr uint64_t kTagCollide = 0x63656c6c2d636f6cULL; /* "cell-col" */
constexpr uint64_t kTagBath = 0x63656c6c2d626174ULL;    /* "cell-bat" */

inline DsmcCellWords cell_words(uint64_t seed, uint64_t tag, int64_t step, int64_t C, int64_t q) {
  gran_rng r;
  keyed_rng(seed, tag, (uint64_t)step * (uint64_t)C + (uint64_t)q, &r);
  return DsmcCellWords(r);
}

/* The threads of a step: gran_set_threads (0: the OpenMP default); one inside a parallel region
 * (replicas already spread over the threads). */
int cell_threads() {
#ifdef _OPENMP
  int32_t n = 1;
  gran_get_threads(&n);
  return omp_in_parallel() ? 1 : std::max<int32_t>(1, n);
#else
  return 1;
#endif
}

inline int thread_num() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

/* A thread's share of a step's sums. */
struct CellPart {
  gran_exactsum ed, heat, P[3];
  std::vector<double> b2;
  double vmax2 = 0, pmax = 0;
  int64_t coll = 0, trials = 0;
  void reset(int64_t M) {
    gran_exactsum_init_(&ed);
    gran_exactsum_init_(&heat);
    for (auto &x : P) gran_exactsum_init_(&x);
    b2.assign((size_t)M, 0.0);
  }
};

/* the parts' bounds into the engine's (maxima) */
void merge_bounds(gran_dsmc *s, const std::vector<CellPart> &parts) {
  DsmcCell *const c = s->cell;
  double *const b2 = s->bound2.data();
  for (const CellPart &p : parts) {
    c->vmax2 = dmax(c->vmax2, p.vmax2);
    for (int64_t k = 0; k < s->M; k++) b2[k] = dmax(b2[k], p.b2[(size_t)k]);
  }
  for (int64_t k = 0; k < s->M; k++) s->bound[(size_t)k] = std::sqrt(b2[k]);
}
/* the exact sum over the parts of one of their accumulators, rounded once */
template <class F>
double merged_value(std::vector<CellPart> &parts, const F &field) {
  gran_exactsum t;
  gran_exactsum_init_(&t);
  for (CellPart &p : parts) gran_exactsum_merge_(&t, &field(p));
  return gran_exactsum_value_(&t);
}
inline CellPart &my_part(std::vector<CellPart> &parts) { return parts[(size_t)thread_num()]; }

/* 1. (streams by cell) Stream and bin in nth threads: the particles' blocks stream in parallel (the
 * speed bounds into the parts), then a stable sort by cell of the particles in key order (c->order),
 * cut into nth chunks: each chunk counts its particles per cell, and fills its places in the lists,
 * which are those of the one-thread sort. The per-cell largest speed and diameter are found in the
 * collision pass. */
void cell_bin_by_cells(gran_dsmc *s, int nth, std::vector<CellPart> &parts) {
  DsmcCell *const c = s->cell;
  const int64_t N = s->N, C = c->C, M = s->M, nc = c->nc;
  const double dt = c->o.dt, L = c->L, invL = 1.0 / L, inv_a = c->inv_a;
  double *const x = s->p.x, *const v = s->p.v;
  const int32_t *const sp = s->p.species;
  int32_t *const cellof = c->cellof.data();
  int64_t *const start = c->start.data();
  const int32_t *const ord = c->order.data();
  int32_t *const list = c->list.data();
  /* one thread: the counts during the streaming, the places in start */
  c->tcount.assign(nth > 1 ? (size_t)nth * (size_t)C : 0, 0);
  int32_t *const cnt = c->tcount.data();
  if (nth == 1) std::fill(start, start + C + 1, 0);
  constexpr int64_t kBlock = 512;
  const int64_t nblk = (N + kBlock - 1) / kBlock;
#pragma omp parallel num_threads(nth)
  {
    const int th = thread_num();
    CellPart &p = parts[(size_t)th];
    double *const b2 = p.b2.data();
    double vm2 = 0;
    alignas(64) int32_t qb[3 * kBlock];
#pragma omp for schedule(static)
    for (int64_t b = 0; b < nblk; b++) {
      const int64_t j0 = b * kBlock, nb = std::min(kBlock, N - j0);
      stream_particles(x, v, qb, j0, nb, dt, L, invL, inv_a, (int32_t)nc - 1);
      for (int64_t j = j0; j < j0 + nb; j++) {
        const int32_t *const qj = qb + 3 * (j - j0);
        const double *vj = v + 3 * j;
        const int64_t cc = ((int64_t)qj[0] * nc + qj[1]) * nc + qj[2];
        cellof[j] = (int32_t)cc;
        if (nth == 1) start[cc + 1]++;
        const double q2 = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
        if (M > 1) b2[sp[j]] = dmax(b2[sp[j]], q2);
        vm2 = dmax(vm2, q2);
      }
    }
    p.vmax2 = dmax(p.vmax2, vm2);
    if (M == 1) b2[0] = dmax(b2[0], vm2);
    if (nth == 1) { /* the stable sort in one pass */
      for (int64_t q = 0; q < C; q++) start[q + 1] += start[q];
      int64_t *const pos = c->fillpos.data();
      std::copy(start, start + C, pos);
      for (int64_t e = 0; e < N; e++) {
        const int32_t j = ord[e];
        list[pos[cellof[j]]++] = j;
      }
    }
  }
  if (nth > 1) {
#pragma omp parallel num_threads(nth)
  {
    const int th = thread_num();
    /* counts of chunk th of the key order */
    const int64_t e0 = N * th / nth, e1 = N * (th + 1) / nth;
    int32_t *const ct = cnt + (size_t)th * (size_t)C;
    for (int64_t e = e0; e < e1; e++) ct[cellof[ord[e]]]++;
#pragma omp barrier
#pragma omp single
    { /* start[q]: the cells before q; chunk t's first place in cell q: start[q] + the chunks before t */
      int64_t at = 0;
      for (int64_t q = 0; q < C; q++) {
        start[q] = at;
        for (int t = 0; t < nth; t++) {
          const int32_t n = cnt[(size_t)t * (size_t)C + (size_t)q];
          cnt[(size_t)t * (size_t)C + (size_t)q] = (int32_t)at;
          at += n;
        }
      }
      start[C] = at;
    }
    for (int64_t e = e0; e < e1; e++) {
      const int32_t j = ord[e];
      list[ct[cellof[j]]++] = j;
    }
  }
  }
  c->vmax2 = 0;
  std::fill(s->bound2.begin(), s->bound2.end(), 0.0);
  merge_bounds(s, parts);
  cell_step_time(s);
}

template <int kRest, bool kDisp, bool kCount>
int cell_step_by_cells(gran_dsmc *s) {
  DsmcCell *const c = s->cell;
  const int64_t C = c->C, M = s->M;
  const int nth = (int)std::min<int64_t>(cell_threads(), std::max<int64_t>(1, std::min(C, s->N) / 64));
  std::vector<CellPart> parts((size_t)nth);
  for (CellPart &p : parts) p.reset(M);
  cell_bin_by_cells(s, nth, parts);
  const int64_t step = c->step;
  const uint64_t seed = s->opt.seed;
  CellStepCtx k = step_ctx(s, false);
  int32_t *const list = c->list.data();
  const int64_t *const start = c->start.data();
  double *const v = s->p.v, *const R = kDisp ? s->p.r : nullptr;
  const int32_t *const sp = s->p.species;
  const double *const mass = s->mix.m.data();
  const double t = k.t;
  const bool heat = c->o.heat_rate > 0, bath = c->o.bath_density > 0;
  const double hd = c->o.heat_rate * c->o.dt;
  const bool prefetch = s->N >= kReorderMin;
  const double *const sig = s->mix.sigma.data();
  double *const cvm2 = c->cvm2.data(), *const csg = c->csg.data();
  /* pass 1, per cell (its list in key order): the collisions, the kicks */
#pragma omp parallel for schedule(dynamic, 16) num_threads(nth)
  for (int64_t q = 0; q < C; q++) {
    CellPart &p = my_part(parts);
    int32_t *const lq = list + start[q];
    const int64_t n = start[q + 1] - start[q];
    if (prefetch && q + kAhead < C) prefetch_cell(list, start, q + kAhead, v, sp, M > 1);
    double vm = 0, sg = 0; /* the cell's largest speed and diameter */
    for (int64_t e = 0; e < n; e++) {
      const double *const vj = v + 3 * lq[e];
      vm = dmax(vm, vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2]);
      if (M > 1) sg = dmax(sg, sig[sp[lq[e]]]);
    }
    cvm2[q] = vm;
    csg[q] = M > 1 ? sg : sig[0];
    DsmcCellWords w = cell_words(seed, kTagCollide, step, C, q);
    CellAcc a{0, 0, 0.0, 0.0, 0.0, &p.vmax2, p.b2.data()};
    collide_cell<kRest, kDisp, kCount, false, true>(k, q, lq, n, w, a, nullptr);
    p.coll += a.coll;
    p.trials += a.trials;
    p.pmax = dmax(p.pmax, a.pmax);
    gran_exactsum_add_(&p.ed, a.ed);
    gran_exactsum_add_(&p.ed, a.edc);
    if (heat) {
      double P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0}, de = 0, dec = 0;
      for (int64_t e = 0; e < n; e++) {
        const int32_t j = lq[e];
        const double m = mass[sp[j]];
        heat_kick<kDisp>(v + 3 * j, kDisp ? R + 3 * j : nullptr, m, std::sqrt(hd / m), t, w, P, Pc, de, dec);
      }
      for (int d = 0; d < 3; d++) {
        gran_exactsum_add_(&p.P[d], P[d]);
        gran_exactsum_add_(&p.P[d], Pc[d]);
      }
      gran_exactsum_add_(&p.heat, de);
      gran_exactsum_add_(&p.heat, dec);
    }
  }
  /* the cell order: the particles move into their lists' order (list is rewritten with their new places) */
  if (c->reorder && (step - 1) % kSortEvery == kSortEvery - 1) {
    cell_reorder(s, c);
    k.v = s->p.v;
  }
  double *const v2 = s->p.v, *const R2 = kDisp ? s->p.r : nullptr;
  double pmax = 0;
  for (const CellPart &p : parts) {
    s->collisions += p.coll;
    s->trials += p.trials;
    pmax = dmax(pmax, p.pmax);
  }
  c->pmax_last = pmax;
  neumaier_add(s->e_diss, s->e_diss_c, merged_value(parts, [](CellPart &p) -> gran_exactsum & { return p.ed; }));
  merge_bounds(s, parts);
  if (heat) { /* pass 2, per cell: the mass-weighted mean kick off every particle */
    double mt = 0, mtc = 0;
    for (int64_t kk = 0; kk < M; kk++) neumaier_add(mt, mtc, mass[kk] * (double)s->count[(size_t)kk]);
    double u[3];
    for (int d = 0; d < 3; d++)
      u[d] = merged_value(parts, [d](CellPart &p) -> gran_exactsum & { return p.P[d]; }) / (mt + mtc);
#pragma omp parallel for schedule(dynamic, 16) num_threads(nth)
    for (int64_t q = 0; q < C; q++) {
      CellPart &p = my_part(parts);
      double de = 0, dec = 0;
      for (int64_t e = start[q]; e < start[q + 1]; e++) {
        const int32_t j = list[e];
        const double q2 = heat_recentre<kDisp>(v2 + 3 * j, kDisp ? R2 + 3 * j : nullptr, mass[sp[j]], u, t, de, dec);
        p.vmax2 = dmax(p.vmax2, q2);
        p.b2[(size_t)sp[j]] = dmax(p.b2[(size_t)sp[j]], q2);
      }
      gran_exactsum_add_(&p.heat, de);
      gran_exactsum_add_(&p.heat, dec);
    }
    merge_bounds(s, parts);
  }
  if (bath) { /* pass 3, per cell: the bath's collisions of its particles, from the cell's bath stream */
    GRAN_CALL(bath_check(s, true, t));
    const BathLaw law = bath_law(c);
#pragma omp parallel for schedule(dynamic, 16) num_threads(nth)
    for (int64_t q = 0; q < C; q++) {
      CellPart &p = my_part(parts);
      DsmcCellWords w = cell_words(seed, kTagBath, step, C, q);
      double de = 0, dec = 0;
      for (int64_t e = start[q]; e < start[q + 1]; e++) {
        const int32_t j = list[e];
        const double q2 =
            bath_particle<kDisp>(v2 + 3 * j, kDisp ? R2 + 3 * j : nullptr, mass[sp[j]], sig[sp[j]], law, t, w, de, dec);
        p.vmax2 = dmax(p.vmax2, q2);
        p.b2[(size_t)sp[j]] = dmax(p.b2[(size_t)sp[j]], q2);
      }
      gran_exactsum_add_(&p.heat, de);
      gran_exactsum_add_(&p.heat, dec);
    }
    merge_bounds(s, parts);
  }
  if (heat || bath)
    neumaier_add(c->e_heat, c->e_heat_c, merged_value(parts, [](CellPart &p) -> gran_exactsum & { return p.heat; }));
  c->order.swap(c->list); /* the new keys: this step's lists one after the other */
  return GRAN_SUCCESS;
}

typedef int (*CellStepFn)(gran_dsmc *s);
template <bool kDisp, bool kCount>
CellStepFn pick_rest(int rest, bool by_cells) {
  if (by_cells) switch (rest) {
      case kRestTable: return &cell_step_by_cells<kRestTable, kDisp, kCount>;
      case kRestVisco: return &cell_step_by_cells<kRestVisco, kDisp, kCount>;
      default: return &cell_step_by_cells<kRestConst, kDisp, kCount>;
    }
  switch (rest) {
    case kRestTable: return &cell_step<kRestTable, kDisp, kCount, false>;
    case kRestVisco: return &cell_step<kRestVisco, kDisp, kCount, false>;
    default: return &cell_step<kRestConst, kDisp, kCount, false>;
  }
}
CellStepFn pick_step(const gran_dsmc *s) {
  if (s->cell->agg) return &cell_step<kRestConst, false, false, true>; /* dsmc_agg_setup checked these */
  const bool disp = s->p.r != nullptr, counts = !s->ccount.empty(), bc = s->cell->by_cells != 0;
  if (disp) return counts ? pick_rest<true, true>(s->rest, bc) : pick_rest<true, false>(s->rest, bc);
  return counts ? pick_rest<false, true>(s->rest, bc) : pick_rest<false, false>(s->rest, bc);
}

}  // namespace

int dsmc_cell_advance(gran_dsmc *s, double t_end, int64_t coll_stop) {
  DsmcCell *const c = s->cell;
  const CellStepFn fn = pick_step(s);
  const double dt = c->o.dt;
  const bool by_time = t_end < DBL_MAX;
  if (by_time) { /* the steps to t_end within the bound of every time-stepped run (core/run_bounds.h) */
    char why[320];
    const double steps = t_end / dt - (double)c->step;
    GRAN_CHECK(gran_run_steps_ok(steps, (double)s->N + (double)c->C, why, sizeof why), GRAN_ERR_ARG,
               "argument 't_end' = %g in steps of cell option 'dt' = %g: %s", s->opt.t_start + t_end, dt, why);
  }
  for (;;) {
    if (by_time) {
      if ((double)(c->step + 1) * dt > t_end + 1e-9 * dt) break;
    } else {
      if (s->collisions >= coll_stop) break;
      GRAN_CHECK(c->vmax2 > 0 && s->N >= 2 && s->g2max > 0, GRAN_ERR_STATE,
                 "no collision can happen: " GRAN_I64_FMT " particle(s), largest speed %g, contact value %g", s->N,
                 std::sqrt(c->vmax2), s->g2max);
    }
    GRAN_CALL(check_dt(s, "for the speeds reached"));
    GRAN_CALL(fn(s));
  }
  if (by_time) {
    if (s->opt.observe & GRAN_OBSERVE_TRAJECTORIES)
      while (s->traj_next < s->opt.traj_samples && (double)s->traj_next * s->opt.traj_dt <= t_end) {
        s->t = (double)s->traj_next * s->opt.traj_dt;
        dsmc_record_trajectories(s);
      }
    s->t = t_end;
  }
  return GRAN_SUCCESS;
}

}  // namespace gran

using namespace gran;

/** @brief Defaults of the cell options (see the header). */
GRAN_EXTERN int gran_dsmc_cell_options_default(gran_dsmc_cell_options *cell) {
  GRAN_CHECK_PTR(cell);
  *cell = gran_dsmc_cell_options{};
  cell->cells = 1;
  cell->dt = 0;
  cell->fn = 1;
  cell->e_agg = 0;
  cell->e_frag = INFINITY;
  cell->eps_f = 1;
  cell->heat_rate = 0;
  cell->bath_density = 0;
  cell->bath_mass = 1;
  cell->bath_T = 1;
  cell->bath_sigma = 1;
  cell->placement = GRAN_PLACE_RANDOM;
  return GRAN_SUCCESS;
}

/** @brief New engine of the time-step/cell selector (the DSMC outline).
 *  @param[in] opt engine options (selector is taken as GRAN_SELECTOR_CELL; volume: the box volume)
 *  @param[in] cell cells, dt, F_N and the effects  @param[out] sim the new engine */
GRAN_EXTERN int gran_dsmc_create_cell(const gran_mixture *mix, const int64_t *counts, const double *T0,
                                      const gran_dsmc_options *opt, const gran_dsmc_cell_options *cell,
                                      gran_dsmc **sim) {
  GRAN_TRY {
    GRAN_CHECK_PTR(sim);
    *sim = nullptr;
    GRAN_CHECK_PTR(mix);
    GRAN_CHECK_PTR(opt);
    GRAN_CHECK_PTR(cell);
    GRAN_CALL(dsmc_cell_check_options(cell));
    gran_dsmc_options o = *opt;
    o.selector = GRAN_SELECTOR_CELL;
    if (o.volume > 0) o.volume /= cell->fn; /* the engine's volume: per simulated particle */
    return dsmc_create_impl(mix, counts, T0, &o, cell, sim);
  }
  GRAN_CATCH
}

/** @brief Steps done, box side, largest F_N (sigma g)_max dt / V_c of the last step. */
GRAN_EXTERN int gran_dsmc_cell_info(const gran_dsmc *sim, int64_t *steps, double *box, double *pmax) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK(sim->cell != nullptr, GRAN_ERR_STATE, "engine 'sim' does not use the cell selector");
    if (steps) *steps = sim->cell->step;
    if (box) *box = sim->cell->L;
    if (pmax) *pmax = sim->cell->pmax_last;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
