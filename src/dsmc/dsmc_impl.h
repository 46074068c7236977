/* dsmc_impl.h - private state of the DSMC engine (src/dsmc). Never installed.
 *
 * One engine state, two pair selectors (low-rank trees, Bird's global bound), one hot loop that is
 * a template over the effects that are on (dsmc_loop.h). Particles are stored grouped by species:
 * species k occupies slots [offset[k], offset[k+1]) of the gran_particles arrays and never moves,
 * so a particle's index is its identity (tracers, checkpoints).
 *
 * Rates (docs/physics.md, "Corrections to the sources"): the physical rate of an unordered pair {j, l} is
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
  int64_t j, l;   /* particle indices (with speed classes: slots) */
  int32_t i, k;   /* their species (low-rank: known at draw time; Bird: filled at use) */
  int32_t a, b;   /* speed classes: the leaves (species, class) of the slots j, l; else 0 */
};

/* ---- speed classes (opt.speed_classes with the low-rank selectors) ----
 * Within each species with at least kClassMin particles the slots are split into kClassNum
 * classes c, each owning the fixed slots [start, start + cap) of which [start, start + n) hold
 * particles. The trees are built over the leaves (species, class) with the capacity in place of
 * the count and the class bound b in place of the species bound, so the law of the proposed slot
 * pairs depends on capacities and bounds only, which change at a tightening (and when a top class
 * is raised), never when a particle changes class: a proposed slot that is empty at use time is
 * rejected (a rate-0 virtual particle), an occupied one stands for whoever occupies it then. A
 * particle may sit in any class of its species whose bound is at least its speed; after a
 * collision it moves to the lowest such class with room (up when it became too fast, down when
 * it fits a lower class), copied into that class's first free slot, its hole filled by the last
 * particle of its old class. Thresholds b_c = w a0 rho^c (w: the species' rms speed at the last
 * tightening), the top class open (the species' largest speed, raised like a species bound).
 * Small species keep one class of cap = N_k (no holes, never moves). */
#ifndef GRAN_DSMC_CLASS_RHO
#define GRAN_DSMC_CLASS_RHO 1.25 /* threshold ratio; measured in bench/b501-dsmc.c */
#endif
#ifndef GRAN_DSMC_CLASS_A0
#define GRAN_DSMC_CLASS_A0 0.4 /* bottom threshold / rms speed */
#endif
#ifndef GRAN_DSMC_CLASS_NUM
#define GRAN_DSMC_CLASS_NUM 11 /* classes of a large species: thresholds up to ~2.5 rms, then the top */
#endif
#ifndef GRAN_DSMC_CLASS_SLACK
#define GRAN_DSMC_CLASS_SLACK 0.05 /* free slots per particle of a large species (0.1: lower acceptance) */
#endif
#ifndef GRAN_DSMC_CLASS_ANCHOR
#define GRAN_DSMC_CLASS_ANCHOR 1 /* 1: w rounded to w_ref rho^m (w_ref: the rms speed at the first sort), so
                                  * that most particles keep their class at a sort (2-4% faster: b501 note) */
#endif
#ifndef GRAN_DSMC_CLASS_DOWN
#define GRAN_DSMC_CLASS_DOWN 2 /* 1: a particle that fits the class below moves down when there is room; 2: only when it fits two classes below (fewer moves, same acceptance: b501) */
#endif
#ifndef GRAN_DSMC_CLASS_KEY_COUNT
#define GRAN_DSMC_CLASS_KEY_COUNT 1 /* 1: the sort's class of a particle by counting thresholds (classes.cpp) */
#endif
#ifndef GRAN_DSMC_CLASS_AUTO_M
#define GRAN_DSMC_CLASS_AUTO_M 2 /* GRAN_SPEED_CLASSES_AUTO: on from this many non-empty species (classes.cpp) */
#endif
enum { kClassNum = GRAN_DSMC_CLASS_NUM, kClassMin = 256, kClassExtra = 4 };
static_assert(kClassNum >= 2 && kClassNum <= 64, "GRAN_DSMC_CLASS_NUM out of range");

struct alignas(64) DsmcLeaf {
  double b, b2;      /* bound of the class (speed) and its square: every occupant's speed <= b */
  double lo2;        /* b2 of the class below (a speed^2 below it fits there); -1 for the lowest */
  int64_t start, cap, n;
  int32_t species;
  int32_t top;       /* 1: the species' last class (open above: raised like a species bound) */
};

/* slots of a species of Nk particles with C classes (C = 1: exactly Nk) */
static inline int64_t dsmc_class_slots(int64_t Nk, int C) {
  return C == 1 ? Nk : Nk + (int64_t)((double)Nk * GRAN_DSMC_CLASS_SLACK) + (int64_t)C * kClassExtra;
}
static inline int dsmc_class_count(int64_t Nk) { return Nk >= kClassMin ? kClassNum : 1; }

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
/* A uniform direction on the sphere (Marsaglia 1972) from pairs of uniforms in [0, 1), pair(a, b):
 * the hot loop's buffered words and DsmcWords (agg_impl.h) draw the pairs their own way. */
template <class Pair>
static inline __attribute__((always_inline)) void dsmc_unit3(Pair pair, double e[3]) {
  double a, b, q;
  do {
    pair(a, b);
    a = 2.0 * a - 1.0;
    b = 2.0 * b - 1.0;
    q = a * a + b * b;
  } while (q >= 1.0);
  const double f = 2.0 * std::sqrt(1.0 - q);
  e[0] = a * f;
  e[1] = b * f;
  e[2] = 1.0 - 2.0 * q;
}
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
/* Cluster sizes of an aggregating engine (agg_impl.h); NULL without aggregation. */
struct DsmcAgg;

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
  /* Tracers (Bodrova & Osinsky Sec. II F): species with n_k = 0 in the mixture but N_k > 0 particles.
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
  /* ---- speed classes: on only with opt.speed_classes and a low-rank selector ----
   * The particles then live in the slot arrays cv (velocities) and cr (displacements: R(t) = r +
   * v (t - t_start)); with trajectories also cid (identity of the particle in a slot: its index at
   * creation) and cslot (slot of each identity). Identities cost a cache miss per class move (b501),
   * so they are kept only where trajectories need them; p is only the view handed out by
   * gran_dsmc_particles, filled at that call (by identity with trajectories, else grouped by
   * species in slot order). */
  int classes = 0;
  int64_t L = 0, S = 0;          /* leaves, slots */
  std::vector<int64_t> sleaf;    /* M+1: leaves of species k are [sleaf[k], sleaf[k+1]) */
  std::vector<int64_t> sslot;    /* M+1: slots of species k are [sslot[k], sslot[k+1]) */
  std::vector<gran::DsmcLeaf> leaf; /* L */
  std::vector<double> cv, cr;    /* 3 S */
  std::vector<int32_t> cid;      /* S, with trajectories only (ids of empty slots: stale) */
  std::vector<int32_t> cslot;    /* N, with trajectories only */
  std::vector<uint8_t> ckey;     /* scratch of the sort: the new class of each particle of a species */
  std::vector<double> cwref;     /* M: rms speed at the first sort (GRAN_DSMC_CLASS_ANCHOR: thresholds on its grid) */
  /* The draw of (r, leaf) in O(1): a Walker alias table over the 3 L pairs (r, a) with weights
   * u^(r)_a V_r built from the class bounds ub at the last sort (total ua_tot), plus a segment
   * tree ud over the same pairs holding what raises of top bounds added since (b - ub) cap ...:
   * the law is the sum of both, exactly the trees' u^(r) (which still give the rate). */
  std::vector<double> ua_p;      /* 3 L */
  std::vector<int32_t> ua_k;     /* 3 L */
  std::vector<double> ub;        /* L */
  double ua_tot = 0, ua_scale = 0; /* sum of the alias weights; 3 L / ua_tot */
  gran_segtree ud{};             /* 3 L */
  int64_t class_moves = 0, class_rebuilds = 0; /* particles moved between classes; overflow rebuilds */
  /* trajectories */
  int64_t ntraj = 0;
  std::vector<int64_t> traj_index;  /* ntraj particle indices */
  std::vector<int32_t> traj_species;
  std::vector<double> traj_xyz;     /* ntraj * traj_samples * 3 (NaN until recorded) */
  int64_t traj_next = 0;            /* next sample to record */
  /* time-step/cell selector (GRAN_SELECTOR_CELL): positions, cells, aggregation; else NULL */
  gran::DsmcCell *cell = nullptr;
  /* aggregation / fragmentation (agg_impl.h), any selector: the cell selector's DsmcCell, or the
   * event selectors' DsmcAggEv (owned: agg_event.cpp); NULL when off */
  gran::DsmcAgg *agg = nullptr;
};

namespace gran {

/* Restitution of a colliding pair of species (i, k) with normal relative velocity squared gn2, by
 * the engine's restitution mode (every selector's collision uses it). */
template <int kRest>
static inline double dsmc_pair_eps(const gran_dsmc *s, const DsmcPair *pair, size_t pik, int64_t i, int64_t k,
                                   double gn2) {
  if (kRest == kRestConst) return s->eps0;
  if (kRest == kRestTable) return pair[pik].a;
  double sb; /* viscoelastic: x = sqrt(beta) |v_n|^(1/10) */
  if (pair)
    sb = pair[pik].a;
  else if (s->visco_sqrt_beta0 >= 0)
    sb = s->visco_sqrt_beta0;
  else
    sb = std::sqrt(mix_beta(&s->mix, i, k));
  return visco_eps(sb * std::pow(gn2, 0.05));
}

/* ---- engine.cpp ---- */
/* Allocate everything for mix/counts/options, no velocities drawn (used by create and checkpoint read). */
int dsmc_alloc(const gran_mixture *mix, const int64_t *counts, const gran_dsmc_options *opt, gran_dsmc *s);
/* Rebuild the selector state (trees / C_max) from the bounds, recompute the rate, flush the pipeline. */
void dsmc_selector_rebuild(gran_dsmc *s);
/* Recompute the exact maximum speed per species, then dsmc_selector_rebuild. */
void dsmc_refresh_bounds(gran_dsmc *s);
/* After a tightening: close the acceptance window, count it, schedule the next one. */
void dsmc_refresh_window(gran_dsmc *s);
/* Raise the bound of species i to speed^2 s2 (called from the hot loop; rare). */
void dsmc_raise_bound(gran_dsmc *s, int32_t i, double s2);
/* Rate and 1/rate from the current selector state. */
void dsmc_update_rate(gran_dsmc *s);
/* Speed classes: raise the bound of top leaf a to speed^2 s2; re-sort species i into its classes
 * (an overflow: every higher class of a particle full). Both change the selection law. */
void dsmc_class_raise(gran_dsmc *s, int64_t a, double s2);
void dsmc_class_rebuild(gran_dsmc *s, int64_t i);
/* Speed classes (classes.cpp): leaves and slots for the counts (dsmc_alloc); sort species k into
 * its classes with top bound bound[k]; the leaf weights, alias tables and rate from the leaves;
 * the identity-ordered view of gran_dsmc_particles. */
int dsmc_class_setup(gran_dsmc *s);
/* GRAN_SPEED_CLASSES_AUTO: 1 where speed classes pay (selector, counts and options of s known), else 0 */
int dsmc_classes_auto(const gran_dsmc *s);
void dsmc_class_layout(gran_dsmc *s, int64_t k);
void dsmc_class_trees(gran_dsmc *s);
int dsmc_class_view(gran_dsmc *s);
void dsmc_class_alias(gran_dsmc *s);
void dsmc_class_read_done(gran_dsmc *s);
/* Walker's alias table of the weights w (engine.cpp) */
void dsmc_build_alias(const std::vector<double> &w, std::vector<double> *p, std::vector<int32_t> *a);
/* The particle velocities the loop works on (the slots with speed classes). */
static inline double *dsmc_hv(gran_dsmc *s) { return s->classes ? s->cv.data() : s->p.v; }
static inline const double *dsmc_hv(const gran_dsmc *s) { return s->classes ? s->cv.data() : s->p.v; }
static inline const double *dsmc_hr(const gran_dsmc *s) { return s->classes ? (s->cr.empty() ? nullptr : s->cr.data()) : s->p.r; }
/* f(a, b) for the ranges [a, b) of hot indices holding species k's particles (one range without
 * speed classes: the order of every sum is then the stored order) */
template <class F>
static inline void dsmc_species_ranges(const gran_dsmc *s, int64_t k, F f) {
  if (!s->classes) {
    f(s->offset[(size_t)k], s->offset[(size_t)k + 1]);
    return;
  }
  for (int64_t a = s->sleaf[(size_t)k]; a < s->sleaf[(size_t)k + 1]; a++) {
    const DsmcLeaf &x = s->leaf[(size_t)a];
    if (x.n > 0) f(x.start, x.start + x.n);
  }
}
int dsmc_check(const gran_dsmc *s, const char *name);

/* ---- hot loops (lowrank.cpp, bird.cpp) ----
 * Run trials until the pending trial lies beyond t_stop or the collision count reaches coll_stop. */
typedef void (*DsmcLoopFn)(gran_dsmc *s, double t_stop, int64_t coll_stop);
DsmcLoopFn dsmc_lowrank_loop(int paper, int disp, int counts, int rest, int tracers);
DsmcLoopFn dsmc_bird_loop(int paper, int disp, int counts, int rest, int tracers);
DsmcLoopFn dsmc_class_loop(int paper, int disp, int counts, int rest, int tracers); /* low-rank with speed classes */

/* ---- derived.cpp: derived values of the inputs, checked at creation (GRAN_ERR_DOMAIN) ---- */
/* the masses that can meet, m_lo (species k_lo) <= m_hi (species k_hi), with kinetic energy E */
int dsmc_check_masses(double m_lo, int64_t k_lo, double m_hi, int64_t k_hi, double E);
/* the squares of the selector's acceptance test (bird: Bird's C_max; else low-rank); sigma_min (species k_min):
 * the smallest diameter present (Bird's right side must not underflow) */
int dsmc_check_acceptance(int bird, double sigma, int64_t k, double b2, double sigma_min, int64_t k_min);
/* both for a new engine after its velocities and bounds (agg: with aggregation; speeds: the
 * energy and the bounds are finite, check what they imply) */
int dsmc_check_derived(const gran_dsmc *s, bool agg, bool speeds);

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
