/* classes.cpp - speed classes of the low-rank selector (dsmc_impl.h explains the
 * layout): setup, the sort of a species into its classes at each tightening of the bounds, the
 * trees over the leaves (species, class), raises and overflow rebuilds, the identity-ordered view
 * of gran_dsmc_particles, and the hot loop's instantiations. */
#include "dsmc_loop.h"

#include <algorithm>
#include <cmath>

namespace gran {

/** @brief Hot loop of the low-rank selector over speed classes for the given effects. */
DsmcLoopFn dsmc_class_loop(int paper, int disp, int counts, int rest, int tracers) {
  return paper ? dsmc_pick<SelClass, true>(disp, counts, rest, tracers)
               : dsmc_pick<SelClass, false>(disp, counts, rest, tracers);
}

/* GRAN_SPEED_CLASSES_AUTO (the default): speed classes where they were measured to pay (b501, README
 * "Speed classes"). Classes cut the trials per collision (acceptance 0.17 -> 0.5) and add work per
 * collision (0.85 moves between classes, the sort at each tightening, the (term, leaf) draw). With
 * one species a trial without classes is the cheapest there is (no tree, no alias choice of the
 * species): classes lost (monodisperse N = 1e5: 140 against 115 ns per collision); from two
 * species on they won (two species 1.15-1.25x, 8 species 1.5x, Table I 1.25-1.45x, 1e4 species
 * 1.9x). With trajectories every move also updates the identity's slot (a cache miss): Table I at
 * N_1 = 1e6 250 against 198 ns, so off. Off for the paper's rule (the literal reference of the
 * speed ratios), Bird and the cell selector (no classes), and without a species of kClassMin
 * particles (no species would have classes). */
int dsmc_classes_auto(const gran_dsmc *s) {
  if (s->selector != GRAN_SELECTOR_LOWRANK || s->paper) return 0;
  if (s->N <= 0 || s->N >= INT32_MAX) return 0;
  if (s->opt.observe & GRAN_OBSERVE_TRAJECTORIES) return 0;
  int64_t big = 0, nonempty = 0;
  for (int64_t k = 0; k < s->M; k++) {
    big += s->count[(size_t)k] >= kClassMin;
    nonempty += s->count[(size_t)k] > 0;
  }
  if (big == 0) return 0;
  return nonempty >= GRAN_DSMC_CLASS_AUTO_M ? 1 : 0;
}

/* Leaves and slots for the counts; every species' particles in its first leaf (sorted into the
 * classes by the first dsmc_refresh_bounds). Velocities are written by the caller. */
int dsmc_class_setup(gran_dsmc *s) {
  const int64_t M = s->M;
  s->classes = 1;
  s->sleaf.assign((size_t)M + 1, 0);
  s->sslot.assign((size_t)M + 1, 0);
  for (int64_t k = 0; k < M; k++) {
    const int C = dsmc_class_count(s->count[(size_t)k]);
    s->sleaf[(size_t)k + 1] = s->sleaf[(size_t)k] + C;
    s->sslot[(size_t)k + 1] = s->sslot[(size_t)k] + dsmc_class_slots(s->count[(size_t)k], C);
  }
  s->L = s->sleaf[(size_t)M];
  s->S = s->sslot[(size_t)M];
  GRAN_CHECK(s->S <= INT32_MAX && s->L <= INT32_MAX, GRAN_ERR_ARG,
             "option 'speed_classes': " GRAN_I64_FMT " slots exceed the 2^31 identities of the class layout", s->S);
  s->leaf.assign((size_t)s->L, DsmcLeaf{});
  for (int64_t k = 0; k < M; k++) {
    const int64_t f = s->sleaf[(size_t)k], e = s->sleaf[(size_t)k + 1];
    const int64_t r0 = s->sslot[(size_t)k], r1 = s->sslot[(size_t)k + 1];
    for (int64_t a = f; a < e; a++) {
      DsmcLeaf &x = s->leaf[(size_t)a];
      x.species = (int32_t)k;
      x.top = a == e - 1;
      x.start = a == f ? r0 : r1;
      x.cap = a == f ? r1 - r0 : 0;
      x.n = a == f ? s->count[(size_t)k] : 0;
      x.lo2 = -1;
    }
  }
  s->cv.assign((size_t)(3 * s->S), 0.0);
  int64_t nmax = 0;
  for (int64_t k = 0; k < M; k++) nmax = std::max(nmax, s->count[(size_t)k]);
  s->ckey.assign((size_t)nmax, 0);
  s->cwref.assign((size_t)M, 0.0);
  if (s->opt.observe & (GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_TRAJECTORIES)) s->cr.assign((size_t)(3 * s->S), 0.0);
  if (s->opt.observe & GRAN_OBSERVE_TRAJECTORIES) {
    s->cid.assign((size_t)s->S, 0);
    for (int64_t k = 0; k < M; k++)
      for (int64_t q = 0; q < s->count[(size_t)k]; q++)
        s->cid[(size_t)(s->sslot[(size_t)k] + q)] = (int32_t)(s->offset[(size_t)k] + q);
    s->cslot.assign((size_t)s->N, 0);
    for (int64_t k = 0; k < M; k++)
      for (int64_t q = 0; q < s->count[(size_t)k]; q++)
        s->cslot[(size_t)(s->offset[(size_t)k] + q)] = (int32_t)(s->sslot[(size_t)k] + q);
  }
  for (int r = 0; r < 3; r++) {
    GRAN_CALL(gran_segtree_init(&s->u[r], s->L, nullptr));
    GRAN_CALL(gran_segtree_init(&s->v[r], s->L, nullptr));
  }
  GRAN_CALL(gran_segtree_init(&s->ud, 3 * s->L, nullptr));
  s->ub.assign((size_t)s->L, 0.0);
  return GRAN_SUCCESS;
}

namespace {

/* one slot's record (velocity, displacement, identity) */
struct Rec {
  double *v, *r;
  int32_t *id;
  void swap(int64_t x, int64_t y) const {
    for (int q = 0; q < 3; q++) std::swap(v[3 * x + q], v[3 * y + q]);
    if (r)
      for (int q = 0; q < 3; q++) std::swap(r[3 * x + q], r[3 * y + q]);
    if (id) std::swap(id[x], id[y]);
  }
  /* n records from slot `from` to slot `to` (overlapping allowed) */
  void move(int64_t from, int64_t to, int64_t n) const {
    if (n <= 0 || from == to) return;
    std::memmove(v + 3 * to, v + 3 * from, sizeof(double) * 3 * (size_t)n);
    if (r) std::memmove(r + 3 * to, r + 3 * from, sizeof(double) * 3 * (size_t)n);
    if (id) std::memmove(id + to, id + from, sizeof(int32_t) * (size_t)n);
  }
};

}  // namespace

/* Sort species k into its classes: thresholds from its rms speed w (rounded to w_ref rho^m with
 * GRAN_DSMC_CLASS_ANCHOR, w_ref its rms speed at the first sort), the top bound = bound[k] (the
 * species' largest speed, set by the caller), capacities from the new occupations. In place: the
 * filled blocks are packed, sorted by class (American flag sort), and spread to their slots. */
void dsmc_class_layout(gran_dsmc *s, int64_t k) {
  const int64_t f = s->sleaf[(size_t)k], C = s->sleaf[(size_t)k + 1] - f;
  DsmcLeaf *const lf = s->leaf.data() + f;
  const int64_t r0 = s->sslot[(size_t)k], Sk = s->sslot[(size_t)k + 1] - r0, Nk = s->count[(size_t)k];
  const double vmax = s->bound[(size_t)k], vmax2 = s->bound2[(size_t)k];
  if (C == 1) {
    lf[0].start = r0;
    lf[0].cap = Nk;
    lf[0].n = Nk;
    lf[0].b = vmax;
    lf[0].b2 = vmax2;
    lf[0].lo2 = -1;
    return;
  }
  const Rec rec{s->cv.data(), s->cr.empty() ? nullptr : s->cr.data(), s->cid.empty() ? nullptr : s->cid.data()};
  const double *v = s->cv.data();
  uint8_t *const key = s->ckey.data();
  int64_t p = r0, old_end[kClassNum];
  for (int64_t c = 0; c < C; c++) { /* pack (destinations never lie above the sources) */
    rec.move(lf[c].start, p, lf[c].n);
    p += lf[c].n;
    old_end[c] = p;
  }
  double sum = 0;
  for (int64_t x = r0; x < r0 + Nk; x++) sum += v[3 * x] * v[3 * x] + v[3 * x + 1] * v[3 * x + 1] + v[3 * x + 2] * v[3 * x + 2];
  double w = std::sqrt(sum / (double)Nk);
#if GRAN_DSMC_CLASS_ANCHOR
  { /* thresholds on a fixed geometric grid: w rounded to w_ref rho^m */
    double &wr = s->cwref[(size_t)k];
    if (!(wr > 0) && w > 0) wr = w;
    if (wr > 0 && w > 0) w = wr * std::pow(GRAN_DSMC_CLASS_RHO, std::nearbyint(std::log(w / wr) / std::log(GRAN_DSMC_CLASS_RHO)));
  }
#endif
  double b[kClassNum], b2[kClassNum];
  for (int64_t c = 0; c < C; c++) {
    const double th = c < C - 1 ? w * GRAN_DSMC_CLASS_A0 * std::pow(GRAN_DSMC_CLASS_RHO, (double)c) : vmax;
    b[c] = th < vmax ? th : vmax;
    b2[c] = c < C - 1 ? b[c] * b[c] : vmax2;
    if (b2[c] > vmax2) b2[c] = vmax2;
  }
  /* new class of each particle: the first class with b2 >= speed^2, else the top; searched from
   * its old class (most particles stay) */
  int64_t n[kClassNum] = {0}, next[kClassNum], end[kClassNum];
#if GRAN_DSMC_CLASS_KEY_COUNT
  { /* the class: the number of thresholds below the speed^2 (b2 is non-decreasing), counted over a
     * fixed length without branches (the search from the old class mispredicted: 30% of the sort) */
    (void)old_end;
    double th[kClassNum];
    for (int64_t c = 0; c < kClassNum; c++) th[c] = c < C - 1 ? b2[c] : INFINITY;
    for (int64_t x = r0; x < r0 + Nk; x++) {
      const double q = v[3 * x] * v[3 * x] + v[3 * x + 1] * v[3 * x + 1] + v[3 * x + 2] * v[3 * x + 2];
      int h = 0;
      for (int c = 0; c < kClassNum - 1; c++) h += q > th[c];
      key[x - r0] = (uint8_t)h;
      n[h]++;
    }
  }
#else
  {
    int64_t c = 0;
    for (int64_t x = r0; x < r0 + Nk; x++) {
      while (x >= old_end[c]) c++;
      const double q = v[3 * x] * v[3 * x] + v[3 * x + 1] * v[3 * x + 1] + v[3 * x + 2] * v[3 * x + 2];
      int64_t h = c;
      while (h < C - 1 && q > b2[h]) h++;
      while (h > 0 && q <= b2[h - 1]) h--;
      key[x - r0] = (uint8_t)h;
      n[h]++;
    }
  }
#endif
  int64_t q0 = r0;
  for (int64_t c = 0; c < C; c++) {
    next[c] = q0;
    q0 += n[c];
    end[c] = q0;
  }
  for (int64_t c = 0; c < C; c++) /* American flag sort by the keys */
    while (next[c] < end[c]) {
      const int64_t x = next[c], kc = key[x - r0];
      if (kc == c) {
        next[c]++;
      } else {
        const int64_t y = next[kc]++;
        rec.swap(x, y);
        std::swap(key[x - r0], key[y - r0]);
      }
    }
  /* capacities: kClassExtra each, the rest of the free slots in proportion to the occupation */
  const int64_t rem = Sk - Nk - C * kClassExtra;
  int64_t cap[kClassNum], used = 0;
  for (int64_t c = 0; c < C; c++) {
    cap[c] = n[c] + kClassExtra + (Nk > 0 ? (int64_t)((double)rem * (double)n[c] / (double)Nk) : 0);
    used += cap[c];
  }
  cap[C - 1] += Sk - used;
  /* spread from the top: each block moves up to its final start */
  int64_t fs[kClassNum];
  {
    int64_t a = r0;
    for (int64_t c = 0; c < C; c++) {
      fs[c] = a;
      a += cap[c];
    }
  }
  for (int64_t c = C - 1; c >= 0; c--) rec.move(end[c] - n[c], fs[c], n[c]);
  for (int64_t c = 0; c < C; c++) {
    lf[c].start = fs[c];
    lf[c].cap = cap[c];
    lf[c].n = n[c];
    lf[c].b = b[c];
    lf[c].b2 = b2[c];
    lf[c].lo2 = c > 0 ? b2[c - 1] : -1.0;
  }
  if (!s->cslot.empty())
    for (int64_t c = 0; c < C; c++)
      for (int64_t x = fs[c]; x < fs[c] + n[c]; x++) s->cslot[(size_t)s->cid[(size_t)x]] = (int32_t)x;
}

/* The weights of the leaves from the capacities and class bounds: u^(r) (trees), v^(r) (trees and
 * alias tables), U_r V_r, the rate. */
void dsmc_class_alias(gran_dsmc *s);
void dsmc_class_trees(gran_dsmc *s) {
  const int64_t L = s->L;
  std::vector<double> w[3];
  for (int r = 0; r < 3; r++) w[r].resize((size_t)L);
  for (int64_t a = 0; a < L; a++) {
    const DsmcLeaf &x = s->leaf[(size_t)a];
    const double sg = s->mix.sigma[(size_t)x.species], cap = (double)x.cap, bn = x.b * cap;
    s->u[0].node[s->u[0].base + a] = bn * sg * sg;
    s->u[1].node[s->u[1].base + a] = 2.0 * bn * sg;
    s->u[2].node[s->u[2].base + a] = bn;
    w[0][(size_t)a] = cap;
    w[1][(size_t)a] = cap * sg;
    w[2][(size_t)a] = cap * sg * sg;
  }
  for (int r = 0; r < 3; r++) {
    for (int64_t a = 0; a < L; a++) s->v[r].node[s->v[r].base + a] = w[r][(size_t)a];
    gran_segtree_rebuild(&s->u[r]);
    gran_segtree_rebuild(&s->v[r]);
    s->inv_vtot[r] = s->v[r].node[1] > 0 ? 1.0 / s->v[r].node[1] : 0.0;
    dsmc_build_alias(w[r], &s->alias_p[r], &s->alias_k[r]);
    s->uv[r] = s->u[r].node[1] * s->v[r].node[1];
  }
  for (int64_t a = 0; a < L; a++) s->ub[(size_t)a] = s->leaf[(size_t)a].b;
  dsmc_class_alias(s);
  for (int64_t x = 0; x < 2 * s->ud.base; x++) s->ud.node[x] = 0.0;
}

/* Weight of the pair (r, a) in the draw for class bound b: u^(r)_a(b) V_r. */
static double pair_weight(const gran_dsmc *s, int r, int64_t a, double b) {
  const DsmcLeaf &x = s->leaf[(size_t)a];
  const double sg = s->mix.sigma[(size_t)x.species], bn = b * (double)x.cap;
  const double u = r == 0 ? bn * sg * sg : r == 1 ? 2.0 * bn * sg : bn;
  return u * s->v[r].node[1];
}

/* The alias table over the pairs (r, a) from the bounds ub (after a sort, and on reading a checkpoint). */
void dsmc_class_alias(gran_dsmc *s) {
  const int64_t L = s->L;
  std::vector<double> w((size_t)(3 * L));
  double tot = 0;
  for (int r = 0; r < 3; r++)
    for (int64_t a = 0; a < L; a++) {
      w[(size_t)(r * L + a)] = pair_weight(s, r, a, s->ub[(size_t)a]);
      tot += w[(size_t)(r * L + a)];
    }
  dsmc_build_alias(w, &s->ua_p, &s->ua_k);
  s->ua_tot = tot;
  s->ua_scale = tot > 0 ? (double)(3 * L) / tot : 0.0;
}

void dsmc_class_raise(gran_dsmc *s, int64_t a, double s2) {
  DsmcLeaf &x = s->leaf[(size_t)a];
  const double b = std::sqrt(s2);
  x.b = b;
  x.b2 = s2;
  const int64_t i = x.species;
  if (s2 > s->bound2[(size_t)i]) {
    s->bound2[(size_t)i] = s2;
    s->bound[(size_t)i] = b;
  }
  s->bound_raises++;
  const double bn = b * (double)x.cap, sg = s->mix.sigma[(size_t)i];
  segtree_set(&s->u[0], a, bn * sg * sg);
  segtree_set(&s->u[1], a, 2.0 * bn * sg);
  segtree_set(&s->u[2], a, bn);
  for (int r = 0; r < 3; r++) {
    s->uv[r] = s->u[r].node[1] * s->v[r].node[1];
    segtree_set(&s->ud, r * s->L + a, pair_weight(s, r, a, b) - pair_weight(s, r, a, s->ub[(size_t)a]));
  }
  dsmc_update_rate(s);
}

void dsmc_class_rebuild(gran_dsmc *s, int64_t i) {
  const double *v = s->cv.data();
  double m2 = 0;
  dsmc_species_ranges(s, i, [&](int64_t a, int64_t b) {
    for (int64_t j = a; j < b; j++) {
      const double q = v[3 * j] * v[3 * j] + v[3 * j + 1] * v[3 * j + 1] + v[3 * j + 2] * v[3 * j + 2];
      m2 = q > m2 ? q : m2;
    }
  });
  s->bound2[(size_t)i] = m2;
  s->bound[(size_t)i] = std::sqrt(m2);
  dsmc_class_layout(s, i);
  dsmc_class_trees(s);
  dsmc_update_rate(s);
  s->class_rebuilds++;
}

/* After a checkpoint's state is read and validated: what is derived from it (the alias tables of
 * v^(r) and of the pairs (r, a), 1/V_r, the slots of the identities). */
void dsmc_class_read_done(gran_dsmc *s) {
  for (int r = 0; r < 3; r++) {
    std::vector<double> w(s->v[r].node + s->v[r].base, s->v[r].node + s->v[r].base + s->L);
    dsmc_build_alias(w, &s->alias_p[r], &s->alias_k[r]);
    s->inv_vtot[r] = s->v[r].node[1] > 0 ? 1.0 / s->v[r].node[1] : 0.0;
  }
  dsmc_class_alias(s);
  if (!s->cslot.empty())
    for (int64_t k = 0; k < s->M; k++)
      dsmc_species_ranges(s, k, [&](int64_t a, int64_t b) {
        for (int64_t x = a; x < b; x++) s->cslot[(size_t)s->cid[(size_t)x]] = (int32_t)x;
      });
}

/* The view of gran_dsmc_particles, filled now: by identity with trajectories (the order of
 * creation), else each species' particles in slot order (species-grouped as offsets says). */
int dsmc_class_view(gran_dsmc *s) {
  const int64_t N = s->N;
  const bool disp = !s->cr.empty();
  if (s->p.capacity < N || (disp && !s->p.r) || !s->p.v) {
    gran_particles_free(&s->p);
    GRAN_CALL(gran_particles_init(&s->p, N, disp ? GRAN_PARTICLES_DISPLACEMENT : 0));
  }
  s->p.n = N;
  const double *v = s->cv.data(), *r = disp ? s->cr.data() : nullptr;
  for (int64_t k = 0; k < s->M; k++) {
    int64_t jn = s->offset[(size_t)k];
    dsmc_species_ranges(s, k, [&](int64_t a, int64_t b) {
      for (int64_t x = a; x < b; x++) {
        const int64_t j = s->cid.empty() ? jn++ : s->cid[(size_t)x];
        for (int d = 0; d < 3; d++) s->p.v[3 * j + d] = v[3 * x + d];
        s->p.species[j] = (int32_t)k;
        if (r) {
          for (int d = 0; d < 3; d++) s->p.r[3 * j + d] = r[3 * x + d];
          s->p.t_last[j] = s->opt.t_start;
        }
      }
    });
  }
  return GRAN_SUCCESS;
}

}  // namespace gran
