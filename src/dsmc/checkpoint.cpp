/* checkpoint.cpp - the complete DSMC engine state in one HDF5 group, so that a restart continues
 * bit for bit: particles, bounds, the tree node arrays as they are, the pre-drawn candidates, RNG
 * state, time and pending trial, counters, the ledger sums with their compensation terms,
 * collision counters, trajectory buffers, options. The mixture is not stored: the reader passes
 * it and it must match (masses, diameters, restitution model, which species are tracers;
 * checked). The tracer flags are derived from that mixture (n_k = 0) and the stored counts, as at
 * creation; the stored flags only check them (files without them are accepted). The fields go
 * through the state interface of the I/O layer (src/io/state.h), which names the file and the
 * field in every refusal. */
#include "dsmc_impl.h"
#include "cell_impl.h"
#include "agg_impl.h"
#include "io/state.h"

#include <algorithm>
#include <cfloat>
#include <string>

namespace gran {
namespace {

const char *kFormat = "granary-dsmc-state 4"; /* 2: the clock counts from t_start; 3: cell selector;
                                               * 4: fragment law, aggregation in the event selectors */
const char *kFormat2 = "granary-dsmc-state 2"; /* read: the same state without the cell selector */
const char *kFormat3 = "granary-dsmc-state 3"; /* read: without the fragment law (monomers) */

/* The state's fields through the state interface (src/io/state.h), with the names the templates
 * below share between writing and reading. */
struct Writer {
  const gran_state::Group &g;
  const char *path;
  int d(const char *name, int64_t n, const double *x) { return g.put(name, n, x); }
  int i64(const char *name, int64_t n, const int64_t *x) { return g.put(name, n, x); }
  int i32(const char *name, int64_t n, const int32_t *x) { return g.put(name, n, x); }
  int u64(const char *name, int64_t n, const uint64_t *x) { return g.put(name, n, x); }
  int d1(const char *name, double x) { return g.put1(name, x); }
  int i1(const char *name, int64_t x) { return g.put1(name, x); }
};

struct Reader {
  const gran_state::Group &g;
  const char *path;
  int d(const char *name, int64_t n, double *x) { return g.get(name, n, x); }
  int i64(const char *name, int64_t n, int64_t *x) { return g.get(name, n, x); }
  int i32(const char *name, int64_t n, int32_t *x) { return g.get(name, n, x); }
  int u64(const char *name, int64_t n, uint64_t *x) { return g.get(name, n, x); }
  /* number of values of a dataset (-1 when missing): sizes are checked before anything is allocated */
  int64_t npoints(const char *name) { return g.npoints(name); }
  bool has(const char *name) { return g.has(name); }
  int i1(const char *name, int64_t *x) { return g.get1(name, x); }
};

/* Speed classes: slots, leaves, the bounds of the alias table and the tree of raises,
 * class counters, the leaves of the pre-drawn candidates. Identities (cid) with trajectories. */
template <class F, class D>
int class_io(F &f, D *s) {
  const int64_t S = s->S, L = s->L;
  GRAN_CALL(f.d("class_v", 3 * S, s->cv.data()));
  if (!s->cr.empty()) GRAN_CALL(f.d("class_r", 3 * S, s->cr.data()));
  if (!s->cid.empty()) GRAN_CALL(f.i32("class_id", S, s->cid.data()));
  std::vector<double> lr((size_t)(3 * L));
  std::vector<int64_t> li((size_t)(3 * L));
  for (int64_t a = 0; a < L; a++) {
    const DsmcLeaf &x = s->leaf[(size_t)a];
    lr[(size_t)(3 * a)] = x.b;
    lr[(size_t)(3 * a + 1)] = x.b2;
    lr[(size_t)(3 * a + 2)] = x.lo2;
    li[(size_t)(3 * a)] = x.start;
    li[(size_t)(3 * a + 1)] = x.cap;
    li[(size_t)(3 * a + 2)] = x.n;
  }
  GRAN_CALL(f.d("class_leaf_real", 3 * L, lr.data()));
  GRAN_CALL(f.i64("class_leaf_int", 3 * L, li.data()));
  for (int64_t a = 0; a < L; a++) {
    DsmcLeaf &x = s->leaf[(size_t)a];
    x.b = lr[(size_t)(3 * a)];
    x.b2 = lr[(size_t)(3 * a + 1)];
    x.lo2 = lr[(size_t)(3 * a + 2)];
    x.start = li[(size_t)(3 * a)];
    x.cap = li[(size_t)(3 * a + 1)];
    x.n = li[(size_t)(3 * a + 2)];
  }
  GRAN_CALL(f.d("class_ub", L, s->ub.data()));
  GRAN_CALL(f.d("class_wref", s->M, s->cwref.data()));
  GRAN_CALL(f.d("class_ud", 2 * s->ud.base, s->ud.node));
  int64_t ct[3] = {s->class_moves, s->class_rebuilds, s->ud.nupdate};
  GRAN_CALL(f.i64("class_counters", 3, ct));
  s->class_moves = ct[0];
  s->class_rebuilds = ct[1];
  s->ud.nupdate = ct[2];
  int32_t ab[2 * kDsmcPipe + 2];
  for (int q = 0; q < kDsmcPipe; q++) {
    ab[2 * q] = s->cand[q].a;
    ab[2 * q + 1] = s->cand[q].b;
  }
  ab[2 * kDsmcPipe] = s->pend_c.a;
  ab[2 * kDsmcPipe + 1] = s->pend_c.b;
  GRAN_CALL(f.i32("class_cand_ab", 2 * kDsmcPipe + 2, ab));
  for (int q = 0; q < kDsmcPipe; q++) {
    s->cand[q].a = ab[2 * q];
    s->cand[q].b = ab[2 * q + 1];
  }
  s->pend_c.a = ab[2 * kDsmcPipe];
  s->pend_c.b = ab[2 * kDsmcPipe + 1];
  return GRAN_SUCCESS;
}

/* Everything but the options, counts and mixture check (shared by write and read through F). */
template <class F, class D>
int state_io(F &f, D *s) {
  const int64_t N = s->N, M = s->M;
  if (s->classes) {
    GRAN_CALL(class_io(f, s)); /* speed classes: the slots instead of the particles */
  } else {
  GRAN_CALL(f.d("v", 3 * N, s->p.v));
  if (s->p.r) {
    GRAN_CALL(f.d("r", 3 * N, s->p.r));
    GRAN_CALL(f.d("t_last", N, s->p.t_last));
  }
  }
  GRAN_CALL(f.d("bound", M, s->bound.data()));
  GRAN_CALL(f.d("bound2", M, s->bound2.data()));
  if (s->selector == GRAN_SELECTOR_LOWRANK) {
    const char *un[3] = {"tree_u0", "tree_u1", "tree_u2"}, *vn[3] = {"tree_v0", "tree_v1", "tree_v2"};
    for (int r = 0; r < 3; r++) {
      GRAN_CALL(f.d(un[r], 2 * s->u[r].base, s->u[r].node));
      GRAN_CALL(f.d(vn[r], 2 * s->v[r].base, s->v[r].node));
    }
    int64_t nup[6] = {s->u[0].nupdate, s->u[1].nupdate, s->u[2].nupdate,
                      s->v[0].nupdate, s->v[1].nupdate, s->v[2].nupdate};
    GRAN_CALL(f.i64("tree_nupdate", 6, nup));
    for (int r = 0; r < 3; r++) {
      s->u[r].nupdate = nup[r];
      s->v[r].nupdate = nup[3 + r];
    }
  }
  GRAN_CALL(f.d("uv", 3, s->uv));
  double sc[16] = {s->cmax,     s->rate,     s->inv_rate, s->t,      s->t_ref,     s->acc_last,
                   s->e_initial, s->e_diss,   s->e_diss_c, s->volume,  s->tprod,     s->tlog,
                   s->pend_t,    s->pend_e[0], s->pend_e[1], s->pend_e[2]};
  GRAN_CALL(f.d("scalars", 16, sc));
  s->cmax = sc[0];
  s->rate = sc[1];
  s->inv_rate = sc[2];
  s->t = sc[3];
  s->t_ref = sc[4];
  s->acc_last = sc[5];
  s->e_initial = sc[6];
  s->e_diss = sc[7];
  s->e_diss_c = sc[8];
  s->volume = sc[9];
  s->tprod = sc[10];
  s->tlog = sc[11];
  s->pend_t = sc[12];
  for (int d = 0; d < 3; d++) s->pend_e[d] = sc[13 + d];
  int64_t ct[15] = {s->collisions,    s->trials,     s->bound_raises,  s->bound_tightenings, s->next_refresh,
                    s->coll_at_refresh, s->trials_at_refresh, s->cand_head, s->cand_count, s->traj_next,
                    s->pend_on,       s->pend_c.j,   s->pend_c.l,      s->pend_c.i,          s->pend_c.k};
  GRAN_CALL(f.i64("counters", 15, ct));
  s->collisions = ct[0];
  s->trials = ct[1];
  s->bound_raises = ct[2];
  s->bound_tightenings = ct[3];
  s->next_refresh = ct[4];
  s->coll_at_refresh = ct[5];
  s->trials_at_refresh = ct[6];
  s->cand_head = (int32_t)ct[7];
  s->cand_count = (int32_t)ct[8];
  s->traj_next = ct[9];
  s->pend_on = (int32_t)ct[10];
  s->pend_c.j = ct[11];
  s->pend_c.l = ct[12];
  s->pend_c.i = (int32_t)ct[13];
  s->pend_c.k = (int32_t)ct[14];
  GRAN_CALL(f.u64("rng", 4, s->rng.s));
  GRAN_CALL(f.u64("rng_lanes", 4 * kRngLanes, &s->vrng.s[0][0]));
  GRAN_CALL(f.u64("rng_buffer", kRngBuf, s->vrng.buf));
  int64_t rpos = s->vrng.pos;
  GRAN_CALL(f.i64("rng_pos", 1, &rpos));
  s->vrng.pos = (int32_t)rpos;
  int64_t cj[2 * kDsmcPipe];
  int32_t ci[2 * kDsmcPipe];
  for (int q = 0; q < kDsmcPipe; q++) {
    cj[2 * q] = s->cand[q].j;
    cj[2 * q + 1] = s->cand[q].l;
    ci[2 * q] = s->cand[q].i;
    ci[2 * q + 1] = s->cand[q].k;
  }
  GRAN_CALL(f.i64("cand_jl", 2 * kDsmcPipe, cj));
  GRAN_CALL(f.i32("cand_ik", 2 * kDsmcPipe, ci));
  for (int q = 0; q < kDsmcPipe; q++) {
    s->cand[q].j = cj[2 * q];
    s->cand[q].l = cj[2 * q + 1];
    s->cand[q].i = ci[2 * q];
    s->cand[q].k = ci[2 * q + 1];
  }
  if (!s->ccount.empty()) GRAN_CALL(f.i64("collision_counts", M * M, s->ccount.data()));
  if (!s->traj_xyz.empty()) GRAN_CALL(f.d("trajectories", (int64_t)s->traj_xyz.size(), s->traj_xyz.data()));
  return GRAN_SUCCESS;
}

/* Speed classes: the leaves partition each species' slots in order, hold its particles, bound
 * their occupants; the trees are the weights of the leaves; identities a permutation. */
template <class Need>
void validate_classes(const gran_dsmc *s, Need &need) {
  const double *v = s->cv.data();
  for (int64_t k = 0; k < s->M; k++) {
    int64_t x = s->sslot[(size_t)k], nk = 0;
    for (int64_t a = s->sleaf[(size_t)k]; a < s->sleaf[(size_t)k + 1]; a++) {
      const DsmcLeaf &l = s->leaf[(size_t)a];
      need(l.start == x && l.cap >= 0 && l.n >= 0 && l.n <= l.cap, "class slots");
      if (!(l.start == x && l.cap >= 0 && l.n >= 0 && l.n <= l.cap)) return;
      need(std::isfinite(l.b) && l.b >= 0 && l.b == std::sqrt(l.b2) && std::isfinite(l.lo2), "class bounds");
      need(l.b2 <= s->bound2[(size_t)k] || s->bound2[(size_t)k] == 0, "class bounds");
      for (int64_t j = l.start; j < l.start + l.n; j++) {
        const double *w = v + 3 * j;
        const double q = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        need(std::isfinite(q) && q <= l.b2 * (1 + 1e-12), "class bounds");
      }
      const double ub = s->ub[(size_t)a];
      need(std::isfinite(ub) && ub >= 0 && ub <= l.b, "class alias bounds");
      x += l.cap;
      nk += l.n;
    }
    need(x == s->sslot[(size_t)k + 1] && nk == s->count[(size_t)k], "class slots");
    if (!(x == s->sslot[(size_t)k + 1] && nk == s->count[(size_t)k])) return;
  }
  for (double w : s->cwref) need(std::isfinite(w) && w >= 0, "class reference speeds");
  /* the leaves of the trees are the weights of the leaves (species, class), bit for bit */
  for (int64_t a = 0; a < s->L; a++) {
    const DsmcLeaf &l = s->leaf[(size_t)a];
    const double sg = s->mix.sigma[(size_t)l.species], cap = (double)l.cap, bn = l.b * cap;
    need(s->u[0].node[s->u[0].base + a] == bn * sg * sg && s->u[1].node[s->u[1].base + a] == 2.0 * bn * sg &&
             s->u[2].node[s->u[2].base + a] == bn,
         "class tree leaves");
    need(s->v[0].node[s->v[0].base + a] == cap && s->v[1].node[s->v[1].base + a] == cap * sg &&
             s->v[2].node[s->v[2].base + a] == cap * sg * sg,
         "class tree leaves");
  }
  const gran_segtree *t = &s->ud;
  for (int64_t i = t->base; i < 2 * t->base; i++) need(std::isfinite(t->node[i]) && t->node[i] >= 0, "class raise tree");
  for (int64_t i = 1; i < t->base; i++) need(t->node[i] == t->node[2 * i] + t->node[2 * i + 1], "class raise tree");
  if (!s->cid.empty()) {
    std::vector<uint8_t> seen((size_t)s->N, 0);
    for (int64_t k = 0; k < s->M; k++)
      dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++) {
          const int64_t id = s->cid[(size_t)j];
          const bool ok = id >= s->offset[(size_t)k] && id < s->offset[(size_t)k + 1] && !seen[(size_t)id];
          need(ok, "class identities");
          if (ok) seen[(size_t)id] = 1;
        }
      });
  }
}

/* Everything read from a file is used without further checks by the hot loop: refuse a state
 * whose indices lie outside their arrays, whose numbers are not finite, or whose trees are not
 * the sums of their leaves (a damaged or edited file that still passed the file checksum). */
int validate_state(const gran_dsmc *s, const char *path) {
  const int64_t N = s->N, M = s->M;
  const char *bad = nullptr;
  auto need = [&](bool ok, const char *what) {
    if (!ok && !bad) bad = what;
  };
  need(s->vrng.pos >= 0 && s->vrng.pos <= kRngBuf, "rng_pos");
  /* generator states: what a generator reaches (src/io/state.h, the GSRD reader's rule) */
  need(gran_state::rng_plausible(s->rng.s[0], s->rng.s[1], s->rng.s[2], s->rng.s[3]), "rng");
  for (int l = 0; l < kRngLanes; l++)
    need(gran_state::rng_plausible(s->vrng.s[0][l], s->vrng.s[1][l], s->vrng.s[2][l], s->vrng.s[3][l]), "rng_lanes");
  need(s->cand_head >= 0 && s->cand_head < kDsmcPipe && (s->cand_count == 0 || s->cand_count == kDsmcPipe),
       "candidate pipeline");
  need(s->traj_next >= 0 && s->traj_next <= s->opt.traj_samples, "trajectory sample index");
  need(s->collisions >= 0 && s->trials >= s->collisions && s->bound_raises >= 0 && s->bound_tightenings >= 0,
       "counters");
  need(s->coll_at_refresh >= 0 && s->coll_at_refresh <= s->collisions && s->trials_at_refresh >= 0 &&
           s->trials_at_refresh <= s->trials && s->next_refresh >= 0,
       "refresh counters");
  need(std::isfinite(s->t) && std::isfinite(s->t_ref), "time");
  need(s->tprod > 0 && s->tprod <= 1 && std::isfinite(s->tlog) && s->tlog >= 0, "pending trial time");
  need(!(s->inv_rate < 0) && !std::isnan(s->inv_rate) && std::isfinite(s->rate) && s->rate >= 0, "trial rate");
  need(std::isfinite(s->cmax) && s->cmax >= 0, "Bird bound C_max");
  need(std::isfinite(s->e_initial) && s->e_initial >= 0 && std::isfinite(s->e_diss) && std::isfinite(s->e_diss_c),
       "energy ledger");
  need(std::isfinite(s->acc_last) && s->acc_last >= 0 && s->acc_last <= 1, "acceptance");
  need(std::isfinite(s->volume) && s->volume > 0, "volume");
  need(!s->pend_on || (std::isfinite(s->pend_t) && s->pend_t >= s->t), "pending collision time");
  for (int d = 0; d < 3; d++) need(std::isfinite(s->pend_e[d]), "pending collision direction");
  auto cand_ok = [&](const DsmcCand &c) {
    if (s->classes) { /* slots within the capacities of their leaves (species, class) */
      if (!(c.a >= 0 && c.a < s->L && c.b >= 0 && c.b < s->L)) return false;
      const DsmcLeaf &A = s->leaf[(size_t)c.a], &B = s->leaf[(size_t)c.b];
      return c.j >= A.start && c.j < A.start + A.cap && c.l >= B.start && c.l < B.start + B.cap &&
             c.i == A.species && c.k == B.species;
    }
    return c.j >= 0 && c.j < N && c.l >= 0 && c.l < N && c.i >= 0 && c.i < M && c.k >= 0 && c.k < M;
  };
  if (s->classes) validate_classes(s, need); /* before the candidates: they index the leaves */
  if (s->cand_count > 0)
    for (int q = 0; q < kDsmcPipe; q++) need(!bad && cand_ok(s->cand[q]), "candidate pairs");
  if (s->pend_on) need(!bad && cand_ok(s->pend_c), "pending collision");
  for (int64_t j = 0; j < 3 * N && !bad && !s->classes; j++) need(std::isfinite(s->p.v[j]), "velocities");
  if (s->p.r)
    for (int64_t j = 0; j < N && !bad; j++)
      need(std::isfinite(s->p.r[3 * j]) && std::isfinite(s->p.r[3 * j + 1]) && std::isfinite(s->p.r[3 * j + 2]) &&
               std::isfinite(s->p.t_last[j]),
           "displacements");
  for (int64_t k = 0; k < M && !bad; k++) {
    const double b = s->bound[(size_t)k];
    need(std::isfinite(b) && b >= 0 && b == std::sqrt(s->bound2[(size_t)k]), "speed bounds");
    /* a bound is an upper bound of the speeds of its species */
    dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
      for (int64_t j = ja; j < jb && !bad; j++) {
        const double *v = dsmc_hv(s) + 3 * j;
        need(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= s->bound2[(size_t)k] * (1 + 1e-12), "speed bounds");
      }
    });
  }
  for (int r = 0; r < 3 && !bad; r++) need(std::isfinite(s->uv[r]) && s->uv[r] >= 0, "rank-one weights");
  if (s->selector == GRAN_SELECTOR_LOWRANK) {
    for (const gran_segtree *t : {&s->u[0], &s->u[1], &s->u[2], &s->v[0], &s->v[1], &s->v[2]}) {
      for (int64_t i = t->base; i < 2 * t->base && !bad; i++) need(std::isfinite(t->node[i]) && t->node[i] >= 0, "tree leaves");
      for (int64_t i = 1; i < t->base && !bad; i++) need(t->node[i] == t->node[2 * i] + t->node[2 * i + 1], "tree sums");
    }
  }
  for (int64_t c : s->ccount) need(c >= 0 && c <= s->collisions, "collision counts");
  for (double x : s->traj_xyz) need(!std::isinf(x), "trajectories");
  GRAN_CHECK(!bad, GRAN_ERR_IO, "checkpoint '%s' holds an inconsistent engine state (%s; damaged or edited file?)",
             path, bad);
  return GRAN_SUCCESS;
}

/* The counters against each other and the rest of the state, once everything is read (a counter
 * far beyond what the run could have done, such as 9.2e18 merges, is an edited file):
 * - per-pair collision counts sum to at most the collisions;
 * - a collision raises at most two speed bounds and moves at most two particles between speed
 *   classes (each move at most one rebuild): bound_raises, class_moves, class_rebuilds in
 *   [0, 2 x collisions]; the trees' update counts >= 0;
 * - the next tightening of the bounds lies refresh_interval collisions after the last one (with
 *   aggregation, whose particle number changes: 1 .. max(interval, mass in monomers) after it);
 * - aggregation (any selector): every collision is a merge, a breakup or a bounce, so
 *   merges + breakups + bounces = collisions;
 * - cell selector: the step count is the elapsed time in steps (t within [step dt, (step + 1) dt)
 *   up to rounding: an advance stops at the last whole step before its end time). */
int counters_validate(const gran_dsmc *s, const char *path) {
  const int64_t C = s->collisions;
  auto refuse = [&](const char *field, int64_t v, const char *rule) {
    return GRAN_ERROR(GRAN_ERR_IO, "checkpoint '%s': counter '%s' = %lld %s (damaged or edited file?)", path, field,
                      (long long)v, rule);
  };
  {
    int64_t sum = 0;
    for (int64_t c : s->ccount) {
      if (c < 0 || c > C - sum) return refuse("collision_counts", c, "makes the per-pair counts exceed the collisions");
      sum += c;
    }
  }
  const double twoC = 2.0 * (double)C;
  if (s->bound_raises < 0 || (double)s->bound_raises > twoC)
    return refuse("bound_raises", s->bound_raises, "is outside [0, 2 x collisions]");
  if (s->class_moves < 0 || (double)s->class_moves > twoC)
    return refuse("class_moves", s->class_moves, "is outside [0, 2 x collisions]");
  if (s->class_rebuilds < 0 || (double)s->class_rebuilds > twoC)
    return refuse("class_rebuilds", s->class_rebuilds, "is outside [0, 2 x collisions]");
  if (s->ud.nupdate < 0) return refuse("class_counters[2]", s->ud.nupdate, "is negative");
  if (s->selector == GRAN_SELECTOR_LOWRANK)
    for (int r = 0; r < 3; r++)
      if (s->u[r].nupdate < 0 || s->v[r].nupdate < 0)
        return refuse("tree_nupdate", std::min(s->u[r].nupdate, s->v[r].nupdate), "is negative");
  {
    /* the interval: bound_refresh, else the particle number at creation (with aggregation at most
     * the mass in monomers: the number now may differ) */
    const int64_t gap = s->next_refresh - s->coll_at_refresh;
    const bool ok = s->agg ? gap >= 1 && gap <= std::max<int64_t>(s->refresh_interval, s->agg->monomers)
                           : gap == s->refresh_interval;
    if (s->next_refresh < s->coll_at_refresh || !ok)
      return refuse("next_refresh", s->next_refresh, "is not the last tightening's collision count + the interval");
  }
  if (s->agg) {
    const DsmcAgg *a = s->agg;
    const double sum = (double)a->merges + (double)a->breakups + (double)a->bounces;
    if (a->merges < 0 || a->breakups < 0 || a->bounces < 0 || sum != (double)C)
      return GRAN_ERROR(GRAN_ERR_IO,
                        "checkpoint '%s': counters 'merges' + 'breakups' + 'bounces' = %lld + %lld + %lld are not the "
                        "%lld collisions (damaged or edited file?)", path, (long long)a->merges, (long long)a->breakups,
                        (long long)a->bounces, (long long)C);
  }
  if (s->cell) {
    const DsmcCell *c = s->cell;
    const double dt = c->o.dt, k = (double)c->step, tk = s->t / dt, tol = 1e-9 + 4.0 * DBL_EPSILON * k;
    if (!(tk >= k - tol && tk < k + 1.0 + tol))
      return GRAN_ERROR(GRAN_ERR_IO,
                        "checkpoint '%s': counter 'step' = %lld does not match the time %g (%g steps of dt = %g; damaged "
                        "or edited file?)", path, (long long)c->step, s->t, tk, dt);
  }
  return GRAN_SUCCESS;
}

/* A stored option against the scene's, for the cell and aggregation blocks. */
int option_differs(const char *group, const char *path, const char *name, double stored, double scene) {
  return GRAN_ERROR(GRAN_ERR_IO,
                    "checkpoint '%s': the DSMC state in '%s' does not match the scene: option '%s' differs (stored "
                    "%.17g, scene %.17g; a checkpoint resumes the run of its own scene)", path, group, name, stored, scene);
}
bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

/* The stored cell options (the scene's [cell] table and its aggregation keys) against the scene's. */
int cell_options_match(const gran_dsmc_cell_options &c, const gran_dsmc_cell_options &o, const char *group,
                       const char *path) {
  const struct {
    const char *name;
    double stored, scene;
  } f[] = {{"cell_options.cells", (double)c.cells, (double)o.cells}, {"cell_options.dt", c.dt, o.dt}, {"cell_options.fn", c.fn, o.fn},
           {"cell_options.e_agg", c.e_agg, o.e_agg}, {"cell_options.e_frag", c.e_frag, o.e_frag}, {"cell_options.eps_f", c.eps_f, o.eps_f},
           {"cell_options.heat_rate", c.heat_rate, o.heat_rate}, {"cell_options.bath_density", c.bath_density, o.bath_density},
           {"cell_options.bath_mass", c.bath_mass, o.bath_mass}, {"cell_options.bath_T", c.bath_T, o.bath_T},
           {"cell_options.bath_sigma", c.bath_sigma, o.bath_sigma}, {"cell_options.placement", (double)c.placement, (double)o.placement},
           {"cell_options.frag_law", (double)c.frag_law, (double)o.frag_law},
           {"cell_options.streams", (double)c.streams, (double)o.streams}};
  for (const auto &x : f)
    if (!same(x.stored, x.scene)) return option_differs(group, path, x.name, x.stored, x.scene);
  return GRAN_SUCCESS;
}

/* The stored aggregation options of an event selector against the scene's (aggregation off: e_agg
 * 0 and e_frag infinite on the side without the block). */
int agg_options_match(const gran_dsmc_agg_options &c, const gran_dsmc_agg_options &o, const char *group,
                      const char *path) {
  if (!same(c.e_agg, o.e_agg)) return option_differs(group, path, "agg_options.e_agg", c.e_agg, o.e_agg);
  if (!same(c.e_frag, o.e_frag)) return option_differs(group, path, "agg_options.e_frag", c.e_frag, o.e_frag);
  if (!same(c.eps_f, o.eps_f)) return option_differs(group, path, "agg_options.eps_f", c.eps_f, o.eps_f);
  if (c.frag_law != o.frag_law)
    return option_differs(group, path, "agg_options.frag_law", (double)c.frag_law, (double)o.frag_law);
  return GRAN_SUCCESS;
}

/* ---- time-step/cell selector (cell.cpp): options, positions, carried fractions, step ----
 * Options first (the reader sets the cell state up from them), then the state. */
int cell_options_io(Writer &w, const gran_dsmc *s) {
  const gran_dsmc_cell_options &o = s->cell->o;
  int64_t ci[4] = {o.cells, o.placement, o.frag_law, o.streams};
  double cd[10] = {o.dt, o.fn, o.e_agg, o.e_frag, o.eps_f, o.heat_rate, o.bath_density, o.bath_mass, o.bath_T, o.bath_sigma};
  /* format 3: two (no fragment law); format 4 before the streams by cell: three (serial streams) */
  GRAN_CALL(w.i64("cell_options_int", o.streams == GRAN_CELL_STREAMS_SERIAL ? 3 : 4, ci));
  GRAN_CALL(w.d("cell_options_real", 10, cd));
  return GRAN_SUCCESS;
}
int cell_options_read(Reader &r, gran_dsmc_cell_options *o) {
  int64_t ci[4] = {0, 0, GRAN_FRAG_MONOMERS, GRAN_CELL_STREAMS_SERIAL};
  double cd[10];
  const int64_t np = r.npoints("cell_options_int");
  const int64_t nci = np == 4 ? 4 : np == 3 ? 3 : 2; /* format 3: no fragment law; no streams: serial */
  GRAN_CALL(r.i64("cell_options_int", nci, ci));
  GRAN_CALL(r.d("cell_options_real", 10, cd));
  gran_dsmc_cell_options_default(o);
  GRAN_CHECK(ci[0] >= 1 && ci[0] <= 1024 && ci[1] >= 0 && ci[1] <= 1 && (ci[2] == GRAN_FRAG_MONOMERS || ci[2] == GRAN_FRAG_BINARY) &&
                 (ci[3] == GRAN_CELL_STREAMS_SERIAL || ci[3] == GRAN_CELL_STREAMS_CELLS),
             GRAN_ERR_IO, "checkpoint '%s' holds invalid cell options (damaged or edited file?)", r.path);
  o->cells = ci[0];
  o->placement = (int32_t)ci[1];
  o->frag_law = (int32_t)ci[2];
  o->streams = (int32_t)ci[3];
  o->dt = cd[0];
  o->fn = cd[1];
  o->e_agg = cd[2];
  o->e_frag = cd[3];
  o->eps_f = cd[4];
  o->heat_rate = cd[5];
  o->bath_density = cd[6];
  o->bath_mass = cd[7];
  o->bath_T = cd[8];
  o->bath_sigma = cd[9];
  return GRAN_SUCCESS;
}
template <class F, class D>
int cell_state_io(F &f, D *s) {
  DsmcCell *c = s->cell;
  GRAN_CALL(f.d("cell_x", 3 * s->N, s->p.x));
  GRAN_CALL(f.d("cell_rem", c->C, c->rem.data()));
  double sc[8] = {c->vmax2, c->pmax_last, c->e_merge, c->e_merge_c, c->e_break, c->e_break_c, c->e_heat, c->e_heat_c};
  GRAN_CALL(f.d("cell_scalars", 8, sc));
  c->vmax2 = sc[0];
  c->pmax_last = sc[1];
  c->e_merge = sc[2];
  c->e_merge_c = sc[3];
  c->e_break = sc[4];
  c->e_break_c = sc[5];
  c->e_heat = sc[6];
  c->e_heat_c = sc[7];
  int64_t ct[6] = {c->step, c->merges, c->breakups, c->bounces, c->kmax, c->monomers};
  GRAN_CALL(f.i64("cell_counters", 6, ct));
  c->step = ct[0];
  c->merges = ct[1];
  c->breakups = ct[2];
  c->bounces = ct[3];
  c->kmax = ct[4];
  c->monomers = ct[5];
  return GRAN_SUCCESS;
}
/* aggregation: the species (size - 1) of every particle and the counts per size */
int cell_agg_write(Writer &w, const gran_dsmc *s) {
  const DsmcCell *c = s->cell;
  GRAN_CALL(w.i32("cell_species", s->N, s->p.species));
  GRAN_CALL(w.i64("cell_nsize", c->kmax, c->nsize.data()));
  return GRAN_SUCCESS;
}
/* the species of every particle and the counts per size (kmax and monomers already read), checked
 * against each other and the mass (both selector families) */
int agg_sizes_read(Reader &r, gran_dsmc *s, DsmcAgg *c, const char *species, const char *nsize) {
  const int64_t K = r.npoints(nsize);
  GRAN_CHECK(K >= 0 && K == c->kmax && K <= INT32_MAX / 2, GRAN_ERR_IO,
             "checkpoint '%s': dataset '%s' does not match the largest cluster size (damaged or edited file?)", r.path,
             nsize);
  GRAN_CALL(r.i32(species, s->N, s->p.species));
  dsmc_agg_grow(c, std::max<int64_t>(K, 1));
  std::fill(c->nsize.begin(), c->nsize.end(), 0);
  GRAN_CALL(r.i64(nsize, K, c->nsize.data()));
  /* the counts per size must be those of the particles, and the mass the stored one */
  std::vector<int64_t> h((size_t)K, 0);
  bool ok = true;
  for (int64_t j = 0; j < s->N && ok; j++) {
    const int32_t k = s->p.species[j];
    ok = k >= 0 && k < K;
    if (ok) h[(size_t)k]++;
  }
  int64_t mass = 0;
  for (int64_t k = 0; k < K && ok; k++) {
    ok = h[(size_t)k] == c->nsize[(size_t)k];
    mass += (k + 1) * h[(size_t)k];
  }
  GRAN_CHECK(ok && mass == c->monomers && (K == 0 || c->nsize[(size_t)K - 1] > 0), GRAN_ERR_IO,
             "checkpoint '%s' holds inconsistent cluster sizes (damaged or edited file?)", r.path);
  for (int64_t k = 0; k < s->M; k++) s->count[(size_t)k] = k < K ? c->nsize[(size_t)k] : 0;
  return GRAN_SUCCESS;
}
int cell_agg_read(Reader &r, gran_dsmc *s) {
  GRAN_CALL(agg_sizes_read(r, s, s->cell, "cell_species", "cell_nsize"));
  s->cell->where.assign((size_t)s->N, 0);
  return GRAN_SUCCESS;
}
int cell_validate(const gran_dsmc *s, const char *path) {
  const DsmcCell *c = s->cell;
  const char *bad = nullptr;
  auto need = [&](bool ok, const char *what) {
    if (!ok && !bad) bad = what;
  };
  for (int64_t j = 0; j < 3 * s->N && !bad; j++) need(s->p.x[j] >= 0 && s->p.x[j] < c->L, "positions");
  for (double r : c->rem) need(r >= 0 && r < 1, "carried candidate fractions");
  need(c->step >= 0 && std::isfinite(c->pmax_last) && c->pmax_last >= 0 && c->merges >= 0 && c->breakups >= 0 &&
           c->bounces >= 0 && c->kmax >= 0 && c->monomers >= 0,
       "cell counters");
  need(std::isfinite(c->e_merge + c->e_merge_c + c->e_break + c->e_break_c + c->e_heat + c->e_heat_c),
       "cell energy ledger");
  double m2 = 0;
  for (int64_t j = 0; j < s->N; j++) {
    const double *v = s->p.v + 3 * j;
    m2 = std::fmax(m2, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  need(std::isfinite(c->vmax2) && c->vmax2 >= m2, "cell speed bound");
  GRAN_CHECK(!bad, GRAN_ERR_IO, "checkpoint '%s' holds an inconsistent cell state (%s; damaged or edited file?)", path,
             bad);
  return GRAN_SUCCESS;
}
/* ---- end of the cell selector's block ---- */

/* ---- aggregation in the event selectors (agg_event.cpp): options, sizes, slots ----
 * The species of every particle, the counts per size, the ledger parts and counters, the global
 * bounds and (low-rank) the slots: the size and speed bound of each, the free list in order and
 * every particle's index in its member list (the lists, hence the draws, come back bit for bit). */
int aggev_write(Writer &w, const gran_dsmc *s) {
  const DsmcAggEv *A = static_cast<const DsmcAggEv *>(s->agg);
  const double od[3] = {A->e_agg, A->e_frag, A->eps_f};
  const int64_t oi[2] = {A->frag_law, A->lowrank};
  GRAN_CALL(w.d("agg_options_real", 3, od));
  GRAN_CALL(w.i64("agg_options_int", 2, oi));
  GRAN_CALL(w.i32("agg_species", s->N, s->p.species));
  GRAN_CALL(w.i64("agg_nsize", A->kmax, A->nsize.data()));
  const double sc[8] = {A->vmax2, A->smax, A->e_merge, A->e_merge_c, A->e_break, A->e_break_c, A->m1, A->sigma1};
  GRAN_CALL(w.d("agg_scalars", 8, sc));
  const int64_t ct[6] = {A->merges, A->breakups, A->bounces, A->kmax, A->monomers, A->ncap};
  GRAN_CALL(w.i64("agg_counters", 6, ct));
  {
    int64_t cd[5 * kDsmcPipe + 2];
    for (int q = 0; q < kDsmcPipe; q++) {
      const DsmcAggEv::Cand &c = A->cand[q];
      const int64_t x[5] = {c.j, c.l, c.a, c.b, c.resolved};
      std::copy(x, x + 5, cd + 5 * q);
    }
    cd[5 * kDsmcPipe] = A->cand_head;
    cd[5 * kDsmcPipe + 1] = A->cand_count;
    GRAN_CALL(w.i64("agg_candidates", 5 * kDsmcPipe + 2, cd));
  }
  if (A->lowrank) {
    GRAN_CALL(w.i64("agg_slot_size", A->ncap, A->slot_size.data()));
    GRAN_CALL(w.d("agg_slot_bound", A->ncap, A->sbound.data()));
    GRAN_CALL(w.i64("agg_free", (int64_t)A->free_slots.size(), A->free_slots.data()));
    GRAN_CALL(w.i64("agg_mpos", s->N, A->mpos.data()));
  } else { /* Bird: the speed bound of each size (C_max is among the engine's scalars) */
    std::vector<double> b((size_t)A->kmax, 0.0);
    std::copy(A->bsz.begin(), A->bsz.begin() + std::min((int64_t)A->bsz.size(), A->kmax), b.begin());
    GRAN_CALL(w.d("agg_size_bound", A->kmax, b.data()));
  }
  return GRAN_SUCCESS;
}
int aggev_read(Reader &r, gran_dsmc *s, const gran_dsmc_agg_options *expect, const char *group) {
  double od[3];
  int64_t oi[2];
  GRAN_CALL(r.d("agg_options_real", 3, od));
  GRAN_CALL(r.i64("agg_options_int", 2, oi));
  gran_dsmc_agg_options o;
  gran_dsmc_agg_options_default(&o);
  o.e_agg = od[0];
  o.e_frag = od[1];
  o.eps_f = od[2];
  o.frag_law = (int32_t)oi[0];
  GRAN_CHECK(dsmc_agg_check_options(&o) == GRAN_SUCCESS && (o.e_agg > 0 || std::isfinite(o.e_frag)) &&
                 oi[1] == (s->selector == GRAN_SELECTOR_LOWRANK),
             GRAN_ERR_IO, "checkpoint '%s' holds invalid aggregation options (damaged or edited file?)", r.path);
  if (expect) GRAN_CALL(agg_options_match(o, *expect, group, r.path));
  /* the particles: as many as stored (they were allocated for the stored velocities) */
  /* sizes and slots of the mixture layout, overwritten below; the refresh counters as stored */
  const double acc = s->acc_last, cmax = s->cmax;
  const int64_t rc[4] = {s->bound_tightenings, s->coll_at_refresh, s->trials_at_refresh, s->next_refresh};
  GRAN_CALL(dsmc_aggev_setup(s, &o));
  s->acc_last = acc;
  s->bound_tightenings = rc[0];
  s->coll_at_refresh = rc[1];
  s->trials_at_refresh = rc[2];
  s->next_refresh = rc[3];
  DsmcAggEv *A = static_cast<DsmcAggEv *>(s->agg);
  int64_t ct[6];
  GRAN_CALL(r.i64("agg_counters", 6, ct));
  GRAN_CHECK(ct[3] >= 0 && ct[4] >= 0 && ct[5] >= 0 && ct[5] <= (INT64_C(1) << 40) && (ct[5] & (ct[5] - 1)) == 0,
             GRAN_ERR_IO, "checkpoint '%s': invalid aggregation counters (damaged or edited file?)", r.path);
  A->merges = ct[0];
  A->breakups = ct[1];
  A->bounces = ct[2];
  A->kmax = ct[3];
  A->monomers = ct[4];
  GRAN_CALL(agg_sizes_read(r, s, A, "agg_species", "agg_nsize"));
  double sc[8];
  GRAN_CALL(r.d("agg_scalars", 8, sc));
  A->vmax2 = sc[0];
  A->smax = sc[1];
  A->e_merge = sc[2];
  A->e_merge_c = sc[3];
  A->e_break = sc[4];
  A->e_break_c = sc[5];
  double m2 = 0;
  for (int64_t j = 0; j < s->N; j++) {
    const double *v = s->p.v + 3 * j;
    m2 = std::fmax(m2, v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  }
  bool ok = sc[6] == A->m1 && sc[7] == A->sigma1 && A->merges >= 0 && A->breakups >= 0 && A->bounces >= 0 &&
            std::isfinite(A->vmax2) && A->vmax2 >= m2 && std::isfinite(A->smax) && A->smax >= 0 &&
            std::isfinite(A->e_merge + A->e_merge_c + A->e_break + A->e_break_c);
  GRAN_CHECK(ok, GRAN_ERR_IO, "checkpoint '%s' holds an inconsistent aggregation state (damaged or edited file?)", r.path);
  {
    int64_t cd[5 * kDsmcPipe + 2];
    GRAN_CALL(r.i64("agg_candidates", 5 * kDsmcPipe + 2, cd));
    for (int q = 0; q < kDsmcPipe; q++) {
      DsmcAggEv::Cand &c = A->cand[q];
      c.j = cd[5 * q];
      c.l = cd[5 * q + 1];
      c.a = cd[5 * q + 2];
      c.b = cd[5 * q + 3];
      c.resolved = cd[5 * q + 4];
    }
    A->cand_head = cd[5 * kDsmcPipe];
    A->cand_count = cd[5 * kDsmcPipe + 1]; /* checked with the slots (dsmc_aggev_read_done) */
  }
  if (!A->lowrank) { /* Bird: the speed bound of each size and C_max as stored */
    const int64_t nb = r.npoints("agg_size_bound");
    if (nb < 0) { /* written before the per-size bounds (2026-12): the global bound for every size */
      A->bsz.assign(A->nsize.size(), 0.0);
      for (int64_t k = 0; k < A->kmax; k++)
        if (A->nsize[(size_t)k] > 0) A->bsz[(size_t)k] = std::sqrt(A->vmax2);
      A->smax = A->kmax > 0 ? A->sigk[(size_t)A->kmax - 1] : 0.0;
      s->cmax = dsmc_aggev_bird_cmax(A);
    } else {
      GRAN_CHECK(nb == A->kmax, GRAN_ERR_IO, "checkpoint '%s': aggregation size bounds (damaged or edited file?)",
                 r.path);
      A->bsz.assign(A->nsize.size(), 0.0);
      GRAN_CALL(r.d("agg_size_bound", nb, A->bsz.data()));
      s->cmax = cmax;
      for (int64_t k = 0; k < nb && ok; k++) ok = std::isfinite(A->bsz[(size_t)k]) && A->bsz[(size_t)k] >= 0;
      for (int64_t j = 0; j < s->N && ok; j++) {
        const double *v = s->p.v + 3 * j, b = A->bsz[(size_t)s->p.species[j]];
        ok = v[0] * v[0] + v[1] * v[1] + v[2] * v[2] <= b * b * (1 + 1e-12);
      }
      ok = ok && (A->kmax == 0 || A->smax >= A->sigk[(size_t)A->kmax - 1]) && std::isfinite(s->cmax) &&
           s->cmax >= dsmc_aggev_bird_cmax(A) * (1 - 1e-12);
      GRAN_CHECK(ok, GRAN_ERR_IO, "checkpoint '%s' holds inconsistent aggregation speed bounds (damaged or edited file?)",
                 r.path);
    }
  }
  if (A->lowrank) {
    const int64_t C = ct[5];
    A->ncap = C;
    A->slot_size.assign((size_t)C, 0);
    A->sbound.assign((size_t)C, 0.0);
    GRAN_CALL(r.i64("agg_slot_size", C, A->slot_size.data()));
    GRAN_CALL(r.d("agg_slot_bound", C, A->sbound.data()));
    const int64_t nf = r.npoints("agg_free");
    GRAN_CHECK(nf >= 0 && nf <= C, GRAN_ERR_IO, "checkpoint '%s': aggregation free slots (damaged or edited file?)", r.path);
    A->free_slots.assign((size_t)nf, 0);
    GRAN_CALL(r.i64("agg_free", nf, A->free_slots.data()));
    A->mpos.assign((size_t)s->N, 0);
    GRAN_CALL(r.i64("agg_mpos", s->N, A->mpos.data()));
    std::vector<uint8_t> seen((size_t)C, 0);
    for (int64_t a : A->free_slots) {
      ok = ok && a >= 0 && a < C && !seen[(size_t)a];
      if (ok) seen[(size_t)a] = 1;
    }
    for (int64_t a = 0; a < C && ok; a++)
      ok = (A->slot_size[(size_t)a] == 0) == (seen[(size_t)a] == 1) && A->slot_size[(size_t)a] >= 0 &&
           std::isfinite(A->sbound[(size_t)a]) && A->sbound[(size_t)a] >= 0;
    GRAN_CHECK(ok, GRAN_ERR_IO, "checkpoint '%s' holds inconsistent aggregation slots (damaged or edited file?)", r.path);
  }
  const int st = dsmc_aggev_read_done(s);
  GRAN_CHECK(st == GRAN_SUCCESS, GRAN_ERR_IO, "checkpoint '%s' holds an inconsistent aggregation state (%s; damaged or "
             "edited file?)", r.path, gran_last_error_message());
  return GRAN_SUCCESS;
}
/* ---- end of the event selectors' aggregation block ---- */

/* The stored options against the run's (scene options, the replica's seed), field by field. */
int options_match(const gran_dsmc_options &c, const gran_dsmc_options &o, const char *group, const char *path) {
  auto differ = [&](const char *name, double a, double b) {
    return GRAN_ERROR(GRAN_ERR_IO,
                      "checkpoint '%s': the DSMC state in '%s' does not match the scene: option '%s' differs (stored "
                      "%.17g, scene %.17g; a checkpoint resumes the run of its own scene)", path, group, name, a, b);
  };
  if (c.seed != o.seed)
    return GRAN_ERROR(GRAN_ERR_IO,
                      "checkpoint '%s': the DSMC state in '%s' does not match the scene: option 'seed' differs (stored "
                      "%llu, this replica's %llu; a checkpoint resumes the run of its own scene)", path, group,
                      (unsigned long long)c.seed, (unsigned long long)o.seed);
  if (c.selector != o.selector) return differ("selector", c.selector, o.selector);
  if (c.observe != o.observe) return differ("observe", c.observe, o.observe);
  if (c.bound_refresh != o.bound_refresh) return differ("bound_refresh", (double)c.bound_refresh, (double)o.bound_refresh);
  if (c.t_start != o.t_start) return differ("t_start", c.t_start, o.t_start);
  if (c.traj_per_species != o.traj_per_species)
    return differ("traj_per_species", (double)c.traj_per_species, (double)o.traj_per_species);
  if (c.traj_samples != o.traj_samples) return differ("traj_samples", (double)c.traj_samples, (double)o.traj_samples);
  if (c.traj_dt != o.traj_dt) return differ("traj_dt", c.traj_dt, o.traj_dt);
  return GRAN_SUCCESS;
}

int options_io_write(Writer &w, const gran_dsmc *s) {
  const gran_dsmc_options &o = s->opt;
  int64_t oi[6] = {o.selector, o.observe, o.bound_refresh, o.traj_per_species, o.traj_samples, s->M};
  double od[3] = {o.volume, o.t_start, o.traj_dt};
  GRAN_CALL(w.i64("options_int", 6, oi));
  GRAN_CALL(w.d("options_real", 3, od));
  GRAN_CALL(w.u64("options_seed", 1, &o.seed));
  if (o.speed_classes) GRAN_CALL(w.i1("options_speed_classes", o.speed_classes)); /* absent: 0 */
  if (s->agg) { /* aggregation: unordered particles, all in the first slot range */
    std::vector<int64_t> lay((size_t)s->M, 0);
    lay[0] = s->N;
    GRAN_CALL(w.i64("counts", s->M, lay.data()));
  } else {
    GRAN_CALL(w.i64("counts", s->M, s->count.data()));
  }
  GRAN_CALL(w.d("mass", s->M, s->mix.m.data()));
  GRAN_CALL(w.d("sigma", s->M, s->mix.sigma.data()));
  GRAN_CALL(w.i1("restitution_model", s->mix.model));
  /* tracer flags: not needed to restart (derived from the mixture passed to the reader and the
   * counts), stored to refuse a mixture whose n_k = 0 pattern differs */
  std::vector<int32_t> trc(s->tracer.begin(), s->tracer.end());
  GRAN_CALL(w.i32("tracer", s->M, trc.data()));
  return GRAN_SUCCESS;
}

}  // namespace
}  // namespace gran

using namespace gran;

/* The engine state into group `group` of the open HDF5 file `fid` (`path` names it in messages). */
int gran_dsmc_checkpoint_write_h5_(const gran_dsmc *sim, int64_t file_id, const char *group, const char *path) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    gran_state::Group g;
    GRAN_CALL(g.create(file_id, group, kFormat, path));
    Writer w{g, path};
    GRAN_CALL(options_io_write(w, sim));
    GRAN_CALL(state_io(w, const_cast<gran_dsmc *>(sim))); /* the writer only reads the state */
    if (sim->cell) {
      GRAN_CALL(cell_options_io(w, sim));
      GRAN_CALL(cell_state_io(w, const_cast<gran_dsmc *>(sim)));
      if (sim->cell->by_cells) { /* streams by cell: the particles' keys */
        std::vector<int64_t> key((size_t)sim->N);
        dsmc_cell_keys(sim, key.data());
        GRAN_CALL(w.i64("cell_keys", sim->N, key.data()));
      }
      if (sim->cell->agg) GRAN_CALL(cell_agg_write(w, sim));
    } else if (sim->agg) {
      GRAN_CALL(aggev_write(w, sim)); /* event selectors with aggregation */
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Write the complete engine state into group `group` of the HDF5 file `path` (created if
 *  missing; an existing group of that name is replaced). */
GRAN_EXTERN int gran_dsmc_checkpoint_write(const gran_dsmc *sim, const char *path, const char *group) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(path);
    GRAN_CHECK_PTR(group);
    GRAN_CHECK(path[0] != '\0', GRAN_ERR_ARG, "argument 'path' is empty");
    GRAN_CHECK(group[0] != '\0' && std::strcmp(group, "/") != 0, GRAN_ERR_ARG,
               "argument 'group' = '%s' must name a group below the root", group);
    /* The file is assembled in memory (an existing one is read in whole) and committed by the
     * state interface: PATH.tmp, fsync, rename, with granary's checksum header. HDF5 never
     * writes to disk itself, so a full disk is a plain GRAN_ERR_IO and the previous file stays as
     * it was. */
    gran_state::File f;
    GRAN_CALL(f.open_update(path));
    GRAN_CALL(gran_dsmc_checkpoint_write_h5_(sim, f.id(), group, path));
    return f.commit("checkpoint");
  }
  GRAN_CATCH
}

/* A new engine from group `group` of the open HDF5 file `file_id` (`path` names it in messages). */
int gran_dsmc_checkpoint_read_h5_(int64_t file_id, const char *group, const gran_mixture *mix,
                                  const gran_dsmc_options *expect, const gran_dsmc_cell_options *expect_cell,
                                  const gran_dsmc_agg_options *expect_agg, gran_dsmc **sim, const char *path) {
  GRAN_TRY {
    GRAN_CHECK_PTR(sim);
    *sim = nullptr;
    GRAN_CALL(check_mixture(mix, "mix"));
    gran_state::Group g;
    GRAN_CALL(g.open(file_id, group, path));
    {
      std::string fmt;
      GRAN_CALL(g.format(&fmt));
      GRAN_CHECK(!fmt.empty(), GRAN_ERR_IO, "group '%s' in '%s' is not a DSMC checkpoint (no format)", group, path);
      GRAN_CHECK(fmt == kFormat || fmt == kFormat2 || fmt == kFormat3, GRAN_ERR_IO,
                 "group '%s' in '%s' is not a '%s' checkpoint", group, path, kFormat);
    }
    Reader rd{g, path};
    int64_t oi[6];
    double od[3];
    gran_dsmc_options o;
    gran_dsmc_options_default(&o);
    GRAN_CALL(rd.i64("options_int", 6, oi));
    GRAN_CALL(rd.d("options_real", 3, od));
    GRAN_CALL(rd.u64("options_seed", 1, &o.seed));
    o.selector = (int32_t)oi[0];
    o.observe = (int32_t)oi[1];
    o.bound_refresh = oi[2];
    o.traj_per_species = oi[3];
    o.traj_samples = oi[4];
    o.volume = od[0];
    o.t_start = od[1];
    o.traj_dt = od[2];
    o.speed_classes = 0; /* a file without the dataset: off, whatever the default */
    if (rd.has("options_speed_classes")) { /* speed classes */
      int64_t sc;
      GRAN_CALL(rd.i1("options_speed_classes", &sc));
      GRAN_CHECK(sc == 0 || sc == 1, GRAN_ERR_IO, "checkpoint '%s' holds invalid engine options (speed_classes)", path);
      o.speed_classes = (int32_t)sc;
    }
    if (expect) GRAN_CALL(options_match(o, *expect, group, path));
    const int64_t M = oi[5];
    GRAN_CHECK(M == mix->M, GRAN_ERR_ARG,
               "mixture 'mix' has " GRAN_I64_FMT " species, the checkpoint '%s' " GRAN_I64_FMT, mix->M, path, M);
    GRAN_CHECK(oi[0] >= 0 && oi[0] <= GRAN_SELECTOR_CELL && oi[1] >= 0 && oi[1] <= 7 && oi[2] >= 0 &&
                   oi[3] >= 0 && oi[4] >= 0 && std::isfinite(od[0]) && std::isfinite(od[1]) && std::isfinite(od[2]),
               GRAN_ERR_IO, "checkpoint '%s' holds invalid engine options (damaged or edited file?)", path);
    GRAN_CHECK(rd.npoints("counts") == M, GRAN_ERR_IO, "checkpoint '%s': dataset 'counts' does not have %" PRId64 " values",
               path, M);
    std::vector<int64_t> counts((size_t)M);
    std::vector<double> mass((size_t)M), sigma((size_t)M);
    int64_t model;
    GRAN_CALL(rd.i64("counts", M, counts.data()));
    GRAN_CALL(rd.d("mass", M, mass.data()));
    GRAN_CALL(rd.d("sigma", M, sigma.data()));
    GRAN_CALL(rd.i1("restitution_model", &model));
    for (int64_t k = 0; k < M; k++)
      GRAN_CHECK(mass[(size_t)k] == mix->m[(size_t)k] && sigma[(size_t)k] == mix->sigma[(size_t)k], GRAN_ERR_ARG,
                 "mixture 'mix' does not match checkpoint '%s': species " GRAN_I64_FMT " differs in mass or diameter",
                 path, k);
    GRAN_CHECK(model == mix->model, GRAN_ERR_ARG,
               "mixture 'mix' does not match checkpoint '%s': restitution model %d, checkpoint %d", path, mix->model,
               (int)model);
    /* the particle arrays are allocated from the counts: the counts must match the velocities on
     * disk before anything is allocated (an edited count asks for memory the file cannot fill) */
    int64_t N = 0;
    for (int64_t k = 0; k < M; k++) {
      GRAN_CHECK(counts[(size_t)k] >= 0 && counts[(size_t)k] <= ((int64_t)1 << 40), GRAN_ERR_IO,
                 "checkpoint '%s': count of species %" PRId64 " is %" PRId64, path, k, counts[(size_t)k]);
      N += counts[(size_t)k];
    }
    const bool lowrank = oi[0] == GRAN_SELECTOR_LOWRANK || oi[0] == GRAN_SELECTOR_LOWRANK_PAPER;
    if (o.speed_classes && lowrank && N > 0 && N < INT32_MAX) { /* speed classes: the slots */
      int64_t S = 0;
      for (int64_t k = 0; k < M; k++) S += dsmc_class_slots(counts[(size_t)k], dsmc_class_count(counts[(size_t)k]));
      GRAN_CHECK(rd.npoints("class_v") == 3 * S, GRAN_ERR_IO,
                 "checkpoint '%s': %" PRId64 " slot velocity values for %" PRId64 " slots (damaged or edited file?)", path,
                 rd.npoints("class_v"), S);
    } else {
    GRAN_CHECK(rd.npoints("v") == 3 * N, GRAN_ERR_IO,
               "checkpoint '%s': %" PRId64 " velocity values for %" PRId64 " particles (damaged or edited file?)", path,
               rd.npoints("v"), N);
    }
    if (o.observe & GRAN_OBSERVE_TRAJECTORIES) {
      int64_t ntraj = 0;
      for (int64_t k = 0; k < M; k++) ntraj += std::min(o.traj_per_species, counts[(size_t)k]);
      GRAN_CHECK(ntraj == 0 || (o.traj_samples <= ((int64_t)1 << 40) / ntraj &&
                                rd.npoints("trajectories") == 3 * ntraj * o.traj_samples),
                 GRAN_ERR_IO, "checkpoint '%s': trajectory sizes do not match the stored trajectories", path);
    }
    gran_dsmc *s = new gran_dsmc();
    int ierr = dsmc_alloc(mix, counts.data(), &o, s);
    /* the trees over v^(r) depend on the counts only: the file must hold what dsmc_alloc built */
    std::vector<double> vtree[3];
    if (ierr == GRAN_SUCCESS && s->selector == GRAN_SELECTOR_LOWRANK)
      for (int r = 0; r < 3; r++) vtree[r].assign(s->v[r].node, s->v[r].node + 2 * s->v[r].base);
    if (ierr == GRAN_SUCCESS && rd.has("tracer")) {
      std::vector<int32_t> trc((size_t)M);
      ierr = rd.i32("tracer", M, trc.data());
      for (int64_t k = 0; k < M && ierr == GRAN_SUCCESS; k++)
        if ((trc[(size_t)k] != 0) != (s->tracer[(size_t)k] != 0))
          ierr = GRAN_ERROR(GRAN_ERR_ARG,
                            "mixture 'mix' does not match checkpoint '%s': species " GRAN_I64_FMT
                            " is %s in the checkpoint and %s with this mixture (n_k = %g)",
                            path, k, trc[(size_t)k] ? "a tracer" : "not a tracer",
                            s->tracer[(size_t)k] ? "a tracer" : "not a tracer", mix->n[(size_t)k]);
    }
    if (ierr == GRAN_SUCCESS) ierr = state_io(rd, s);
    if (ierr == GRAN_SUCCESS) ierr = validate_state(s, path);
    if (ierr == GRAN_SUCCESS && o.selector == GRAN_SELECTOR_CELL) { /* cell selector block */
      gran_dsmc_cell_options co;
      ierr = cell_options_read(rd, &co);
      if (ierr == GRAN_SUCCESS && expect_cell) ierr = cell_options_match(co, *expect_cell, group, path);
      if (ierr == GRAN_SUCCESS) ierr = dsmc_cell_setup(s, &co);
      if (ierr == GRAN_SUCCESS) ierr = cell_state_io(rd, s);
      if (ierr == GRAN_SUCCESS && s->cell->agg) ierr = cell_agg_read(rd, s);
      if (ierr == GRAN_SUCCESS) ierr = cell_validate(s, path);
      if (ierr == GRAN_SUCCESS && s->cell->by_cells) { /* streams by cell: the keys (after the positions' check) */
        std::vector<int64_t> key((size_t)s->N);
        ierr = rd.i64("cell_keys", s->N, key.data());
        if (ierr == GRAN_SUCCESS) ierr = dsmc_cell_order_from_keys(s, key.data(), path);
      }
      if (ierr == GRAN_SUCCESS) ierr = dsmc_cell_check_bath(s);
    }
    const bool aggev = o.selector != GRAN_SELECTOR_CELL && rd.has("agg_options_real");
    if (ierr == GRAN_SUCCESS && aggev) ierr = aggev_read(rd, s, expect_agg, group); /* event selectors with aggregation */
    if (ierr == GRAN_SUCCESS && !aggev && o.selector != GRAN_SELECTOR_CELL && expect_agg) { /* stored without */
      gran_dsmc_agg_options none;
      gran_dsmc_agg_options_default(&none);
      ierr = agg_options_match(none, *expect_agg, group, path);
    }
    if (ierr == GRAN_SUCCESS && s->classes) dsmc_class_read_done(s); /* alias tables, identities' slots */
    if (ierr == GRAN_SUCCESS) ierr = counters_validate(s, path);
    if (ierr == GRAN_SUCCESS && s->selector == GRAN_SELECTOR_LOWRANK && !s->classes && !aggev)
      for (int r = 0; r < 3 && ierr == GRAN_SUCCESS; r++)
        if (std::memcmp(vtree[r].data(), s->v[r].node, sizeof(double) * vtree[r].size()) != 0)
          ierr = GRAN_ERROR(GRAN_ERR_IO, "checkpoint '%s': the species trees do not match the counts (damaged file?)",
                            path);
    if (ierr != GRAN_SUCCESS) {
      gran_dsmc_destroy(&s);
      return ierr;
    }
    *sim = s;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief New engine from the state in group `group` of `path`; `mix` must be the mixture the
 *  state was made with (checked: species count, masses, diameters, restitution model). */
GRAN_EXTERN int gran_dsmc_checkpoint_read(const char *path, const char *group, const gran_mixture *mix,
                                          gran_dsmc **sim) {
  GRAN_TRY {
    GRAN_CHECK_PTR(sim);
    *sim = nullptr;
    GRAN_CHECK_PTR(path);
    GRAN_CHECK_PTR(group);
    GRAN_CALL(check_mixture(mix, "mix"));
    gran_state::File f;
    GRAN_CALL(f.open_read(path, "checkpoint"));
    return gran_dsmc_checkpoint_read_h5_(f.id(), group, mix, nullptr, nullptr, nullptr, sim, path);
  }
  GRAN_CATCH
}
