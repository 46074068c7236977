/* dsmc_loop.h - the hot loop of the DSMC engine, a template over the selector and the effects
 * that are on. Included by lowrank.cpp and bird.cpp, which instantiate it for their selector and
 * hand out function pointers; gran_dsmc_advance picks one pointer per call (dispatch outside the
 * loop). An effect whose template flag is off leaves no instruction and touches no memory here.
 *
 * One trial (Bodrova & Osinsky Sec. III, steps 1-5):
 *   take the oldest pre-drawn candidate pair (j, l) of species (i, k) and draw a new one in its
 *   place (prefetching its velocities); reject j == l; accept with w |g| / B (default) or
 *   w |g.e| / B with e uniform (paper variant), where B bounds w |g|; collide (Eq. 41), update
 *   the displacements lazily (Eq. 45), the ledger, the counters and the bounds; draw the time of
 *   the next trial, t += Exp(1) / Lambda (Eq. 38 / 50).
 * With tracers (kTracer: a species with n_k = 0 and particles, Bodrova & Osinsky Sec. II F) a tracer-tracer
 * candidate is rejected before the acceptance test (its rate is 0), and a tracer-gas collision
 * changes only the tracer's velocity (and displacement); the ledger books minus the tracer's
 * kinetic-energy change as dissipated (energy exchanged with the infinite bath), so
 * e_initial - e_dissipated == e_kin still holds. Mixtures without tracers run kTracer = false.
 */
#ifndef GRANARY_DSMC_LOOP_H
#define GRANARY_DSMC_LOOP_H

#include "dsmc_impl.h"

namespace gran {

#ifndef GRAN_DSMC_DISP_TLAST
#define GRAN_DSMC_DISP_TLAST 0
#endif
constexpr bool kDispTlast = GRAN_DSMC_DISP_TLAST != 0;
#ifndef GRAN_DSMC_PREFETCH_R
#define GRAN_DSMC_PREFETCH_R 1
#endif
constexpr bool kPrefetchR = GRAN_DSMC_PREFETCH_R != 0;
/* 1: one 64-bit word per trial gives both the uniform of the trial time (high 32 bits) and the
 * acceptance uniform (low 32 bits) instead of one word each ("fewer draws"; measured in
 * the report of the speed branch: see README, DSMC performance). */
#ifndef GRAN_DSMC_RNG_SPLIT
#define GRAN_DSMC_RNG_SPLIT 0
#endif
constexpr bool kRngSplit = GRAN_DSMC_RNG_SPLIT != 0;
/* 1: the alias tables' column-or-alias choices of the speed-class draw as selects (no branch: the
 * coins are unpredictable): Table I N_1 = 1e5 126 -> 115 ns per collision, 1e6 121 -> 115 (README,
 * DSMC performance). Without classes no gain (one coin per trial, often predictable): not used. */
#ifndef GRAN_DSMC_ALIAS_SELECT
#define GRAN_DSMC_ALIAS_SELECT 1
#endif
constexpr bool kAliasSelect = GRAN_DSMC_ALIAS_SELECT != 0;
/* 1: the low-rank draw of a one-species mixture skips the term, tree and alias choices (their
 * result is species 0 whatever the random words; the same words give j and l: bit for bit the
 * same run); measured in the README's DSMC performance notes. */
#ifndef GRAN_DSMC_ONE_SPECIES
#define GRAN_DSMC_ONE_SPECIES 1
#endif
/* c if take, else a, without a branch the compiler could turn it into */
static inline int64_t select_i64(bool take, int64_t c, int64_t a) {
  const int64_t m = -(int64_t)take;
  return (c & m) | (a & ~m);
}

static inline void prefetch_particle(const double *v, int64_t j) {
  __builtin_prefetch(v + 3 * j);
  __builtin_prefetch(v + 3 * j + 2);
}

/* Descent of a sum tree with target x in [0, total): one compare per level (the core's guarded
 * descent tests the sibling's weight too). Rounding can steer it into a zero-weight leaf (an
 * empty species, a padding leaf); that never-taken case repeats the guarded descent of the core. */
static inline int64_t tree_find(const gran_segtree *t, double x) {
  const double *node = t->node;
  const int64_t base = t->base;
  const double x0 = x;
  int64_t i = 1;
  while (i < base) {
    const double wl = node[2 * i];
    if (x < wl) {
      i = 2 * i;
    } else {
      x -= wl;
      i = 2 * i + 1;
    }
  }
  if (node[i] > 0.0) return i - base;
  return segtree_sample(t, x0 / node[1]);
}

/* Low-rank selector: choose the rank-one term r with probability U_r V_r / sum and species i from
 * the tree of u^(r) with one uniform (the residual of the first choice, scaled to the tree's units
 * by 1/V_r, a constant), species k from v^(r) (constant: its alias table), then j, l uniformly
 * within the species.
 * Uses kNum random words r[0..kNum-1]. */
struct SelLowRank {
  enum { kNum = 4, kClasses = 0 };
  /* Kept out of line on purpose: inlined into the loop, gcc 12 schedules the prefetches so that
   * they no longer run ahead (measured 2.6x slower at N = 1.2e6, b501). */
  __attribute__((noinline)) static void draw(const gran_dsmc *s, const uint64_t *r, DsmcCand *c) {
    if (GRAN_DSMC_ONE_SPECIES && s->M == 1) { /* i = k = 0 whatever r[0], r[1]: the same pair, bit for bit */
      c->i = c->k = 0;
      c->j = u64_below(r[2], s->count[0]);
      c->l = u64_below(r[3], s->count[0]);
      prefetch_particle(s->p.v, c->j);
      prefetch_particle(s->p.v, c->l);
      return;
    }
    const double u0 = s->uv[0], u1 = s->uv[1];
    const double x = u64_uniform(r[0]) * (u0 + u1 + s->uv[2]);
    const int q = (int)(x >= u0) + (int)(x >= u0 + u1);
    const double xr = x - (q == 0 ? 0.0 : q == 1 ? u0 : u0 + u1); /* in [0, U_q V_q) */
    const int64_t i = tree_find(&s->u[q], xr * s->inv_vtot[q]);
    /* v^(r) never changes: O(1) by its alias table; one word gives the column (high part of
     * r M) and the uniform deciding between the column and its alias (low part) */
    const unsigned __int128 km = (unsigned __int128)r[1] * (unsigned __int128)(uint64_t)s->M;
    const int64_t k0 = (int64_t)(km >> 64);
    const int64_t k = (double)(uint64_t)km * 0x1.0p-64 < s->alias_p[q][(size_t)k0] ? k0 : s->alias_k[q][(size_t)k0];
    c->i = (int32_t)i;
    c->k = (int32_t)k;
    c->j = s->offset[(size_t)i] + u64_below(r[2], s->count[(size_t)i]);
    c->l = s->offset[(size_t)k] + u64_below(r[3], s->count[(size_t)k]);
    prefetch_particle(s->p.v, c->j);
    prefetch_particle(s->p.v, c->l);
  }
  static inline void species(const gran_dsmc *, DsmcCand *) {}
  static inline bool occupied(const gran_dsmc *, const DsmcCand &) { return true; }
  /* bound B of w |g| and weight w of the pair */
  static inline double bound(const gran_dsmc *s, const DsmcCand &c, double *w) {
    *w = 1.0;
    return s->bound[(size_t)c.i] + s->bound[(size_t)c.k];
  }
};

/* Low-rank selector over speed classes (dsmc_impl.h): the same draw over the leaves (species,
 * class) with capacities and class bounds, slots uniform within the leaves' capacities; a slot
 * beyond its leaf's filling is rejected at use time (rate 0). */
struct SelClass {
  enum { kNum = 4, kClasses = 1 };
  /* The pipeline holds draws of the part of the law fixed between sorts (the alias table of the
   * pairs (r, a)); the part the raises of top bounds added since (the tree ud) is drawn at use
   * time with probability D / (A + D) (draw_raise): a raise changes the rate, never the pipeline. */
  __attribute__((noinline)) static void draw(const gran_dsmc *s, const uint64_t *r, DsmcCand *c) {
    const int64_t L3 = 3 * s->L;
    const double t = u64_uniform(r[0]) * (double)L3; /* column and coin of the alias table */
    int64_t col = (int64_t)t;
    col = col < L3 ? col : L3 - 1;
    const int64_t qa = kAliasSelect ? select_i64(t - (double)col < s->ua_p[(size_t)col], col, s->ua_k[(size_t)col])
                                    : (t - (double)col < s->ua_p[(size_t)col] ? col : s->ua_k[(size_t)col]);
    finish(s, r, qa, c);
  }
  static void draw_raise(const gran_dsmc *s, const uint64_t *r, DsmcCand *c) {
    finish(s, r, tree_find(&s->ud, u64_uniform(r[0]) * s->ud.node[1]), c);
  }
  static inline void finish(const gran_dsmc *s, const uint64_t *r, int64_t qa, DsmcCand *c) {
    const int64_t L = s->L;
    const int q = (int)(qa >= L) + (int)(qa >= 2 * L);
    const int64_t a = qa - q * L;
    const unsigned __int128 km = (unsigned __int128)r[1] * (unsigned __int128)(uint64_t)s->L;
    const int64_t b0 = (int64_t)(km >> 64);
    const bool keep = (double)(uint64_t)km * 0x1.0p-64 < s->alias_p[q][(size_t)b0];
    const int64_t b = kAliasSelect ? select_i64(keep, b0, s->alias_k[q][(size_t)b0]) : (keep ? b0 : s->alias_k[q][(size_t)b0]);
    const DsmcLeaf *lf = s->leaf.data();
    c->a = (int32_t)a;
    c->b = (int32_t)b;
    c->i = lf[a].species;
    c->k = lf[b].species;
    c->j = lf[a].start + u64_below(r[2], lf[a].cap);
    c->l = lf[b].start + u64_below(r[3], lf[b].cap);
    /* (skipping the prefetch of a slot empty at draw time was measured without gain: docs/performance.md) */
    prefetch_particle(s->cv.data(), c->j);
    prefetch_particle(s->cv.data(), c->l);
  }
  static inline void species(const gran_dsmc *, DsmcCand *) {}
  static inline bool occupied(const gran_dsmc *s, const DsmcCand &c) {
    const DsmcLeaf *lf = s->leaf.data();
    return c.j < lf[c.a].start + lf[c.a].n && c.l < lf[c.b].start + lf[c.b].n;
  }
  static inline double bound(const gran_dsmc *s, const DsmcCand &c, double *w) {
    *w = 1.0;
    return s->leaf[(size_t)c.a].b + s->leaf[(size_t)c.b].b;
  }
};

constexpr bool kClassDown = GRAN_DSMC_CLASS_DOWN != 0;

/* Speed classes: after a collision the particle in slot x of leaf a has speed^2 s2; move it to the
 * lowest class of its species that admits it and has room, if that differs from a (up: it must;
 * down: when there is room). Returns 0 (the law unchanged), 1 (a top bound was raised) or 2 (the
 * species was re-sorted into its classes: every slot of it may have changed). *hole_from: the
 * slot whose particle now fills x (the last of leaf a), or -1. */
template <bool kDisp>
static inline int class_relocate(gran_dsmc *s, double *v, double *R, int64_t x, int64_t a, double s2,
                                 int64_t *hole_from) {
  DsmcLeaf *const lf = s->leaf.data();
  *hole_from = -1;
  const bool up = s2 > lf[a].b2;
  /* down: when it fits the class below (GRAN_DSMC_CLASS_DOWN 1) or two below (2: fewer moves) */
  const double lo2 = GRAN_DSMC_CLASS_DOWN == 2 ? (lf[a].lo2 < 0 ? -1.0 : lf[a - 1].lo2) : lf[a].lo2;
  if (!up && !(kClassDown && s2 < lo2)) return 0;
  const int64_t i = lf[a].species;
  const int64_t f = s->sleaf[(size_t)i], e = s->sleaf[(size_t)i + 1];
  int ret = 0;
  int64_t d;
  if (up) {
    for (d = a + 1; d < e; d++)
      if (s2 <= lf[d].b2 && lf[d].n < lf[d].cap) break;
    if (d == e) {
      if (s2 > lf[e - 1].b2) {
        dsmc_class_raise(s, e - 1, s2);
        ret = 1;
        if (e - 1 == a) return 1; /* the top class itself: it now admits the particle */
        if (lf[e - 1].n < lf[e - 1].cap) d = e - 1;
      }
      if (d == e) {
        dsmc_class_rebuild(s, i);
        return 2;
      }
    }
  } else {
    for (d = f; d < a; d++)
      if (s2 <= lf[d].b2 && lf[d].n < lf[d].cap) break;
    if (d == a) return 0;
  }
  int32_t *const id = s->cid.empty() ? nullptr : s->cid.data(); /* identities: with trajectories only */
  auto move = [&](int64_t from, int64_t to) {
    for (int q = 0; q < 3; q++) v[3 * to + q] = v[3 * from + q];
    if (kDisp)
      for (int q = 0; q < 3; q++) R[3 * to + q] = R[3 * from + q];
    if (id) {
      id[to] = id[from];
      s->cslot[(size_t)id[to]] = (int32_t)to;
    }
  };
  const int64_t y = lf[d].start + lf[d].n++;
  move(x, y);
  const int64_t last = lf[a].start + --lf[a].n;
  if (last != x) {
    move(last, x);
    *hole_from = last;
  }
  s->class_moves++;
  return ret;
}

/* Bird's selector: j, l uniformly among all N particles (ordered), one global bound C_max (Eq. 49). */
struct SelBird {
  enum { kNum = 2, kClasses = 0 };
  __attribute__((noinline)) static void draw(const gran_dsmc *s, const uint64_t *r, DsmcCand *c) {
    c->j = u64_below(r[0], s->N);
    c->l = u64_below(r[1], s->N);
    __builtin_prefetch(s->p.species + c->j);
    __builtin_prefetch(s->p.species + c->l);
    prefetch_particle(s->p.v, c->j);
    prefetch_particle(s->p.v, c->l);
  }
  static inline void species(const gran_dsmc *s, DsmcCand *c) {
    c->i = s->p.species[c->j];
    c->k = s->p.species[c->l];
  }
  static inline bool occupied(const gran_dsmc *, const DsmcCand &) { return true; }
  static inline double bound(const gran_dsmc *s, const DsmcCand &c, double *w) {
    const double sik = 0.5 * (s->mix.sigma[(size_t)c.i] + s->mix.sigma[(size_t)c.k]);
    *w = sik * sik;
    return s->cmax;
  }
};

template <class Sel, bool kPaper, bool kDisp, bool kCount, int kRest, bool kTracer>
void dsmc_loop(gran_dsmc *s, double t_stop, int64_t coll_stop) {
  constexpr int K = kDsmcPipe;
  DsmcRng *const vr = &s->vrng;
  const uint64_t *const buf = vr->buf;
  int pos = vr->pos;
  /* at least n unread random words (refilling discards the rest: deterministic) */
  auto need = [&](int n) {
    if (pos + n > kRngBuf) {
      dsmc_rng_refill(vr);
      pos = 0;
    }
  };
  /* uniform direction on the sphere, two words of the buffer per try */
  auto unit3 = [&](double e[3]) {
    dsmc_unit3(
        [&](double &a, double &b) {
          need(2);
          a = u64_uniform(buf[pos]);
          b = u64_uniform(buf[pos + 1]);
          pos += 2;
        },
        e);
  };
  double *const v = Sel::kClasses ? s->cv.data() : s->p.v;
  double *const R = kDisp ? (Sel::kClasses ? s->cr.data() : s->p.r) : nullptr;
  double *const tl = (kDisp && !Sel::kClasses) ? s->p.t_last : nullptr;
  /* The engine's clock counts from t_start (t, t_ref, pend_t, t_stop): a run that starts at
   * t_start = 1e20 keeps the resolution of one that starts at 0. t_last holds absolute times. */
  const double t0 = s->opt.t_start;
  (void)t0;
  int64_t *const cc = kCount ? s->ccount.data() : nullptr;
  const double *const mass = s->mix.m.data();
  const uint8_t *const trc = kTracer ? s->tracer.data() : nullptr;
  const int64_t M = s->M;
  const DsmcPair *const pair = s->pair.empty() ? nullptr : s->pair.data();
  double inv_rate = s->inv_rate;
  int64_t coll = s->collisions, trials = s->trials;
  double ed = s->e_diss, edc = s->e_diss_c;
  int head = s->cand_head, count = s->cand_count;
  double t_ref = s->t_ref, tprod = s->tprod, tlog = s->tlog;
  bool stop = false;
  /* time of the last trial drawn (one log) */
  auto now = [&]() { return t_ref + (tlog - std::log(tprod)) * inv_rate; };
  /* without displacements, the last trial lies beyond t_stop iff tprod < pthr: a compare instead
   * of a log per collision (with displacements the time of each collision is needed anyway) */
  double pthr = 0;
  auto set_thr = [&]() { pthr = std::exp(tlog - (t_stop - t_ref) * s->rate); };
  set_thr();

  /* The bounds tightened to the exact maxima at time tn (dsmc_refresh_bounds, which also removes the
   * mean flow and books its energy in e_diss: the loop's running sums go there first and come back) */
  auto tighten = [&](double tn) {
    s->collisions = coll;
    s->trials = trials;
    s->e_diss = ed;
    s->e_diss_c = edc;
    if (kDisp) s->t = tn;
    dsmc_refresh_bounds(s);
    ed = s->e_diss;
    edc = s->e_diss_c;
  };
  /* Stale bounds: a species whose speeds fall fast between tightenings (a tracer freezing in a bath
   * at rest loses a large share of its speed at each collision) keeps a bound far above them until
   * the next tightening, refresh_interval collisions later, and the acceptance falls towards 0 in
   * between. So the bounds are also tightened between two trials once at least 64 max(N, 64)
   * trials since the last tightening have accepted fewer than 1 in 64: at most one tightening (O(N))
   * per 64 N trials where the acceptance is that low anyway, none in a gas whose bounds are good.
   * Counted in trials and collisions only: the same sequence after a resume. */
  const int64_t stale_trials = 64 * std::max<int64_t>(s->N, 64);
  auto stale = [&]() {
    const int64_t dt = trials - s->trials_at_refresh;
    return dt >= stale_trials && dt > 64 * (coll - s->coll_at_refresh + 1);
  };

  /* Collide the accepted pair c at time t (Eq. 41); e: the direction drawn before the acceptance
   * (paper rule), unused otherwise. Updates displacements, ledger, counters, bounds. */
  auto collide = [&](const DsmcCand &c, double t, const double *e) __attribute__((always_inline)) {
    double *const vj = v + 3 * c.j;
    double *const vl = v + 3 * c.l;
    const double g[3] = {vj[0] - vl[0], vj[1] - vl[1], vj[2] - vl[2]};
    double gn[3], gn2;
    if (kPaper) {
      const double ge = g[0] * e[0] + g[1] * e[1] + g[2] * e[2];
      gn[0] = ge * e[0];
      gn[1] = ge * e[1];
      gn[2] = ge * e[2];
      gn2 = ge * ge;
    } else {
      /* e from the |g.e|-weighted law: e ~ (g/|g| - u) with u uniform, so that
       * (g.e) e = (g - |g| u) / 2 (the elastic collision scatters g uniformly). */
      const double ga = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      double u[3];
      unit3(u);
      gn[0] = 0.5 * (g[0] - ga * u[0]);
      gn[1] = 0.5 * (g[1] - ga * u[1]);
      gn[2] = 0.5 * (g[2] - ga * u[2]);
      gn2 = gn[0] * gn[0] + gn[1] * gn[1] + gn[2] * gn[2];
    }
    const size_t pik = (size_t)c.i * (size_t)M + (size_t)c.k;
    const double eps = dsmc_pair_eps<kRest>(s, pair, pik, c.i, c.k, gn2);
    if (kDisp && kDispTlast && !Sel::kClasses) { /* Eq. 45 literally: r += v (t - t_last), t_last = t */
      double *const rj = R + 3 * c.j, *const rl = R + 3 * c.l;
      const double dj = (t + t0) - tl[c.j], dl = (t + t0) - tl[c.l]; /* t_last: absolute times */
      for (int d = 0; d < 3; d++) {
        rj[d] += vj[d] * dj;
        rl[d] += vl[d] * dl;
      }
      tl[c.j] = t + t0;
      tl[c.l] = t + t0;
    }
    const double mi = mass[c.i], mk = mass[c.k];
    const double inv = 1.0 / (mi + mk);
    const double a = (1.0 + eps) * inv;
    double aj = a * mk, al = a * mi;
    double ediss = 0.0;
    bool one_sided = false;
    if (kTracer) {
      /* one side is a tracer (tracer-tracer pairs never get here): only it changes, by the same
       * dv as in the two-sided collision; the ledger books minus its kinetic-energy change,
       * computed from dv (no cancellation): dE = m a (a g_n^2 -/+ 2 v.g_n) / 2 */
      if (trc[c.i]) {
        al = 0.0;
        one_sided = true;
        const double vg = vj[0] * gn[0] + vj[1] * gn[1] + vj[2] * gn[2];
        ediss = -0.5 * mi * aj * (aj * gn2 - 2.0 * vg);
      } else if (trc[c.k]) {
        aj = 0.0;
        one_sided = true;
        const double vg = vl[0] * gn[0] + vl[1] * gn[1] + vl[2] * gn[2];
        ediss = -0.5 * mk * al * (al * gn2 + 2.0 * vg);
      }
    }
    vj[0] -= aj * gn[0];
    vj[1] -= aj * gn[1];
    vj[2] -= aj * gn[2];
    vl[0] += al * gn[0];
    vl[1] += al * gn[1];
    vl[2] += al * gn[2];
    if (kDisp && (!kDispTlast || Sel::kClasses)) {
      /* Eq. 45 with the reference time fixed at t_start (t_last stays t_start): R(t) = r + v (t - t_start)
       * holds when r absorbs -dv (t - t_start) at each velocity change dv. One array per particle. */
      double *const rj = R + 3 * c.j, *const rl = R + 3 * c.l;
      const double ts = t, bj = aj * ts, bl = al * ts; /* t: elapsed since t_start */
      rj[0] += bj * gn[0];
      rj[1] += bj * gn[1];
      rj[2] += bj * gn[2];
      rl[0] -= bl * gn[0];
      rl[1] -= bl * gn[1];
      rl[2] -= bl * gn[2];
    }
    if (!kTracer || !one_sided) ediss = 0.5 * (1.0 - eps * eps) * mi * mk * inv * gn2;
    neumaier_add(ed, edc, ediss);
    if (kCount) {
      const int64_t lo = c.i < c.k ? c.i : c.k, hi = c.i < c.k ? c.k : c.i;
      cc[lo * M + hi]++;
    }
    ++coll;
    const double sj = vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2];
    const double sl = vl[0] * vl[0] + vl[1] * vl[1] + vl[2] * vl[2];
    bool changed = false, flush = !Sel::kClasses; /* classes: a raise keeps the pipeline (SelClass) */
    if (Sel::kClasses) {
      int64_t hf;
      const int rj = class_relocate<kDisp>(s, v, R, c.j, c.a, sj, &hf);
      changed = rj != 0;
      flush = rj == 2;
      if (rj != 2 || c.i != c.k) { /* after a re-sort of species i its particles all fit */
        const int64_t l = hf == c.l ? c.j : c.l; /* l (the last of leaf a) filled j's hole */
        const int rl = class_relocate<kDisp>(s, v, R, l, c.b, sl, &hf);
        changed = changed || rl != 0;
        flush = flush || rl == 2;
      }
    } else {
      if (sj > s->bound2[(size_t)c.i]) {
        dsmc_raise_bound(s, c.i, sj);
        changed = true;
      }
      if (sl > s->bound2[(size_t)c.k]) {
        dsmc_raise_bound(s, c.k, sl);
        changed = true;
      }
    }
    if (coll >= s->next_refresh) {
      tighten(t); /* the displacements are corrected to the time of this collision */
      changed = true;
      flush = true;
    }
    if (changed) {
      if (!kDisp) { /* the rate changes now: the trial times restart from this collision */
        t_ref = t_ref + (tlog - std::log(tprod)) * inv_rate;
        tprod = 1.0;
        tlog = 0.0;
      }
      inv_rate = s->inv_rate;
      set_thr();
      if (flush) count = 0; /* the selection law changed: discard the pre-drawn candidates */
    }
  };

  double t_last_coll = -INFINITY;
  if (s->pend_on) { /* accepted before the last stop, at a time beyond it */
    if (s->pend_t > t_stop) return;
    s->pend_on = 0;
    if (kDisp) t_ref = s->pend_t;
    t_last_coll = s->pend_t;
    collide(s->pend_c, s->pend_t, s->pend_e);
    stop = coll >= coll_stop;
  }
  if (std::isinf(inv_rate)) stop = true; /* all bounds 0: no collision can ever happen */

  /* Trial times: the spacings are iid Exp(1)/Lambda, independent of the acceptances, so the time
   * of a trial is t_ref + (sum of the spacings since t_ref) / Lambda, and that sum is -log of the
   * product of one uniform per trial (folded into tlog before it underflows). With displacements
   * t_ref moves to each collision (one log per collision: Eq. 45 needs its time); without, it
   * moves only when Lambda changes (a raise or a tightening of the bounds), and whether a
   * collision lies beyond t_stop is a compare of tprod with a threshold: no log at all.
   * Every 64 trials, between two trials, the time reached is compared with t_stop, so a stop is
   * found without an acceptance; the rejected trials beyond it simply count in the next interval
   * (the sequence of trials does not depend on where the run is cut). */
  while (!stop) {
    if ((trials & 63) == 0) {
      if (kDisp ? now() > t_stop : tprod < pthr) break;
      if (stale()) { /* between two trials: the trial times restart here (the Poisson clock has no memory) */
        const double tn = now();
        tighten(tn);
        t_ref = tn;
        tprod = 1.0;
        tlog = 0.0;
        inv_rate = s->inv_rate;
        set_thr();
        count = 0;
        if (std::isinf(inv_rate)) break; /* all bounds 0: no collision can ever happen */
      }
    }
    ++trials;
    if (count == 0) {
      for (int q = 0; q < K; q++) {
        need(Sel::kNum);
        Sel::draw(s, buf + pos, &s->cand[q]);
        pos += Sel::kNum;
        if (kDisp && kPrefetchR) {
          prefetch_particle(R, s->cand[q].j);
          prefetch_particle(R, s->cand[q].l);
        }
      }
      head = 0;
      count = K;
    }
    DsmcCand c;
    bool fresh = false; /* speed classes: the part of the law added by raises, drawn now */
    if constexpr (Sel::kClasses) {
      const double D = s->ud.node[1];
      if (D > 0) {
        need(2 * Sel::kNum + 3);
        fresh = u64_uniform(buf[pos++]) * (s->ua_tot + D) >= s->ua_tot;
        if (fresh) {
          Sel::draw_raise(s, buf + pos, &c);
          pos += Sel::kNum;
        }
      }
    }
    if (!fresh) {
      c = s->cand[head];
      need(Sel::kNum + 2);
      Sel::draw(s, buf + pos, &s->cand[head]);
      pos += Sel::kNum;
      if (kDisp && kPrefetchR) { /* speculative: only accepted candidates need r */
        prefetch_particle(R, s->cand[head].j);
        prefetch_particle(R, s->cand[head].l);
      }
      head = (head + 1) & (K - 1);
    }
    const uint64_t wsplit = kRngSplit ? buf[pos] : 0;
    tprod *= kRngSplit ? ((double)(wsplit >> 32) + 1.0) * 0x1.0p-32 : u64_uniform_pos(buf[pos]);
    pos++;
    if (tprod < 1e-280) {
      tlog -= std::log(tprod);
      tprod = 1.0;
      set_thr();
    }
    if (c.j == c.l) continue; /* the same particle twice: no pair */
    if (!Sel::occupied(s, c)) continue; /* speed classes: an empty slot (rate 0) */
    Sel::species(s, &c);
    if (kTracer && (trc[c.i] & trc[c.k])) continue; /* tracer-tracer: rate 0 (Sec. II F) */
    double w;
    const double B = Sel::bound(s, c, &w);
    if (kRest != kRestConst && pair) w *= pair[(size_t)c.i * (size_t)M + (size_t)c.k].g2r;
    const double *const vj = v + 3 * c.j;
    const double *const vl = v + 3 * c.l;
    const double g[3] = {vj[0] - vl[0], vj[1] - vl[1], vj[2] - vl[2]};
    const double ub = (kRngSplit ? (double)(wsplit & 0xffffffffu) * 0x1.0p-32 : u64_uniform(buf[pos++])) * B;
    double e[3];
    if (kPaper) {
      unit3(e);
      const double ge = g[0] * e[0] + g[1] * e[1] + g[2] * e[2];
      if (!(ub < w * std::fabs(ge))) continue;
    } else {
      const double g2 = g[0] * g[0] + g[1] * g[1] + g[2] * g[2];
      if (!(ub * ub < w * w * g2)) continue;
    }
    const double tc = kDisp ? now() : 0.0;
    if (kDisp ? tc > t_stop : tprod < pthr) { /* the collision belongs to a later interval */
      s->pend_on = 1;
      s->pend_c = c;
      s->pend_t = kDisp ? tc : now();
      for (int d = 0; d < 3; d++) s->pend_e[d] = kPaper ? e[d] : 0.0;
      if (kDisp) {
        tprod = 1.0;
        tlog = 0.0;
        t_ref = s->pend_t;
      }
      break;
    }
    if (kDisp) {
      t_ref = tc;
      tprod = 1.0;
      tlog = 0.0;
    }
    collide(c, tc, e);
    if (coll >= coll_stop) {
      t_last_coll = kDisp ? tc : now();
      break;
    }
  }
  vr->pos = pos;
  if (t_last_coll > s->t) s->t = t_last_coll;
  s->t_ref = t_ref;
  s->tprod = tprod;
  s->tlog = tlog;
  s->collisions = coll;
  s->trials = trials;
  s->e_diss = ed;
  s->e_diss_c = edc;
  s->cand_head = head;
  s->cand_count = count;
}

/* Function pointer for the runtime flags (dispatch once per advance). */
template <class Sel, bool kPaper, bool kDisp, bool kCount, bool kTracer>
static DsmcLoopFn dsmc_pick_rest(int rest) {
  switch (rest) {
    case kRestTable: return &dsmc_loop<Sel, kPaper, kDisp, kCount, kRestTable, kTracer>;
    case kRestVisco: return &dsmc_loop<Sel, kPaper, kDisp, kCount, kRestVisco, kTracer>;
    default: return &dsmc_loop<Sel, kPaper, kDisp, kCount, kRestConst, kTracer>;
  }
}
template <class Sel, bool kPaper, bool kTracer>
static DsmcLoopFn dsmc_pick_eff(int disp, int counts, int rest) {
  if (disp)
    return counts ? dsmc_pick_rest<Sel, kPaper, true, true, kTracer>(rest)
                  : dsmc_pick_rest<Sel, kPaper, true, false, kTracer>(rest);
  return counts ? dsmc_pick_rest<Sel, kPaper, false, true, kTracer>(rest)
                : dsmc_pick_rest<Sel, kPaper, false, false, kTracer>(rest);
}
template <class Sel, bool kPaper>
static DsmcLoopFn dsmc_pick(int disp, int counts, int rest, int tracers) {
  return tracers ? dsmc_pick_eff<Sel, kPaper, true>(disp, counts, rest)
                 : dsmc_pick_eff<Sel, kPaper, false>(disp, counts, rest);
}

}  // namespace gran

#endif
