/* agg_event.cpp - aggregation and fragmentation in the event selectors (low-rank and Bird; issue
 * 10): a loop of its own, used only by engines made with gran_dsmc_create_agg and the processes on
 * (the hot loop of dsmc_loop.h is not touched: off costs nothing). One trial: propose an ordered
 * pair (j, l) by the selector, accept with the exact-rate ratio, then merge, shatter or bounce by
 * the rules of agg_impl.h (those of the cell selector). Trial times are the engine's (product of
 * uniforms against a threshold, restarted whenever the rate changes: after every merge and breakup,
 * and when a bound rises). The bounds are tightened to the exact maxima every refresh_interval
 * collisions. Sizes: see DsmcAggEv in agg_impl.h. */
#include "agg_impl.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <new>

namespace gran {

namespace {

const double kPi = 3.14159265358979323846;

inline DsmcAggEv *ev(gran_dsmc *s) { return static_cast<DsmcAggEv *>(s->agg); }

/* ---- low-rank slots ---- */

/* the six leaves of slot a from its count, bound and diameter */
void slot_touch(DsmcAggEv *A, int64_t a) {
  const double n = (double)A->members[(size_t)a].size(), b = A->sbound[(size_t)a];
  const double sg = A->slot_size[(size_t)a] > 0 ? A->sigk[(size_t)A->slot_size[(size_t)a] - 1] : 0.0;
  const double bn = b * n;
  segtree_set(&A->u[0], a, bn * sg * sg);
  segtree_set(&A->u[1], a, 2.0 * bn * sg);
  segtree_set(&A->u[2], a, bn);
  segtree_set(&A->v[0], a, n);
  segtree_set(&A->v[1], a, n * sg);
  segtree_set(&A->v[2], a, n * sg * sg);
}

/* trees of capacity ncap from the slots (creation, growth, checkpoint reading, tightening) */
int slot_trees(DsmcAggEv *A) {
  const int64_t C = A->ncap;
  std::vector<double> w[6];
  for (auto &x : w) x.assign((size_t)C, 0.0);
  for (int64_t a = 0; a < C; a++) {
    if (A->slot_size[(size_t)a] == 0) continue;
    const double n = (double)A->members[(size_t)a].size(), b = A->sbound[(size_t)a];
    const double sg = A->sigk[(size_t)A->slot_size[(size_t)a] - 1], bn = b * n;
    w[0][(size_t)a] = bn * sg * sg;
    w[1][(size_t)a] = 2.0 * bn * sg;
    w[2][(size_t)a] = bn;
    w[3][(size_t)a] = n;
    w[4][(size_t)a] = n * sg;
    w[5][(size_t)a] = n * sg * sg;
  }
  for (int r = 0; r < 3; r++) {
    gran_segtree_free(&A->u[r]);
    gran_segtree_free(&A->v[r]);
    GRAN_CALL(gran_segtree_init(&A->u[r], C, w[r].data()));
    GRAN_CALL(gran_segtree_init(&A->v[r], C, w[3 + r].data()));
  }
  return GRAN_SUCCESS;
}

/* the slot of size k, made when the size has none (the trees grow by doubling) */
int64_t slot_get(DsmcAggEv *A, int64_t k) {
  dsmc_agg_grow(A, k);
  if ((int64_t)A->slot_of.size() < (int64_t)A->nsize.size()) A->slot_of.resize(A->nsize.size(), -1);
  const int32_t have = A->slot_of[(size_t)k - 1];
  if (have >= 0) return have;
  if (A->free_slots.empty()) { /* double the slots */
    const int64_t old = A->ncap, C = std::max<int64_t>(2 * old, 16);
    A->slot_size.resize((size_t)C, 0);
    A->sbound.resize((size_t)C, 0.0);
    A->members.resize((size_t)C);
    for (int64_t a = C - 1; a >= old; a--) A->free_slots.push_back(a);
    A->ncap = C;
    if (slot_trees(A) != GRAN_SUCCESS) throw std::bad_alloc();
  }
  const int64_t a = A->free_slots.back();
  A->free_slots.pop_back();
  A->slot_size[(size_t)a] = k;
  A->sbound[(size_t)a] = 0.0;
  A->members[(size_t)a].clear();
  A->slot_of[(size_t)k - 1] = (int32_t)a;
  return a;
}

void slot_add(DsmcAggEv *A, int64_t a, int64_t j) {
  std::vector<int32_t> &m = A->members[(size_t)a];
  A->mpos[(size_t)j] = (int64_t)m.size();
  m.push_back((int32_t)j);
}

/* particle j leaves slot a; an empty slot is freed */
void slot_remove(DsmcAggEv *A, int64_t a, int64_t j) {
  std::vector<int32_t> &m = A->members[(size_t)a];
  const int64_t q = A->mpos[(size_t)j], y = m.back();
  m[(size_t)q] = (int32_t)y;
  A->mpos[(size_t)y] = q;
  m.pop_back();
  if (m.empty()) {
    A->slot_of[(size_t)A->slot_size[(size_t)a] - 1] = -1;
    A->slot_size[(size_t)a] = 0;
    A->sbound[(size_t)a] = 0.0;
    A->free_slots.push_back(a);
  }
}

/* raise the bound of slot a to speed^2 q2 (the leaves are set by the caller) */
inline bool slot_raise(DsmcAggEv *A, int64_t a, double q2) {
  if (q2 <= A->sbound[(size_t)a] * A->sbound[(size_t)a]) return false;
  A->sbound[(size_t)a] = std::sqrt(q2);
  return true;
}

/* ---- Bird: C_max of Eq. 49 over the sizes present, from a speed bound per size ----
 * A pair (i, k) has ((sigma_i + sigma_k)/2)^2 |g| <= ((sigma_i + sigma_M)/2)^2 b_i + ((sigma_M + sigma_k)/2)^2 b_k
 * <= C_max (Eq. 48), so one global bound stays exact while heavy clusters, which are slow, no longer
 * set it with the monomers' speeds: with one 4-mer among 1e6 monomers the bound sigma_pair,max^2
 * 2 v_max (before) was about 1.5 times this one. */

/* a particle of size k reached speed^2 q2: the size's bound rises and C_max with its term;
 * returns whether C_max rose (the trial rate changes) */
bool bird_raise(gran_dsmc *s, DsmcAggEv *A, int64_t k, double q2) {
  if ((int64_t)A->bsz.size() < k) A->bsz.resize(std::max(A->nsize.size(), (size_t)k), 0.0);
  double &b = A->bsz[(size_t)k - 1];
  if (q2 <= b * b) return false;
  b = std::sqrt(q2);
  const double w = 0.5 * (A->sigk[(size_t)k - 1] + A->smax);
  const double c = 2.0 * w * w * b;
  if (c <= s->cmax) return false;
  s->cmax = c;
  return true;
}

/* a size K appeared: if it is larger than sigma_M, sigma_M becomes sigma_K and every term of
 * C_max grows by at most (sigma_K / sigma_M)^2, since (sigma_k + sigma_K) / (sigma_k + sigma_M) <=
 * sigma_K / sigma_M (O(1), where the exact C_max would scan every size present) */
bool bird_grow(gran_dsmc *s, DsmcAggEv *A, int64_t K) {
  const double sK = A->sigk[(size_t)K - 1];
  if (sK <= A->smax) return false;
  if (A->smax > 0) {
    const double f = sK / A->smax;
    s->cmax *= f * f;
    A->smax = sK;
  } else {
    A->smax = sK;
    s->cmax = dsmc_aggev_bird_cmax(A);
  }
  return true;
}

}  // namespace

/* Over every size with a bound, present or not: a size that emptied since the last tightening keeps
 * its bound and its term (C_max only grows between tightenings, which reset the bounds of absent
 * sizes to 0), so that a cluster of that size made later, at a speed under the old bound, is covered
 * without a raise. The same holds for the bounds of a checkpoint, which this checks on reading. */
double dsmc_aggev_bird_cmax(const DsmcAggEv *A) {
  double c = 0;
  for (size_t k = 0; k < A->bsz.size(); k++)
    if (A->bsz[k] > 0) {
      const double w = 0.5 * (A->sigk[k] + A->smax);
      c = std::max(c, 2.0 * w * w * A->bsz[k]);
    }
  return c;
}

/* Rate of the trials: low-rank pi/(4V) sum_r U_r V_r, Bird pi N^2 C / (2V) (both |g| acceptance). */
static void aggev_rate(gran_dsmc *s) {
  DsmcAggEv *A = ev(s);
  double rate;
  if (A->lowrank) {
    double w = 0;
    for (int r = 0; r < 3; r++) w += A->u[r].node[1] * A->v[r].node[1];
    rate = kPi / (4.0 * s->volume) * w;
  } else {
    const double n = (double)s->p.n; /* s->N follows at the end of a loop (aggev_sync) */
    rate = 0.5 * kPi * n * n * s->cmax / s->volume; /* C_max kept by bird_raise, bird_grow, the tightening */
  }
  rate *= s->g2max;
  if (s->p.n < 2) rate = 0;
  s->rate = rate;
  s->inv_rate = rate > 0 ? 1.0 / rate : INFINITY;
}

/* the engine's per-species view: N, counts of the mixture's sizes, one bound for all */
static void aggev_sync(gran_dsmc *s) {
  DsmcAggEv *A = ev(s);
  s->N = s->p.n;
  s->n_gas = s->p.n;
  while (A->kmax > 0 && A->nsize[(size_t)A->kmax - 1] == 0) A->kmax--;
  for (int64_t k = 0; k < s->M; k++) {
    s->count[(size_t)k] = k < (int64_t)A->nsize.size() ? A->nsize[(size_t)k] : 0;
    s->bound2[(size_t)k] = A->vmax2;
    s->bound[(size_t)k] = std::sqrt(A->vmax2);
  }
}

/* the bounds to their exact maxima (and sigma_max to the largest size present), trees rebuilt */
static int aggev_tighten(gran_dsmc *s) {
  DsmcAggEv *A = ev(s);
  const double *v = s->p.v;
  const int32_t *sp = s->p.species;
  double m2 = 0;
  if (A->lowrank) {
    std::fill(A->sbound.begin(), A->sbound.end(), 0.0);
  } else {
    A->bsz.assign(A->nsize.size(), 0.0);
  }
  for (int64_t j = 0; j < s->p.n; j++) {
    const double q = v[3 * j] * v[3 * j] + v[3 * j + 1] * v[3 * j + 1] + v[3 * j + 2] * v[3 * j + 2];
    m2 = q > m2 ? q : m2;
    double &b = A->lowrank ? A->sbound[(size_t)A->slot_of[(size_t)sp[j]]] : A->bsz[(size_t)sp[j]];
    b = q > b ? q : b; /* squared here, rooted below */
  }
  if (A->lowrank) {
    for (double &b : A->sbound) b = std::sqrt(b);
    GRAN_CALL(slot_trees(A));
  } else {
    for (double &b : A->bsz) b = std::sqrt(b);
  }
  A->vmax2 = m2;
  while (A->kmax > 0 && A->nsize[(size_t)A->kmax - 1] == 0) A->kmax--;
  if (!A->lowrank) { /* Bird: sigma_M of the largest size present, C_max exact (Eq. 49) */
    A->smax = A->kmax > 0 ? A->sigk[(size_t)A->kmax - 1] : 0.0;
    s->cmax = dsmc_aggev_bird_cmax(A);
  }
  A->cand_count = 0; /* the law changed */
  aggev_rate(s);
  dsmc_refresh_window(s);
  return GRAN_SUCCESS;
}

int dsmc_agg_check_options(const gran_dsmc_agg_options *o, const char *who) {
  GRAN_CHECK_PTR(o);
  GRAN_CHECK(std::isfinite(o->e_agg) && o->e_agg >= 0, GRAN_ERR_ARG, "%s option 'e_agg' = %g must be finite and >= 0",
             who, o->e_agg);
  GRAN_CHECK(!std::isnan(o->e_frag) && o->e_frag >= 0, GRAN_ERR_ARG,
             "%s option 'e_frag' = %g must be >= 0 (INFINITY: no fragmentation)", who, o->e_frag);
  GRAN_CHECK(std::isfinite(o->eps_f) && o->eps_f >= 0 && o->eps_f <= 1, GRAN_ERR_ARG,
             "%s option 'eps_f' = %g must be in [0, 1]", who, o->eps_f);
  GRAN_CHECK(o->frag_law == GRAN_FRAG_MONOMERS || o->frag_law == GRAN_FRAG_BINARY, GRAN_ERR_ARG,
             "%s option 'frag_law' = %d is not a gran_frag_law", who, (int)o->frag_law);
  return GRAN_SUCCESS;
}

/* the slots, member lists and trees from the particles' species (creation, checkpoint reading
 * fills them from the file instead) */
static int aggev_slots_from_particles(gran_dsmc *s) {
  DsmcAggEv *A = ev(s);
  A->slot_of.assign(A->nsize.size(), -1);
  A->mpos.assign((size_t)s->p.capacity, 0);
  for (int64_t j = 0; j < s->p.n; j++) slot_add(A, slot_get(A, (int64_t)s->p.species[j] + 1), j);
  return GRAN_SUCCESS;
}

int dsmc_aggev_setup(gran_dsmc *s, const gran_dsmc_agg_options *o) {
  GRAN_CALL(dsmc_agg_check_options(o));
  GRAN_CHECK(!s->paper && !s->classes, GRAN_ERR_UNSUPPORTED,
             "aggregation and fragmentation in the event selectors need GRAN_SELECTOR_LOWRANK or GRAN_SELECTOR_BIRD "
             "(the paper variants and speed classes are not supported)");
  GRAN_CHECK(!s->has_tracers, GRAN_ERR_ARG, "aggregation: tracers (n_k = 0 with particles) are not supported");
  GRAN_CHECK(s->N < (s->selector == GRAN_SELECTOR_LOWRANK ? (int64_t)INT32_MAX : (INT64_C(1) << 40)), GRAN_ERR_ARG,
             "aggregation: too many particles (" GRAN_I64_FMT "; the low-rank selector's member lists hold fewer than 2^31)",
             s->N);
  DsmcAggEv *A = new DsmcAggEv();
  s->agg = A; /* owned from here: dsmc_aggev_free */
  A->e_agg = o->e_agg;
  A->e_frag = o->e_frag;
  A->eps_f = o->eps_f;
  A->frag_law = o->frag_law;
  A->lowrank = s->selector == GRAN_SELECTOR_LOWRANK;
  GRAN_CALL(dsmc_agg_setup(s, A));
  if (A->lowrank) GRAN_CALL(aggev_slots_from_particles(s));
  GRAN_CALL(aggev_tighten(s));
  s->bound_tightenings = 0;
  s->cand_count = 0;
  aggev_sync(s);
  return GRAN_SUCCESS;
}

void dsmc_aggev_free(gran_dsmc *s) {
  if (!s->agg || s->cell) return; /* the cell selector's sizes live in its DsmcCell */
  DsmcAggEv *A = ev(s);
  for (int r = 0; r < 3; r++) {
    gran_segtree_free(&A->u[r]);
    gran_segtree_free(&A->v[r]);
  }
  delete A;
  s->agg = nullptr;
}

/* The pre-drawn candidates index what they should (checkpoint reading). Every stored index is
 * range-checked before anything is indexed with it: Bird's candidates are resolved particles
 * (slots 0, no member lists); low-rank ones name occupied slots, unresolved positions within their
 * member lists, resolved particles of the slot's size (the loop takes the size from the slot). */
static int cand_check(const gran_dsmc *s) {
  const DsmcAggEv *A = static_cast<const DsmcAggEv *>(s->agg);
  GRAN_CHECK((A->cand_count == 0 || A->cand_count == kDsmcPipe) && A->cand_head >= 0 && A->cand_head < kDsmcPipe,
             GRAN_ERR_IO, "dataset 'agg_candidates': the candidate pipeline (head " GRAN_I64_FMT ", count " GRAN_I64_FMT
             ")", A->cand_head, A->cand_count);
  for (int q = 0; q < kDsmcPipe && A->cand_count > 0; q++) {
    const DsmcAggEv::Cand &c = A->cand[q];
    const int64_t n = s->p.n;
    bool ok = c.resolved == 0 || c.resolved == 1;
    if (ok && !A->lowrank) ok = c.resolved == 1 && c.a == 0 && c.b == 0;
    if (ok && A->lowrank)
      ok = c.a >= 0 && c.a < A->ncap && c.b >= 0 && c.b < A->ncap && A->slot_size[(size_t)c.a] > 0 &&
           A->slot_size[(size_t)c.b] > 0;
    if (ok && !c.resolved)
      ok = c.j >= 0 && c.j < (int64_t)A->members[(size_t)c.a].size() && c.l >= 0 &&
           c.l < (int64_t)A->members[(size_t)c.b].size();
    if (ok && c.resolved) ok = c.j >= 0 && c.j < n && c.l >= 0 && c.l < n;
    if (ok && c.resolved && A->lowrank)
      ok = s->p.species[c.j] + 1 == A->slot_size[(size_t)c.a] && s->p.species[c.l] + 1 == A->slot_size[(size_t)c.b];
    GRAN_CHECK(ok, GRAN_ERR_IO, "dataset 'agg_candidates': candidate pair %d (j " GRAN_I64_FMT ", l " GRAN_I64_FMT
               ", slots " GRAN_I64_FMT " " GRAN_I64_FMT ", resolved " GRAN_I64_FMT ") out of range",
               q, c.j, c.l, c.a, c.b, c.resolved);
  }
  return GRAN_SUCCESS;
}

/* checkpoint reading (checkpoint.cpp): slots and members from the stored slot sizes and member
 * positions; 0, or an error naming what does not fit */
int dsmc_aggev_read_done(gran_dsmc *s) {
  DsmcAggEv *A = ev(s);
  aggev_sync(s);
  if (!A->lowrank) {
    aggev_rate(s);
    return cand_check(s);
  }
  const int64_t C = A->ncap;
  A->slot_of.assign(A->nsize.size(), -1);
  A->members.clear();
  A->members.assign((size_t)C, {});
  for (int64_t a = 0; a < C; a++) {
    const int64_t k = A->slot_size[(size_t)a];
    if (k == 0) continue;
    GRAN_CHECK(k >= 1 && k <= (int64_t)A->nsize.size() && A->slot_of[(size_t)k - 1] < 0 && A->nsize[(size_t)k - 1] > 0,
               GRAN_ERR_IO, "aggregation slots");
    A->slot_of[(size_t)k - 1] = (int32_t)a;
    A->members[(size_t)a].assign((size_t)A->nsize[(size_t)k - 1], -1);
  }
  for (int64_t j = 0; j < s->p.n; j++) {
    const int64_t k = (int64_t)s->p.species[j] + 1, a = A->slot_of[(size_t)k - 1];
    GRAN_CHECK(a >= 0, GRAN_ERR_IO, "aggregation slots");
    const int64_t q = A->mpos[(size_t)j];
    std::vector<int32_t> &m = A->members[(size_t)a];
    GRAN_CHECK(q >= 0 && q < (int64_t)m.size() && m[(size_t)q] < 0, GRAN_ERR_IO, "aggregation member positions");
    m[(size_t)q] = (int32_t)j;
  }
  for (size_t k = 0; k < A->nsize.size(); k++)
    GRAN_CHECK(A->nsize[k] == 0 || A->slot_of[k] >= 0, GRAN_ERR_IO, "aggregation slots");
  for (int64_t a = 0; a < C; a++) {
    const int64_t k = A->slot_size[(size_t)a];
    if (k == 0) continue;
    for (int64_t j : A->members[(size_t)a]) {
      const double *v = s->p.v + 3 * j;
      GRAN_CHECK(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= A->sbound[(size_t)a] * A->sbound[(size_t)a] * (1 + 1e-12),
                 GRAN_ERR_IO, "aggregation speed bounds");
    }
  }
  A->mpos.resize((size_t)std::max<int64_t>(s->p.capacity, s->p.n));
  GRAN_CALL(slot_trees(A));
  aggev_rate(s);
  GRAN_CALL(cand_check(s));
  return GRAN_SUCCESS;
}

namespace {

/* One run of trials up to t_stop or coll_stop collisions. Returns a status (a failed growth). */
template <bool kLow>
int aggev_loop(gran_dsmc *s, double t_stop, int64_t coll_stop) {
  DsmcAggEv *const A = ev(s);
  DsmcWords w{&s->vrng};
  gran_particles *const p = &s->p;
  const double m1 = A->m1, e_agg = A->e_agg, e_frag = A->e_frag, eps0 = s->eps0;
  double inv_rate = s->inv_rate;
  /* the engine's counters and clock, in place (a trial costs two random particle loads anyway) */
  int64_t &coll = s->collisions, &trials = s->trials;
  double &ed = s->e_diss, &edc = s->e_diss_c;
  double &t_ref = s->t_ref, &tprod = s->tprod, &tlog = s->tlog;
  auto now = [&]() { return t_ref + (tlog - std::log(tprod)) * inv_rate; };
  double pthr = 0;
  auto set_thr = [&]() { pthr = std::exp(tlog - (t_stop - t_ref) * s->rate); };
  set_thr();
  int status = GRAN_SUCCESS;

  /* the slot of particle x's size (low-rank) */
  auto slot_of_p = [&](int64_t x) { return (int64_t)A->slot_of[(size_t)p->species[x]]; };
  /* swap-remove particle x from the arrays; the last particle takes its index (its member entry
   * moves with it unless it is `loose`, in no member list) */
  auto remove_particle = [&](int64_t x, int64_t loose) {
    const int64_t last = p->n - 1;
    if (kLow && last != x && last != loose) {
      const int64_t a = slot_of_p(last), q = A->mpos[(size_t)last];
      A->members[(size_t)a][(size_t)q] = (int32_t)x;
      A->mpos[(size_t)x] = q;
    }
    gran_particles_swap_remove(p, x);
  };
  auto prefetch_v = [&](int64_t x) {
    __builtin_prefetch(p->v + 3 * x);
    __builtin_prefetch(p->v + 3 * x + 2);
    if (!kLow) __builtin_prefetch(p->species + x);
  };
  auto raise_all = [&](double q2) {
    if (q2 > A->vmax2) {
      A->vmax2 = q2;
      return true;
    }
    return false;
  };

  const int kPipe = kDsmcPipe;
  bool flush = false; /* the particles changed (a merge or a breakup): the candidates are stale */
  /* collide the accepted pair (j, l); returns whether the trial rate changed */
  auto collide = [&](int64_t j, int64_t l, int32_t i, int32_t k, int64_t ai, int64_t ak) -> bool {
    const int64_t ki = (int64_t)i + 1, kk = (int64_t)k + 1, K = ki + kk;
    double *vj = p->v + 3 * j, *vl = p->v + 3 * l;
    const double g[3] = {vj[0] - vl[0], vj[1] - vl[1], vj[2] - vl[2]};
    const double g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
    const double mi = (double)ki * m1, mk = (double)kk * m1, inv = 1.0 / (mi + mk), mu = mi * mk * inv;
    const double Eimp = 0.5 * mu * g2;
    ++coll;
    if (Eimp < e_agg) { /* merge: j becomes the (k+j)-mer, l leaves */
      agg_merge_velocity(vj, vl, (double)ki, (double)kk);
      const double q2 = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
      agg_book_merge(A, ki, kk, Eimp);
      if (kLow) {
        slot_remove(A, ai, j);
        slot_touch(A, ai);
        slot_remove(A, ak, l);
        slot_touch(A, ak);
      }
      p->species[j] = (int32_t)(K - 1);
      const int64_t jj = j == p->n - 1 ? l : j; /* j is the last particle: it moves into l */
      remove_particle(l, j);
      if (kLow) {
        const int64_t a = slot_get(A, K);
        slot_add(A, a, jj);
        slot_raise(A, a, q2);
        slot_touch(A, a);
      } else {
        bird_grow(s, A, K);
        bird_raise(s, A, K, q2);
      }
      raise_all(q2);
      flush = true;
      return true;
    }
    double u[3];
    w.unit3(u);
    const double ga = std::sqrt(g2);
    const double gn[3] = {0.5 * (g[0] - ga * u[0]), 0.5 * (g[1] - ga * u[1]), 0.5 * (g[2] - ga * u[2])};
    const double gn2 = gn[0] * gn[0] + gn[1] * gn[1] + gn[2] * gn[2];
    if (0.5 * mu * gn2 > e_frag) { /* shatter into the pieces of the fragment law */
      const AggPieces pc = agg_pieces(w, A->frag_law, K);
      const int64_t P = pc.P, n0 = p->n;
      if (kLow && n0 + P - 2 >= INT32_MAX) { /* the member lists hold 32-bit indices */
        status = GRAN_ERROR(GRAN_ERR_RANGE, "fragmentation would make more than 2^31 particles (low-rank selector)");
        return false;
      }
      if (n0 + P - 2 > p->capacity) { /* one growth at most, geometric */
        const int64_t want = std::max(n0 + P - 2, 2 * p->capacity);
        status = gran_particles_reserve(p, want);
        if (status != GRAN_SUCCESS) return false;
        if (kLow) A->mpos.resize((size_t)p->capacity);
        vj = p->v + 3 * j;
        vl = p->v + 3 * l;
      }
      if (kLow) {
        slot_remove(A, ai, j);
        slot_touch(A, ai);
        slot_remove(A, ak, l); /* ak == ai: the slot still holds l (it held j and l) */
        slot_touch(A, ak);
      }
      double Vc[3];
      for (int d = 0; d < 3; d++) Vc[d] = ((double)ki * vj[d] + (double)kk * vl[d]) / (double)K;
      p->n = n0 + P - 2;
      double *const v = p->v;
      auto target = [&](int64_t q) { return q == 0 ? j : q == 1 ? l : n0 + q - 2; };
      const double E0 = A->eps_f * A->eps_f * Eimp;
      const double m2 = agg_fragment_velocities(w, pc, [&](int64_t q) { return v + 3 * target(q); }, Vc,
                                                agg_fragment_speed(ki, kk, A->eps_f, ga), E0, m1);
      for (int64_t q = 0; q < P; q++) p->species[target(q)] = (int32_t)(pc.size(q) - 1);
      agg_book_shatter(A, ki, kk, pc, Eimp, E0);
      if (kLow) {
        int64_t last_a = -1;
        for (int64_t q = 0; q < P; q++) {
          const int64_t t = target(q), a = slot_get(A, pc.size(q));
          slot_add(A, a, t);
          const double *vt = v + 3 * t;
          slot_raise(A, a, vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2]);
          if (a != last_a && last_a >= 0) slot_touch(A, last_a);
          last_a = a;
        }
        slot_touch(A, last_a);
      } else { /* each size among the pieces: its bound at least the fastest piece's speed */
        for (int64_t q = 0; q < P; q++)
          if (q == 0 || pc.size(q) != pc.size(q - 1)) {
            bird_grow(s, A, pc.size(q));
            bird_raise(s, A, pc.size(q), m2);
          }
      }
      raise_all(m2);
      flush = true;
      return true;
    }
    /* bounce (constant eps) */
    const double a = (1.0 + eps0) * inv, aj = a * mk, al = a * mi;
    for (int d = 0; d < 3; d++) {
      vj[d] -= aj * gn[d];
      vl[d] += al * gn[d];
    }
    neumaier_add(ed, edc, 0.5 * (1.0 - eps0 * eps0) * mu * gn2);
    A->bounces++;
    const double sj = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
    const double sl = vl[0] * vl[0] + vl[1] * vl[1] + vl[2] * vl[2];
    bool changed = false;
    if (kLow) {
      if (slot_raise(A, ai, sj)) {
        slot_touch(A, ai);
        changed = true;
      }
      if (slot_raise(A, ak, sl)) {
        slot_touch(A, ak);
        changed = true;
      }
      raise_all(std::max(sj, sl));
    } else {
      raise_all(std::max(sj, sl));
      changed = bird_raise(s, A, ki, sj);
      changed = bird_raise(s, A, kk, sl) || changed;
    }
    if (changed) s->bound_raises++;
    return changed;
  };

  /* after a collision: tighten when due, restart the trial times when the rate changed */
  auto after = [&](bool changed) {
    if (coll >= s->next_refresh) {
      flush = true;
      if (aggev_tighten(s) != GRAN_SUCCESS) status = GRAN_ERR_NOMEM;
      changed = true;
    } else if (changed) {
      aggev_rate(s);
    }
    if (changed) {
      if (kLow || flush) A->cand_count = 0; /* low-rank: any change is a change of the law */
      t_ref = now();
      tprod = 1.0;
      tlog = 0.0;
      inv_rate = s->inv_rate;
      set_thr();
    }
    flush = false;
  };

  /* stage 1 of a candidate: the pair drawn, the member entries (low-rank) or the particles (Bird)
   * prefetched; stage 2 (low-rank): the member entries read, the particles prefetched */
  auto draw = [&](DsmcAggEv::Cand &c) {
    if (kLow) {
      const double u0 = A->u[0].node[1] * A->v[0].node[1], u1 = A->u[1].node[1] * A->v[1].node[1],
                   u2 = A->u[2].node[1] * A->v[2].node[1];
      const double x = w.uniform() * (u0 + u1 + u2);
      const int r = x < u0 ? 0 : x < u0 + u1 ? 1 : 2;
      c.a = segtree_sample(&A->u[r], w.uniform());
      c.b = segtree_sample(&A->v[r], w.uniform());
      const std::vector<int32_t> &ma = A->members[(size_t)c.a], &mb = A->members[(size_t)c.b];
      c.j = w.below((int64_t)ma.size());
      c.l = w.below((int64_t)mb.size());
      c.resolved = 0;
      __builtin_prefetch(ma.data() + c.j);
      __builtin_prefetch(mb.data() + c.l);
    } else {
      c.j = w.below(p->n);
      c.l = w.below(p->n);
      c.a = c.b = 0;
      c.resolved = 1;
      prefetch_v(c.j);
      prefetch_v(c.l);
    }
  };
  auto resolve = [&](DsmcAggEv::Cand &c) {
    if (!kLow || c.resolved) return;
    c.j = A->members[(size_t)c.a][(size_t)c.j];
    c.l = A->members[(size_t)c.b][(size_t)c.l];
    c.resolved = 1;
    prefetch_v(c.j);
    prefetch_v(c.l);
  };

  double t_last_coll = -INFINITY;
  bool stop = false;
  if (s->pend_on) { /* accepted before the last stop, at a time beyond it */
    if (s->pend_t > t_stop) return GRAN_SUCCESS;
    s->pend_on = 0;
    t_last_coll = s->pend_t;
    const int64_t j = s->pend_c.j, l = s->pend_c.l;
    after(collide(j, l, p->species[j], p->species[l], kLow ? slot_of_p(j) : -1, kLow ? slot_of_p(l) : -1));
    stop = coll >= coll_stop || status != GRAN_SUCCESS;
  }
  while (!stop) {
    if (std::isinf(inv_rate)) break; /* no pair can collide */
    if ((trials & 63) == 0 && tprod < pthr) break;
    ++trials;
    if (A->cand_count == 0) { /* refill: draw all, resolve the first half */
      for (int q = 0; q < kPipe; q++) draw(A->cand[q]);
      for (int q = 0; q < kPipe / 2; q++) resolve(A->cand[q]);
      A->cand_head = 0;
      A->cand_count = kPipe;
    }
    DsmcAggEv::Cand &slot = A->cand[A->cand_head];
    resolve(slot);
    const DsmcAggEv::Cand c = slot;
    draw(slot); /* its replacement, used kPipe trials from now */
    resolve(A->cand[(A->cand_head + kPipe / 2) & (kPipe - 1)]);
    A->cand_head = (A->cand_head + 1) & (kPipe - 1);
    const int64_t j = c.j, l = c.l;
    double wgt = 1.0;
    const double B = kLow ? A->sbound[(size_t)c.a] + A->sbound[(size_t)c.b] : s->cmax;
    tprod *= u64_uniform_pos(w.next());
    if (tprod < 1e-280) {
      tlog -= std::log(tprod);
      tprod = 1.0;
      set_thr();
    }
    const double ub = w.uniform() * B;
    if (j == l) continue;
    const double *vj = p->v + 3 * j, *vl = p->v + 3 * l;
    const double g[3] = {vj[0] - vl[0], vj[1] - vl[1], vj[2] - vl[2]};
    if (!kLow) {
      const double sjl = 0.5 * (A->sigk[(size_t)p->species[j]] + A->sigk[(size_t)p->species[l]]);
      wgt = sjl * sjl;
    }
    if (!(ub * ub < wgt * wgt * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]))) continue;
    if (tprod < pthr) { /* the collision belongs to a later interval */
      s->pend_on = 1;
      s->pend_c = DsmcCand{j, l, 0, 0, 0, 0};
      s->pend_t = now();
      break;
    }
    const double tc = now();
    /* the sizes: low-rank from the slots (no load of the species), Bird loaded above */
    const int32_t i = kLow ? (int32_t)(A->slot_size[(size_t)c.a] - 1) : p->species[j];
    const int32_t k = kLow ? (int32_t)(A->slot_size[(size_t)c.b] - 1) : p->species[l];
    after(collide(j, l, i, k, c.a, c.b));
    if (status != GRAN_SUCCESS) break;
    if (coll >= coll_stop) {
      t_last_coll = tc;
      break;
    }
  }
  if (t_last_coll > s->t) s->t = t_last_coll;
  aggev_sync(s);
  return status;
}

}  // namespace

int dsmc_aggev_advance(gran_dsmc *s, double t_end, int64_t coll_stop) {
  DsmcAggEv *A = ev(s);
  try {
    GRAN_CALL(A->lowrank ? aggev_loop<true>(s, t_end, coll_stop) : aggev_loop<false>(s, t_end, coll_stop));
  } catch (const std::bad_alloc &) {
    return GRAN_ERROR(GRAN_ERR_NOMEM, "aggregation: cannot grow the size tables (" GRAN_I64_FMT " particles)", s->N);
  }
  if (s->collisions >= coll_stop) return GRAN_SUCCESS;
  GRAN_CHECK(t_end < DBL_MAX, GRAN_ERR_STATE, "no collision can happen: the total collision rate is 0 (" GRAN_I64_FMT
             " cluster(s) left)", s->N);
  s->t = t_end;
  return GRAN_SUCCESS;
}

}  // namespace gran

using namespace gran;

/** @brief Defaults of the aggregation options: off (e_agg 0, e_frag INFINITY), eps_f 1, monomers. */
GRAN_EXTERN int gran_dsmc_agg_options_default(gran_dsmc_agg_options *agg) {
  GRAN_CHECK_PTR(agg);
  *agg = gran_dsmc_agg_options{};
  agg->e_agg = 0;
  agg->e_frag = INFINITY;
  agg->eps_f = 1;
  agg->frag_law = GRAN_FRAG_MONOMERS;
  return GRAN_SUCCESS;
}

/** @brief New engine of an event selector with aggregation and fragmentation.
 *  @param[in] agg the processes (both off: the same engine as gran_dsmc_create)
 *  @param[out] sim the new engine */
GRAN_EXTERN int gran_dsmc_create_agg(const gran_mixture *mix, const int64_t *counts, const double *T0,
                                     const gran_dsmc_options *opt, const gran_dsmc_agg_options *agg,
                                     gran_dsmc **sim) {
  GRAN_TRY {
    GRAN_CHECK_PTR(sim);
    *sim = nullptr;
    GRAN_CHECK_PTR(mix);
    GRAN_CHECK_PTR(opt);
    GRAN_CALL(dsmc_agg_check_options(agg));
    GRAN_CHECK(opt->selector != GRAN_SELECTOR_CELL, GRAN_ERR_ARG,
               "option 'selector' = GRAN_SELECTOR_CELL: use gran_dsmc_create_cell (its options hold e_agg, e_frag, "
               "eps_f and frag_law)");
    gran_dsmc *s = nullptr;
    gran_dsmc_options o = *opt;
    const bool on = agg->e_agg > 0 || std::isfinite(agg->e_frag);
    /* the automatic speed classes stay off with the processes (explicit ones are refused below) */
    if (on && o.speed_classes == GRAN_SPEED_CLASSES_AUTO) o.speed_classes = GRAN_SPEED_CLASSES_OFF;
    GRAN_CALL(gran_dsmc_create(mix, counts, T0, &o, &s));
    if (!on) { /* off: the plain engine */
      *sim = s;
      return GRAN_SUCCESS;
    }
    int st = dsmc_check_derived(s, true, true); /* the masses and diameters clusters can reach */
    if (st != GRAN_SUCCESS) {
      gran_dsmc_destroy(&s);
      return st;
    }
    try {
      st = dsmc_aggev_setup(s, agg);
    } catch (const std::bad_alloc &) {
      st = GRAN_ERROR(GRAN_ERR_NOMEM, "aggregation: cannot allocate the size tables");
    }
    if (st != GRAN_SUCCESS) {
      gran_dsmc_destroy(&s);
      return st;
    }
    *sim = s;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
