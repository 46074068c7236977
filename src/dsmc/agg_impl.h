/* agg_impl.h - aggregation and fragmentation shared by every DSMC selector: the
 * cluster-size bookkeeping (DsmcAgg: the cell selector's DsmcCell and the event selectors'
 * DsmcAggEv both extend it), the random words of the engine's buffered streams, and the collision
 * rules (the DSMC outline step 10 as corrected in docs/physics.md):
 *   - merge (mu g^2/2 < e_agg): one (k+j)-mer with the centre-of-mass velocity;
 *   - shatter (mu g_n^2/2 > e_frag): pieces by the fragment law (monomers, or two pieces of a
 *     uniform size), random directions, the last piece closing the momentum (Eq. 14), one common
 *     factor giving the centre-of-mass kinetic energy eps_f^2 mu g^2/2 exactly (Eq. 10);
 *   - otherwise a restitutive bounce.
 * Species are cluster sizes: species k-1 is the k-mer of mass k m_1 and diameter sigma_1 k^(1/3). */
#ifndef GRANARY_DSMC_AGG_IMPL_H
#define GRANARY_DSMC_AGG_IMPL_H

#include "dsmc_impl.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace gran {

/* The draws on a source of 64-bit words (D::next): uniform, below n, unit vector, normal pairs. */
#define GRAN_DRAW inline __attribute__((always_inline)) /* the hot loops' draws: inlined, as before the template */
template <class D>
struct DsmcDraws {
  GRAN_DRAW double uniform() { return u64_uniform(self().next()); }
  GRAN_DRAW int64_t below(int64_t n) { return u64_below(self().next(), n); }
  GRAN_DRAW void unit3(double e[3]) {
    dsmc_unit3(
        [&](double &a, double &b) {
          a = uniform();
          b = uniform();
        },
        e);
  }
  GRAN_DRAW void normal2(double z[2]) { /* Marsaglia's polar method: two independent N(0, 1) */
    double a, b, q;
    do {
      a = 2.0 * uniform() - 1.0;
      b = 2.0 * uniform() - 1.0;
      q = a * a + b * b;
    } while (q >= 1.0 || q == 0.0);
    const double f = std::sqrt(-2.0 * std::log(q) / q);
    z[0] = a * f;
    z[1] = b * f;
  }

 private:
  GRAN_DRAW D &self() { return *static_cast<D *>(this); }
};
#undef GRAN_DRAW

/* next word of the engine's buffered streams */
struct DsmcWords : DsmcDraws<DsmcWords> {
  DsmcRng *r;
  explicit DsmcWords(DsmcRng *rng) : r(rng) {}
  inline uint64_t next() {
    if (r->pos >= kRngBuf) dsmc_rng_refill(r);
    return r->buf[r->pos++];
  }
};

/* One xoshiro256** stream held by value (the cell DSMC's per-cell streams, GRAN_CELL_STREAMS_CELLS):
 * seeded from a keyed generator (core/keyed.h). */
struct DsmcCellWords : DsmcDraws<DsmcCellWords> {
  gran_rng g;
  explicit DsmcCellWords(const gran_rng &seeded) : g(seeded) {}
  inline uint64_t next() { return gran_xo_next(&g); }
};

/* Cluster-size bookkeeping of an aggregating engine (any selector). */
struct DsmcAgg {
  int agg = 0;                 /* 1: species are cluster sizes (e_agg > 0 or e_frag finite) */
  double e_agg = 0, e_frag = INFINITY, eps_f = 1;
  int32_t frag_law = GRAN_FRAG_MONOMERS; /* gran_frag_law */
  double m1 = 1, sigma1 = 1;   /* monomer mass and diameter */
  int64_t kmax = 0;            /* largest cluster size present */
  std::vector<int64_t> nsize;  /* clusters of size k at [k-1], grown on demand (doubling) */
  std::vector<double> sigk;    /* diameter of a k-mer at [k-1], grown with nsize */
  int64_t merges = 0, breakups = 0, bounces = 0;
  double e_merge = 0, e_merge_c = 0; /* energy lost in merges (Neumaier sum, compensation) */
  double e_break = 0, e_break_c = 0; /* lost in breakups */
  int64_t monomers = 0;              /* total mass in monomers (conserved) */
};

/* a k-mer: mass k m1, diameter sigma1 k^(1/3) */
static inline double agg_sigma(const DsmcAgg *c, int64_t k) { return c->sigma1 * std::cbrt((double)k); }

/* agg.cpp */
/* room for a size k (1-based) in nsize / sigk */
void dsmc_agg_grow(DsmcAgg *c, int64_t k);
/* checks (mixture of k-mers, constant restitution, observables) and the size tables from s->count */
int dsmc_agg_setup(gran_dsmc *s, DsmcAgg *c);
/* per-particle observables of an aggregating gas (species = size - 1): the mixture's M sizes */
void dsmc_agg_mean_flow(const gran_dsmc *s, double u[3]);
/* T per size (T may be NULL; GRAN_ERR_NUMERIC when an occupied size's T is not finite) and a2 per size (a2 may
 * be NULL; GRAN_ERR_NUMERIC when an occupied size has no thermal motion or a non-finite velocity); NaN for an
 * empty size */
int dsmc_agg_temperatures(const gran_dsmc *s, double *T, double *a2);
void dsmc_agg_energy_momentum(const gran_dsmc *s, double *e_kin, double p[3]);

/* ---- the collision rules ---- */

/* merge: v_j becomes the centre-of-mass velocity of the pair (masses mi, mk in any unit) */
static inline void agg_merge_velocity(double *vj, const double *vl, double mi, double mk) {
  const double inv = 1.0 / (mi + mk);
  for (int d = 0; d < 3; d++) vj[d] = (mi * vj[d] + mk * vl[d]) * inv;
}

/* Pieces of a shattering K-mer by the fragment law: returns their number P; size(q) of piece q is
 * 1 for monomers, else (binary) a for q = 0 and K - a for q = 1 with a uniform in 1..K-1. */
struct AggPieces {
  int64_t P = 0, a = 1, K = 0;
  inline int64_t size(int64_t q) const { return P == K ? 1 : (q == 0 ? a : K - a); }
};
template <class W>
static inline AggPieces agg_pieces(W &w, int32_t law, int64_t K) {
  AggPieces p;
  p.K = K;
  if (law == GRAN_FRAG_BINARY && K > 2) {
    p.P = 2;
    p.a = 1 + w.below(K - 1);
  } else {
    p.P = K; /* monomers (a dimer's binary breakup is two monomers too) */
  }
  return p;
}

/* Velocities of the pieces (vel(q): where piece q's velocity goes): random directions at speed u,
 * the last piece closing the momentum (Eq. 14), then Vc + lam * that with one common lam so that
 * the kinetic energy in the centre-of-mass frame is E0 exactly (Eq. 10). Returns the largest
 * speed^2. Masses in monomers (m1 the monomer mass). */
template <class W, class Vel>
static inline double agg_fragment_velocities(W &w, const AggPieces &pc, Vel vel, const double Vc[3], double u,
                                             double E0, double m1) {
  const int64_t P = pc.P;
  double sum[3] = {0, 0, 0}, S = 0;
  for (int64_t q = 0; q < P - 1; q++) {
    double e[3];
    w.unit3(e);
    double *vq = vel(q);
    const double mq = (double)pc.size(q);
    for (int d = 0; d < 3; d++) {
      vq[d] = u * e[d];
      sum[d] += mq * vq[d];
    }
  }
  {
    double *vq = vel(P - 1);
    const double ml = (double)pc.size(P - 1);
    for (int d = 0; d < 3; d++) vq[d] = -sum[d] / ml;
  }
  for (int64_t q = 0; q < P; q++) {
    const double *vq = vel(q);
    S += (double)pc.size(q) * (vq[0] * vq[0] + vq[1] * vq[1] + vq[2] * vq[2]);
  }
  const double lam = S > 0 ? std::sqrt(E0 / (0.5 * m1 * S)) : 0.0;
  double m2 = 0;
  for (int64_t q = 0; q < P; q++) {
    double *vq = vel(q);
    for (int d = 0; d < 3; d++) vq[d] = Vc[d] + lam * vq[d];
    m2 = std::fmax(m2, vq[0] * vq[0] + vq[1] * vq[1] + vq[2] * vq[2]);
  }
  return m2;
}

/* counts and ledger of a merge of sizes ki, kk (1-based) into ki + kk */
static inline void agg_book_merge(DsmcAgg *c, int64_t ki, int64_t kk, double Eimp) {
  const int64_t K = ki + kk;
  dsmc_agg_grow(c, K);
  c->nsize[(size_t)ki - 1]--;
  c->nsize[(size_t)kk - 1]--;
  c->nsize[(size_t)K - 1]++;
  if (K > c->kmax) c->kmax = K;
  neumaier_add(c->e_merge, c->e_merge_c, Eimp);
  c->merges++;
}

/* counts and ledger of a breakup of sizes ki, kk into the pieces pc (E0 kept of Eimp) */
static inline void agg_book_shatter(DsmcAgg *c, int64_t ki, int64_t kk, const AggPieces &pc, double Eimp, double E0) {
  dsmc_agg_grow(c, pc.K); /* a binary piece may be larger than any size present */
  c->nsize[(size_t)ki - 1]--;
  c->nsize[(size_t)kk - 1]--;
  for (int64_t q = 0; q < pc.P; q++) {
    const int64_t z = pc.size(q);
    c->nsize[(size_t)z - 1]++;
    if (z > c->kmax) c->kmax = z;
  }
  neumaier_add(c->e_break, c->e_break_c, Eimp - E0);
  c->breakups++;
}

/* the speed u of Eq. 11 before the common factor (only its direction statistics matter) */
static inline double agg_fragment_speed(int64_t ki, int64_t kk, double eps_f, double g) {
  return std::sqrt((double)ki * (double)kk) * eps_f * g / (double)(ki + kk);
}

/* ---- event selectors (agg_event.cpp) ----
 * Particles unordered in the engine's arrays (species = size - 1; a merged partner is swap-removed,
 * fragments are appended). Bird: one global bound C = sigma_p^2 2 vmax (sigma_p the largest pair
 * diameter present, of the two largest clusters). Low-rank: the sizes present own slots (reused through a free list; the slot
 * arrays and trees grow by doubling), each with its member list and a speed bound b_a; the trees
 * hold u^(r)_a = b_a N_a (sigma_a^2, 2 sigma_a, 1) and v^(r)_a = N_a (1, sigma_a, sigma_a^2), the
 * rank-3 decomposition of (sigma_a + sigma_b)^2 b_a N_a N_b that engine.cpp uses for species. */
struct DsmcAggEv : DsmcAgg {
  int lowrank = 0;
  double vmax2 = 0;                  /* bound of |v|^2 over all particles (raised; exact at a tightening) */
  double smax = 0;                   /* Bird: the largest diameter sigma_M that C_max (s->cmax) accounts for
                                      * (>= that of the largest size present; exact at a tightening) */
  std::vector<double> bsz;           /* Bird: speed bound of the particles of size k at [k-1] (raised; exact at a
                                      * tightening); C_max = 2 max_k ((sigma_k + sigma_M)/2)^2 b_k (Eq. 49) */
  /* low-rank only */
  int64_t ncap = 0;                  /* slots (leaves of the trees; a power of two) */
  std::vector<int64_t> slot_size;    /* ncap: size held by a slot (0: free) */
  std::vector<double> sbound;        /* ncap: speed bound of the slot's particles */
  std::vector<int64_t> free_slots;   /* free slots (a stack) */
  std::vector<int32_t> slot_of;      /* per size [k-1]: its slot or -1 (grown with nsize) */
  std::vector<std::vector<int32_t>> members; /* ncap: particle indices of the slot's size (N < 2^31) */
  std::vector<int64_t> mpos;         /* per particle: its index in its member list */
  gran_segtree u[3]{}, v[3]{};
  /* pipeline of pre-drawn candidate pairs (as the hot loop's): drawn kDsmcPipe trials ahead, the
   * member entries prefetched then, resolved to particles (and their velocities prefetched) half
   * way; discarded whenever the particles or the law change (a merge, a breakup, a low-rank raise,
   * a tightening). Part of the state. */
  struct Cand {
    int64_t j, l;   /* low-rank: positions in the member lists until resolved; then particles */
    int64_t a, b;   /* low-rank: slots */
    int64_t resolved;
  };
  Cand cand[kDsmcPipe]{};
  int64_t cand_head = 0, cand_count = 0;
};
int dsmc_aggev_setup(gran_dsmc *s, const gran_dsmc_agg_options *o); /* after dsmc_alloc and the velocities */
void dsmc_aggev_free(gran_dsmc *s);
/* checkpoint reading: member lists and trees from the stored slots, checked */
int dsmc_aggev_read_done(gran_dsmc *s);
int dsmc_aggev_advance(gran_dsmc *s, double t_end, int64_t coll_stop);
/* Bird: the exact C_max of Eq. 49 from the per-size bounds (bsz, smax, the sizes present) */
double dsmc_aggev_bird_cmax(const DsmcAggEv *A);
/* the process options; `who` names them in messages ("aggregation" options, "cell" options) */
int dsmc_agg_check_options(const gran_dsmc_agg_options *o, const char *who = "aggregation");

}  // namespace gran

#endif
