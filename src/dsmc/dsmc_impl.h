/* dsmc_impl.h - private state of the DSMC engine (src/dsmc). Never installed.
 *
 * One engine state, two pair selectors (low-rank trees, Bird's global bound), one hot loop that is
 * a template over the effects that are on (dsmc_loop.h). Particles are stored grouped by species:
 * species k occupies slots [offset[k], offset[k+1]) of the gran_particles arrays and never moves,
 * so a particle's index is its identity (tracers, checkpoints).
 *
 * Rates (PHYSICS-NOTES Sec. 1): the physical rate of an unordered pair {j, l} is
 * g2_jl pi sigma_jl^2 |g| / V. Both selectors propose pairs at a rate that bounds it and accept
 * with the ratio; the "paper" variants draw e uniformly and accept |g.e| (Eq. 40 / 48), the
 * default variants accept |g| against a bound half as large and then draw e from its |g.e|-weighted
 * law (the same collision statistics with twice the acceptance).
 */
#ifndef GRANARY_DSMC_IMPL_H
#define GRANARY_DSMC_IMPL_H

#include "granary_impl.h"
#include "theory/theory_impl.h"

#include <vector>

namespace gran {

/* Pre-drawn candidate pairs: the particle indices of the next trials are drawn ahead and their
 * cache lines prefetched, so the memory latency of a trial overlaps the work of the trials before
 * it. Candidates are independent of the velocities; they are discarded ("flushed") whenever the
 * selection law changes (a bound is raised or the bounds are tightened). Part of the state. */
#ifndef GRAN_DSMC_PIPE
#define GRAN_DSMC_PIPE 16 /* power of two; measured in bench/b501-dsmc.c */
#endif
enum { kDsmcPipe = GRAN_DSMC_PIPE };

struct DsmcCand {
  int64_t j, l;   /* particle indices */
  int32_t i, k;   /* their species (low-rank: known at draw time; Bird: filled at use) */
};

/* Buffered random numbers for the hot loop: kRngLanes xoshiro256** streams (gran_rng_stream
 * 1..kRngLanes of the seed: independent, non-overlapping) advanced together in a loop the compiler
 * vectorises, kRngBuf outputs at a time. The scalar generator's state goes through memory at every
 * call when the loop hands it to a helper (7 calls per trial): measured in b501. Part of the state
 * (checkpointed with the unread part of the buffer). */
enum { kRngLanes = 8, kRngBuf = 512 };
struct DsmcRng {
  uint64_t s[4][kRngLanes];
  uint64_t buf[kRngBuf];
  int32_t pos; /* next unread output; kRngBuf: empty */
};

/* GCC vector extension: one operation per kRngLanes lanes (AVX-512 or split by the compiler). */
typedef uint64_t DsmcLanes __attribute__((vector_size(8 * kRngLanes)));

static inline void dsmc_rng_refill(DsmcRng *r) {
  DsmcLanes s0, s1, s2, s3;
  std::memcpy(&s0, r->s[0], sizeof s0);
  std::memcpy(&s1, r->s[1], sizeof s1);
  std::memcpy(&s2, r->s[2], sizeof s2);
  std::memcpy(&s3, r->s[3], sizeof s3);
  for (int b = 0; b < kRngBuf; b += kRngLanes) {
    const DsmcLanes x = s1 * 5;
    const DsmcLanes out = ((x << 7) | (x >> 57)) * 9;
    std::memcpy(r->buf + b, &out, sizeof out);
    const DsmcLanes t = s1 << 17;
    s2 ^= s0;
    s3 ^= s1;
    s1 ^= s2;
    s0 ^= s3;
    s2 ^= t;
    s3 = (s3 << 45) | (s3 >> 19);
  }
  std::memcpy(r->s[0], &s0, sizeof s0);
  std::memcpy(r->s[1], &s1, sizeof s1);
  std::memcpy(r->s[2], &s2, sizeof s2);
  std::memcpy(r->s[3], &s3, sizeof s3);
  r->pos = 0;
}

static inline double u64_uniform(uint64_t x) { return (double)(x >> 11) * 0x1.0p-53; }           /* [0,1) */
static inline double u64_uniform_pos(uint64_t x) { return ((double)(x >> 11) + 1.0) * 0x1.0p-53; } /* (0,1] */
/* integer in [0, n) (multiply-shift) */
static inline int64_t u64_below(uint64_t x, int64_t n) {
  return (int64_t)(((unsigned __int128)x * (unsigned __int128)(uint64_t)n) >> 64);
}

/* Per-pair parameters for the table modes: a = eps (table) or sqrt(beta) (viscoelastic);
 * g2r = g2_ik / g2_max (the extra acceptance factor of a non-uniform contact value). */
struct DsmcPair {
  double a;
  double g2r;
};

/* How the restitution (and g2) of a pair is found in the hot loop. */
enum DsmcRest {
  kRestConst = 0, /* one eps, uniform g2: no table */
  kRestTable = 1, /* eps per pair from the M*M table (matrix model or non-uniform g2) */
  kRestVisco = 2  /* eps(v_n) with sqrt(beta) per pair: from the table, or from the mixture formula */
};

/* Neumaier compensated summation (the ledger must close to 1e-12 after 1e7 collisions). */
static inline void neumaier_add(double &s, double &c, double x) {
  const double t = s + x;
  if (std::fabs(s) >= std::fabs(x))
    c += (s - t) + x;
  else
    c += (x - t) + s;
  s = t;
}

/* Time-step/cell selector state (cell.cpp, cell_impl.h); NULL for the event selectors. */
struct DsmcCell;

}  // namespace gran

struct gran_dsmc {
  /* ---- configuration (fixed at creation) ---- */
  gran_dsmc_options opt;
  gran_mixture mix;              /* own copy of the mixture (pair accessors of theory_impl.h) */
  int64_t M = 0;                 /* species */
  int64_t N = 0;                 /* particles */
  double volume = 0;
  std::vector<int64_t> count;    /* M */
  std::vector<int64_t> offset;   /* M+1 */
  int selector = 0;              /* gran_selector */
  int paper = 0;                 /* 1: the paper's acceptance rule (e uniform, |g.e|) */
  int rest = gran::kRestConst;   /* gran::DsmcRest */
  double eps0 = 1;               /* kRestConst */
  double g2max = 1;              /* rates are scaled by the largest contact value */
  std::vector<gran::DsmcPair> pair; /* M*M for the table modes (empty: scalar / formula) */
  double visco_sqrt_beta0 = -1;  /* viscoelastic with one beta and no table: sqrt(beta) */
  /* Tracers (seed 000 Sec. II F): species with n_k = 0 in the mixture but N_k > 0 particles.
   * They collide with the gas (n_k > 0) at the physical rate, only the tracer's velocity changes,
   * and tracer-tracer candidates are rejected. Derived from mix and counts at creation (so a
   * checkpoint reader derives it from the mixture it is given; the file stores it for a check). */
  std::vector<uint8_t> tracer;   /* M: 1 for a tracer species */
  int has_tracers = 0;           /* any tracer: the loop instantiation with the tracer branch */
  int64_t n_gas = 0;             /* particles of the non-tracer species */
  double sigma_max = 0;          /* largest diameter among non-empty species (Bird) */
  std::vector<double> bird_w;    /* ((sigma_i + sigma_max)/2)^2 (Bird) */
  int64_t refresh_interval = 0;  /* collisions between tightenings of the bounds */

  /* ---- state ---- */
  gran_particles p{};            /* grouped by species */
  std::vector<double> bound;     /* M: max speed per species (exact maximum at the last refresh) */
  std::vector<double> bound2;    /* M: bound^2 */
  gran_segtree u[3]{};           /* low-rank: u^(r)_i (depend on the bounds) */
  gran_segtree v[3]{};           /* low-rank: v^(r)_k (depend on the counts only) */
  double uv[3] = {0, 0, 0};      /* U_r V_r: the weights of the three rank-one terms */
  double inv_vtot[3] = {0, 0, 0}; /* 1 / V_r (constant) */
  std::vector<double> alias_p[3];  /* Walker alias tables of v^(r) (constant): O(1) species k */
  std::vector<int32_t> alias_k[3];
  double cmax = 0;               /* Bird: C_max of Eq. 49 (without pi/V) */
  double rate = 0;               /* total trial rate Lambda */
  double inv_rate = 0;           /* 1/Lambda (inf when 0) */
  gran_rng rng{};                /* scalar stream: initial velocities */
  gran::DsmcRng vrng{};          /* buffered streams: the hot loop */
  double t = 0;                  /* time of the state */
  double t_ref = 0;              /* time of the last collision (or of the start): trial times count from it */
  double tprod = 1, tlog = 0;    /* trials since t_ref: product of their uniforms, folded -log */
  int32_t pend_on = 0;           /* 1: an accepted collision lies beyond the last stop time */
  gran::DsmcCand pend_c{};
  double pend_t = 0;
  double pend_e[3] = {0, 0, 0};  /* its direction (paper rule) */
  int64_t collisions = 0, trials = 0, bound_raises = 0, bound_tightenings = 0;
  int64_t next_refresh = 0;      /* collision count at which the bounds are tightened next */
  int64_t coll_at_refresh = 0, trials_at_refresh = 0;
  double acc_last = 0;           /* acceptance of the last completed window */
  double e_initial = 0;
  double e_diss = 0, e_diss_c = 0; /* dissipated energy: Neumaier sum and its compensation */
  std::vector<int64_t> ccount;   /* M*M, upper triangle (i <= k) used; only with COLLISION_COUNTS */
  /* pipeline of pre-drawn candidates */
  gran::DsmcCand cand[gran::kDsmcPipe]{};
  int32_t cand_head = 0, cand_count = 0;
  /* trajectories */
  int64_t ntraj = 0;
  std::vector<int64_t> traj_index;  /* ntraj particle indices */
  std::vector<int32_t> traj_species;
  std::vector<double> traj_xyz;     /* ntraj * traj_samples * 3 (NaN until recorded) */
  int64_t traj_next = 0;            /* next sample to record */
  /* time-step/cell selector (GRAN_SELECTOR_CELL): positions, cells, aggregation; else NULL */
  gran::DsmcCell *cell = nullptr;
};

namespace gran {

/* ---- engine.cpp ---- */
/* Allocate everything for mix/counts/options, no velocities drawn (used by create and checkpoint read). */
int dsmc_alloc(const gran_mixture *mix, const int64_t *counts, const gran_dsmc_options *opt, gran_dsmc *s);
/* Rebuild the selector state (trees / C_max) from the bounds, recompute the rate, flush the pipeline. */
void dsmc_selector_rebuild(gran_dsmc *s);
/* Recompute the exact maximum speed per species, then dsmc_selector_rebuild. */
void dsmc_refresh_bounds(gran_dsmc *s);
/* Raise the bound of species i to speed^2 s2 (called from the hot loop; rare). */
void dsmc_raise_bound(gran_dsmc *s, int32_t i, double s2);
/* Rate and 1/rate from the current selector state. */
void dsmc_update_rate(gran_dsmc *s);
int dsmc_check(const gran_dsmc *s, const char *name);

/* ---- hot loops (lowrank.cpp, bird.cpp) ----
 * Run trials until the pending trial lies beyond t_stop or the collision count reaches coll_stop. */
typedef void (*DsmcLoopFn)(gran_dsmc *s, double t_stop, int64_t coll_stop);
DsmcLoopFn dsmc_lowrank_loop(int paper, int disp, int counts, int rest, int tracers);
DsmcLoopFn dsmc_bird_loop(int paper, int disp, int counts, int rest, int tracers);

/* ---- cell.cpp (GRAN_SELECTOR_CELL) ---- */
void dsmc_cell_free(gran_dsmc *s);
/* after the velocities of a new engine: positions, cells (checks the cell options) */
int dsmc_cell_init(gran_dsmc *s, const gran_dsmc_cell_options *cell);
/* engine.cpp: gran_dsmc_create, with the cell options for GRAN_SELECTOR_CELL */
int dsmc_create_impl(const gran_mixture *mix, const int64_t *counts, const double *T0, const gran_dsmc_options *opt,
                     const gran_dsmc_cell_options *cell, gran_dsmc **sim);
/* steps up to t_end (elapsed since t_start) or until coll_stop collisions (t_end = DBL_MAX) */
int dsmc_cell_advance(gran_dsmc *s, double t_end, int64_t coll_stop);

/* ---- observables.cpp ---- */
void dsmc_record_trajectories(gran_dsmc *s);
/* Mean flow of the gas (species that are not tracers), Neumaier-summed; 0 without gas. */
void dsmc_mean_flow(const gran_dsmc *s, double u[3]);

}  // namespace gran

#endif
