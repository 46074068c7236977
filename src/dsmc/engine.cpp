/* engine.cpp - DSMC engine of the homogeneous cooling state (Bodrova & Osinsky Sec. III): creation, the
 * speed bounds and selector state (trees / C_max), the advance driver. The hot loop is in
 * dsmc_loop.h; observables in observables.cpp; checkpoints in checkpoint.cpp. */
#include "dsmc_impl.h"
#include "cell_impl.h"
#include "agg_impl.h"
#include "core/derived.h" /* the rule for derived values: finite and within range */

#include <algorithm>
#include <cfloat>
#include <cmath>

namespace gran {

namespace {

const int kObserveAll = GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS | GRAN_OBSERVE_TRAJECTORIES;
/* Pair tables of at most this many entries are cached even where a formula would do (16 B each). */
const int64_t kPairTableAuto = INT64_C(1) << 18;
/* Collision counters: at most this many (8 B each). */
const int64_t kMaxCounters = INT64_C(1) << 27;
const int64_t kMaxParticles = INT64_C(1) << 40;

int check_options(const gran_dsmc_options *opt) {
  GRAN_CHECK_PTR(opt);
  GRAN_CHECK(opt->selector >= GRAN_SELECTOR_LOWRANK && opt->selector <= GRAN_SELECTOR_CELL, GRAN_ERR_ARG,
             "option 'selector' = %d is not a gran_selector", (int)opt->selector);
  GRAN_CHECK((opt->observe & ~kObserveAll) == 0, GRAN_ERR_ARG, "option 'observe' = %d has unknown bits",
             (int)opt->observe);
  GRAN_CHECK(std::isfinite(opt->volume), GRAN_ERR_ARG, "option 'volume' is not finite (%g)", opt->volume);
  GRAN_CHECK(std::isfinite(opt->t_start), GRAN_ERR_ARG, "option 't_start' is not finite (%g)", opt->t_start);
  GRAN_CHECK(opt->bound_refresh >= 0, GRAN_ERR_ARG, "option 'bound_refresh' is negative (" GRAN_I64_FMT ")",
             opt->bound_refresh);
  GRAN_CHECK(opt->traj_per_species >= 0, GRAN_ERR_ARG, "option 'traj_per_species' is negative (" GRAN_I64_FMT ")",
             opt->traj_per_species);
  GRAN_CHECK(opt->traj_samples >= 0, GRAN_ERR_ARG, "option 'traj_samples' is negative (" GRAN_I64_FMT ")",
             opt->traj_samples);
  GRAN_CHECK(opt->speed_classes == GRAN_SPEED_CLASSES_OFF || opt->speed_classes == GRAN_SPEED_CLASSES_ON ||
                 opt->speed_classes == GRAN_SPEED_CLASSES_AUTO,
             GRAN_ERR_ARG, "option 'speed_classes' = %d must be 0 (off), 1 (on) or -1 (GRAN_SPEED_CLASSES_AUTO)",
             (int)opt->speed_classes);
  GRAN_CHECK(opt->speed_classes != GRAN_SPEED_CLASSES_ON || opt->selector == GRAN_SELECTOR_LOWRANK ||
                 opt->selector == GRAN_SELECTOR_LOWRANK_PAPER,
             GRAN_ERR_ARG, "option 'speed_classes' = 1 needs a low-rank selector (selector = %d has no speed classes)",
             (int)opt->selector);
  if (opt->observe & GRAN_OBSERVE_TRAJECTORIES) {
    GRAN_CHECK(std::isfinite(opt->traj_dt) && opt->traj_dt > 0, GRAN_ERR_ARG,
               "option 'traj_dt' = %g must be finite and > 0 with GRAN_OBSERVE_TRAJECTORIES", opt->traj_dt);
    GRAN_CHECK(opt->traj_samples >= 1, GRAN_ERR_ARG,
               "option 'traj_samples' must be >= 1 with GRAN_OBSERVE_TRAJECTORIES");
    GRAN_CHECK(opt->traj_per_species >= 1, GRAN_ERR_ARG,
               "option 'traj_per_species' must be >= 1 with GRAN_OBSERVE_TRAJECTORIES");
  }
  return GRAN_SUCCESS;
}

}  // namespace

/* Walker's alias table (Vose's construction) for weights w >= 0 with a positive sum: column c is
 * taken with probability p[c], else its alias a[c]. A zero weight gets p = 0 and a positive alias,
 * so it is never returned. */
void dsmc_build_alias(const std::vector<double> &w, std::vector<double> *p, std::vector<int32_t> *a) {
  const size_t m = w.size();
  p->assign(m, 0.0);
  a->assign(m, 0);
  double tot = 0;
  int32_t any = -1;
  for (size_t c = 0; c < m; c++) {
    tot += w[c];
    if (w[c] > 0 && any < 0) any = (int32_t)c;
  }
  if (!(tot > 0)) return;
  std::vector<double> q(m);
  std::vector<int32_t> small, large;
  for (size_t c = 0; c < m; c++) {
    q[c] = w[c] * (double)m / tot;
    (q[c] < 1.0 ? small : large).push_back((int32_t)c);
  }
  while (!small.empty() && !large.empty()) {
    const int32_t sm = small.back(), lg = large.back();
    small.pop_back();
    (*p)[(size_t)sm] = q[(size_t)sm];
    (*a)[(size_t)sm] = lg;
    q[(size_t)lg] -= 1.0 - q[(size_t)sm];
    if (q[(size_t)lg] < 1.0) {
      large.pop_back();
      small.push_back(lg);
    }
  }
  for (int32_t c : large) {
    (*p)[(size_t)c] = 1.0;
    (*a)[(size_t)c] = c;
  }
  for (int32_t c : small) { /* rounding leftovers: keep them only if they have weight */
    (*p)[(size_t)c] = w[(size_t)c] > 0 ? 1.0 : 0.0;
    (*a)[(size_t)c] = w[(size_t)c] > 0 ? c : any;
  }
  for (size_t c = 0; c < m; c++)
    if ((*p)[c] < 1.0 && w[(size_t)(*a)[c]] <= 0) (*a)[c] = any;
}

namespace {

/* Decide how the hot loop finds eps (and g2) of a pair; fill the pair table where one is used. */
void setup_pairs(gran_dsmc *s) {
  const gran_mixture *x = &s->mix;
  const int64_t M = s->M;
  const bool g2_uniform = x->g2_mat.empty();
  double g2max = x->g2;
  if (!g2_uniform) {
    g2max = 0;
    for (double g : x->g2_mat) g2max = g > g2max ? g : g2max;
  }
  s->g2max = g2max;
  bool table = false;
  if (x->model == GRAN_RESTITUTION_CONSTANT && g2_uniform) {
    s->rest = kRestConst;
    s->eps0 = x->eps;
  } else if (x->model == GRAN_RESTITUTION_VISCOELASTIC) {
    s->rest = kRestVisco;
    table = M * M <= kPairTableAuto || !x->beta_mat.empty() || !g2_uniform;
    if (!table && x->visco == GRAN_VISCO_CONSTANT) s->visco_sqrt_beta0 = std::sqrt(x->beta);
  } else {
    s->rest = kRestTable; /* matrix model, or constant eps with a g2 matrix: the mixture holds M*M */
    table = true;
  }
  if (!table) return;
  s->pair.resize((size_t)(M * M));
  for (int64_t i = 0; i < M; i++)
    for (int64_t k = 0; k < M; k++) {
      DsmcPair &q = s->pair[(size_t)(i * M + k)];
      q.a = s->rest == kRestVisco ? std::sqrt(mix_beta(x, i, k)) : mix_eps(x, i, k);
      q.g2r = g2max > 0 ? mix_g2(x, i, k) / g2max : 0.0;
    }
}

}  // namespace

int dsmc_check(const gran_dsmc *s, const char *name) {
  GRAN_CHECK(s != nullptr, GRAN_ERR_ARG, "argument '%s' is NULL", name);
  GRAN_CHECK(s->M >= 1 && (s->p.v != nullptr || s->N == 0 || s->classes), GRAN_ERR_STATE,
             "argument '%s' is not a DSMC engine made by gran_dsmc_create", name);
  return GRAN_SUCCESS;
}

void dsmc_update_rate(gran_dsmc *s) {
  const double pi = 3.14159265358979323846;
  double rate;
  if (s->selector == GRAN_SELECTOR_LOWRANK) {
    /* sum_ik A_ik = pi/(4V) sum_r U_r V_r; ordered-pair rate of the paper: 2 sum A (Eq. 42) */
    rate = (s->paper ? 2.0 : 1.0) * pi / (4.0 * s->volume) * (s->uv[0] + s->uv[1] + s->uv[2]);
  } else {
    /* N^2 ordered pairs at pi C_max / V (Eq. 50), half of it with the |g| acceptance */
    const double n = (double)s->N;
    rate = (s->paper ? 1.0 : 0.5) * pi * n * n * s->cmax / s->volume;
  }
  rate *= s->g2max;
  s->rate = rate;
  s->inv_rate = rate > 0 ? 1.0 / rate : INFINITY;
}

void dsmc_selector_rebuild(gran_dsmc *s) {
  const int64_t M = s->M;
  if (s->classes) {
    dsmc_class_trees(s); /* speed classes (classes.cpp) */
  } else if (s->selector == GRAN_SELECTOR_LOWRANK) {
    for (int64_t i = 0; i < M; i++) {
      const double bn = s->bound[(size_t)i] * (double)s->count[(size_t)i];
      const double sg = s->mix.sigma[(size_t)i];
      s->u[0].node[s->u[0].base + i] = bn * sg * sg;
      s->u[1].node[s->u[1].base + i] = 2.0 * bn * sg;
      s->u[2].node[s->u[2].base + i] = bn;
    }
    for (int r = 0; r < 3; r++) {
      gran_segtree_rebuild(&s->u[r]);
      s->uv[r] = s->u[r].node[1] * s->v[r].node[1];
    }
  } else {
    double c = 0;
    for (int64_t i = 0; i < M; i++)
      if (s->count[(size_t)i] > 0) c = std::fmax(c, 2.0 * s->bird_w[(size_t)i] * s->bound[(size_t)i]);
    s->cmax = c;
  }
  dsmc_update_rate(s);
  s->cand_count = 0;
}

/* The gas has no mean flow (the initial state subtracts it, collisions conserve momentum), but
 * rounding leaves one of about 1e-16 of the initial speeds, which never cools: once the thermal
 * speeds fall below it (t ~ 1e18 tau0 in a 240-particle HCS) it dominates every speed bound and
 * the acceptance falls tenfold per decade. At each tightening of the bounds the mean flow of the
 * gas (species that are not tracers) is removed from every particle (a Galilean change of frame);
 * its kinetic energy, of the order of the rounding of the initial energy, is booked as
 * dissipated so that the ledger still closes. */
static void remove_mean_flow(gran_dsmc *s) {
  if (s->n_gas == 0) return;
  double *v = dsmc_hv(s);
  double u[3];
  dsmc_mean_flow(s, u);
  if (u[0] == 0 && u[1] == 0 && u[2] == 0) return;
  double de = 0, dec = 0; /* E_after - E_before = sum m (|v - u|^2 - |v|^2)/2 = sum m u.(u/2 - v) */
  for (int64_t k = 0; k < s->M; k++) {
    const double mk = s->mix.m[(size_t)k];
    dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
      for (int64_t j = ja; j < jb; j++) {
        double *x = v + 3 * j;
        neumaier_add(de, dec, mk * (u[0] * (0.5 * u[0] - x[0]) + u[1] * (0.5 * u[1] - x[1]) + u[2] * (0.5 * u[2] - x[2])));
        x[0] -= u[0];
        x[1] -= u[1];
        x[2] -= u[2];
      }
    });
  }
  neumaier_add(s->e_diss, s->e_diss_c, -(de + dec));
  /* displacements: R(t) = r + v (t - t_start) must not jump when v changes by -u */
  if (s->classes && !s->cr.empty()) /* speed classes: t_last = t_start for every particle */
    for (int64_t k = 0; k < s->M; k++)
      dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++)
          for (int d = 0; d < 3; d++) s->cr[(size_t)(3 * j + d)] += u[d] * s->t;
      });
  if (s->p.r && !s->classes)
    for (int64_t j = 0; j < s->N; j++) {
      const double ts = s->t - (s->p.t_last[j] - s->opt.t_start);
      for (int d = 0; d < 3; d++) s->p.r[3 * j + d] += u[d] * ts;
    }
}

void dsmc_refresh_bounds(gran_dsmc *s) {
  if (s->collisions > 0) remove_mean_flow(s);
  const double *v = dsmc_hv(s);
  for (int64_t i = 0; i < s->M; i++) {
    double m2 = 0;
    dsmc_species_ranges(s, i, [&](int64_t ja, int64_t jb) {
      for (int64_t j = ja; j < jb; j++) {
        const double q = v[3 * j] * v[3 * j] + v[3 * j + 1] * v[3 * j + 1] + v[3 * j + 2] * v[3 * j + 2];
        m2 = q > m2 ? q : m2;
      }
    });
    s->bound2[(size_t)i] = m2;
    s->bound[(size_t)i] = std::sqrt(m2);
    if (s->classes) dsmc_class_layout(s, i); /* speed classes: thresholds and capacities */
  }
  dsmc_selector_rebuild(s);
  dsmc_refresh_window(s);
}

void dsmc_refresh_window(gran_dsmc *s) {
  const int64_t dt = s->trials - s->trials_at_refresh;
  if (dt > 0) s->acc_last = (double)(s->collisions - s->coll_at_refresh) / (double)dt;
  if (s->collisions > 0) s->bound_tightenings++;
  s->coll_at_refresh = s->collisions;
  s->trials_at_refresh = s->trials;
  s->next_refresh = s->collisions + s->refresh_interval;
}

void dsmc_raise_bound(gran_dsmc *s, int32_t i, double s2) {
  const double b = std::sqrt(s2);
  s->bound2[(size_t)i] = s2;
  s->bound[(size_t)i] = b;
  s->bound_raises++;
  if (s->selector == GRAN_SELECTOR_LOWRANK) {
    const double bn = b * (double)s->count[(size_t)i];
    const double sg = s->mix.sigma[(size_t)i];
    segtree_set(&s->u[0], i, bn * sg * sg);
    segtree_set(&s->u[1], i, 2.0 * bn * sg);
    segtree_set(&s->u[2], i, bn);
    for (int r = 0; r < 3; r++) s->uv[r] = s->u[r].node[1] * s->v[r].node[1];
  } else {
    s->cmax = std::fmax(s->cmax, 2.0 * s->bird_w[(size_t)i] * b);
  }
  dsmc_update_rate(s);
}

int dsmc_alloc(const gran_mixture *mix, const int64_t *counts, const gran_dsmc_options *opt, gran_dsmc *s) {
  GRAN_CALL(check_mixture(mix, "mix"));
  GRAN_CALL(check_options(opt));
  const int64_t M = mix->M;
  GRAN_CHECK(M <= INT32_MAX, GRAN_ERR_ARG, "mixture has too many species (" GRAN_I64_FMT ")", M);
  s->opt = *opt;
  s->mix = *mix;
  s->M = M;
  s->selector = (opt->selector == GRAN_SELECTOR_BIRD || opt->selector == GRAN_SELECTOR_BIRD_PAPER)
                    ? GRAN_SELECTOR_BIRD
                    : GRAN_SELECTOR_LOWRANK;
  if (opt->selector == GRAN_SELECTOR_CELL) s->selector = GRAN_SELECTOR_CELL; /* cell.cpp: no trees */
  s->paper = (opt->selector == GRAN_SELECTOR_LOWRANK_PAPER || opt->selector == GRAN_SELECTOR_BIRD_PAPER);

  /* counts: given, or N_k = round(n_k V) (Table I: rounded to the nearest integer) */
  s->count.assign((size_t)M, 0);
  int64_t N = 0;
  if (counts) {
    for (int64_t k = 0; k < M; k++) {
      GRAN_CHECK(counts[k] >= 0, GRAN_ERR_ARG, "argument 'counts[" GRAN_I64_FMT "]' is negative (" GRAN_I64_FMT ")",
                 k, counts[k]);
      GRAN_CHECK(counts[k] <= kMaxParticles - N, GRAN_ERR_ARG, "argument 'counts' sums to more than 2^40 particles");
      s->count[(size_t)k] = counts[k];
      N += counts[k];
    }
    if (opt->volume > 0) {
      s->volume = opt->volume;
    } else {
      /* V = (particles of the species with n_k > 0) / sum n_k: tracers (n_k = 0) do not count */
      double ntot = 0, ngas = 0;
      for (int64_t k = 0; k < M; k++) {
        ntot += mix->n[(size_t)k];
        if (mix->n[(size_t)k] > 0) ngas += (double)counts[k];
      }
      GRAN_CHECK(ntot > 0, GRAN_ERR_ARG,
                 "option 'volume' = %g <= 0 and the mixture's densities sum to 0: the volume is unknown", opt->volume);
      s->volume = ngas / ntot;
      GRAN_CHECK(s->volume > 0, GRAN_ERR_ARG,
                 "option 'volume' = %g <= 0 and 'counts' are 0 for every species with n_k > 0", opt->volume);
      GRAN_CHECK(std::isfinite(s->volume), GRAN_ERR_DOMAIN,
                 "option 'volume' = %g <= 0, so the volume is the particles over the mixture's 'density' sum (%g): "
                 "%g particles over it overflow (choose units with densities nearer 1, or give 'volume')",
                 opt->volume, ntot, ngas);
    }
  } else {
    GRAN_CHECK(opt->volume > 0, GRAN_ERR_ARG,
               "option 'volume' = %g must be > 0 when 'counts' is NULL (N_k = round(n_k V))", opt->volume);
    s->volume = opt->volume;
    for (int64_t k = 0; k < M; k++) {
      const double nk = mix->n[(size_t)k] * opt->volume;
      GRAN_CHECK(nk < (double)(kMaxParticles - N), GRAN_ERR_ARG,
                 "n_k V = %g for species " GRAN_I64_FMT " exceeds 2^40 particles", nk, k);
      s->count[(size_t)k] = (int64_t)std::llround(nk);
      N += s->count[(size_t)k];
    }
  }
  s->N = N;
  s->offset.assign((size_t)M + 1, 0);
  /* tracers: n_k = 0 with particles (check_mixture guarantees some n_k > 0, the gas) */
  s->tracer.assign((size_t)M, 0);
  s->has_tracers = 0;
  s->n_gas = 0;
  for (int64_t k = 0; k < M; k++) {
    s->tracer[(size_t)k] = (uint8_t)(mix->n[(size_t)k] == 0.0 && s->count[(size_t)k] > 0);
    s->has_tracers |= s->tracer[(size_t)k];
    if (!s->tracer[(size_t)k]) s->n_gas += s->count[(size_t)k];
  }
  for (int64_t k = 0; k < M; k++) s->offset[(size_t)k + 1] = s->offset[(size_t)k] + s->count[(size_t)k];

  if (opt->observe & GRAN_OBSERVE_COLLISION_COUNTS) {
    GRAN_CHECK(M <= kMaxCounters / M, GRAN_ERR_ARG,
               "GRAN_OBSERVE_COLLISION_COUNTS needs M*M counters: M = " GRAN_I64_FMT " is too many", M);
    s->ccount.assign((size_t)(M * M), 0);
  }
  setup_pairs(s);

  /* speed classes (classes.cpp): the slot arrays instead of p (N < 2^31); "auto" decided now
   * (dsmc_classes_auto) and stored resolved, so that a checkpoint holds what ran */
  if (opt->speed_classes == GRAN_SPEED_CLASSES_AUTO) s->opt.speed_classes = dsmc_classes_auto(s);
  opt = &s->opt;
  if (opt->speed_classes && N >= INT32_MAX)
    gran_warning_add("option 'speed_classes': " GRAN_I64_FMT " particles exceed the 2^31 slots of the class layout; "
                     "running without speed classes", N);
  if (opt->speed_classes && s->selector == GRAN_SELECTOR_LOWRANK && N > 0 && N < INT32_MAX) {
    GRAN_CALL(dsmc_class_setup(s));
  } else {
  /* particles, grouped by species; displacement arrays only when observed */
  const int flags = (opt->observe & (GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_TRAJECTORIES)) ? GRAN_PARTICLES_DISPLACEMENT : 0;
  GRAN_CALL(gran_particles_init(&s->p, N, flags));
  s->p.n = N;
  for (int64_t k = 0; k < M; k++)
    for (int64_t j = s->offset[(size_t)k]; j < s->offset[(size_t)k + 1]; j++) s->p.species[j] = (int32_t)k;
  if (s->p.r) {
    std::memset(s->p.r, 0, sizeof(double) * 3 * (size_t)N);
    for (int64_t j = 0; j < N; j++) s->p.t_last[j] = opt->t_start;
  }
  }

  s->bound.assign((size_t)M, 0.0);
  s->bound2.assign((size_t)M, 0.0);
  if (s->classes) {
    for (int r = 0; r < 3; r++) { /* trees made by dsmc_class_setup, weights by dsmc_class_trees */
      s->alias_p[r].assign((size_t)s->L, 0.0);
      s->alias_k[r].assign((size_t)s->L, 0);
    }
  } else if (s->selector == GRAN_SELECTOR_LOWRANK) {
    std::vector<double> w((size_t)M);
    for (int r = 0; r < 3; r++) {
      GRAN_CALL(gran_segtree_init(&s->u[r], M, nullptr));
      for (int64_t k = 0; k < M; k++) {
        const double sg = mix->sigma[(size_t)k];
        w[(size_t)k] = (double)s->count[(size_t)k] * (r == 0 ? 1.0 : r == 1 ? sg : sg * sg);
      }
      GRAN_CALL(gran_segtree_init(&s->v[r], M, w.data()));
      s->inv_vtot[r] = s->v[r].node[1] > 0 ? 1.0 / s->v[r].node[1] : 0.0;
      dsmc_build_alias(w, &s->alias_p[r], &s->alias_k[r]);
    }
  } else {
    double smax = 0;
    for (int64_t k = 0; k < M; k++)
      if (s->count[(size_t)k] > 0) smax = std::fmax(smax, mix->sigma[(size_t)k]);
    s->sigma_max = smax;
    s->bird_w.resize((size_t)M);
    for (int64_t k = 0; k < M; k++) {
      const double h = 0.5 * (mix->sigma[(size_t)k] + smax);
      s->bird_w[(size_t)k] = h * h;
    }
  }
  s->refresh_interval = opt->bound_refresh > 0 ? opt->bound_refresh : (N > 0 ? N : 1);

  if (opt->observe & GRAN_OBSERVE_TRAJECTORIES) {
    for (int64_t k = 0; k < M; k++) {
      const int64_t nt = std::min(opt->traj_per_species, s->count[(size_t)k]);
      for (int64_t q = 0; q < nt; q++) {
        s->traj_index.push_back(s->offset[(size_t)k] + q);
        s->traj_species.push_back((int32_t)k);
      }
    }
    s->ntraj = (int64_t)s->traj_index.size();
    GRAN_CHECK(s->ntraj == 0 || opt->traj_samples <= (INT64_C(1) << 40) / s->ntraj, GRAN_ERR_ARG,
               "trajectories need " GRAN_I64_FMT " x " GRAN_I64_FMT " samples: too many", s->ntraj, opt->traj_samples);
    s->traj_xyz.assign((size_t)(s->ntraj * opt->traj_samples * 3), NAN);
  }
  s->t = s->t_ref = 0.0; /* the engine's clock: time elapsed since opt->t_start */
  return GRAN_SUCCESS;
}

}  // namespace gran

using namespace gran;

/** @brief Defaults: low-rank selector, no observables, seed 1, volume 0 (give counts or set it),
 *  t_start 0, bound_refresh 0 (= N collisions), no trajectories (traj_dt 1). */
GRAN_EXTERN int gran_dsmc_options_default(gran_dsmc_options *opt) {
  GRAN_CHECK_PTR(opt);
  *opt = gran_dsmc_options{};
  opt->selector = GRAN_SELECTOR_LOWRANK;
  opt->observe = 0;
  opt->seed = 1;
  opt->volume = 0;
  opt->t_start = 0;
  opt->bound_refresh = 0;
  opt->traj_per_species = 0;
  opt->traj_dt = 1.0;
  opt->traj_samples = 0;
  opt->speed_classes = GRAN_SPEED_CLASSES_AUTO; /* on where it pays (dsmc_classes_auto; docs/developers/dsmc-speed.md) */
  return GRAN_SUCCESS;
}

/** @brief New engine: N_k particles of each species (counts, or round(n_k V)), Maxwellian
 *  velocities at T0[k] (NULL: the HCS of mix with <T(0)> = 1; T_k = 1 for viscoelastic
 *  restitution, which has no HCS), zero momentum of the gas. A species with n_k = 0 and
 *  particles (explicit counts) is a tracer (Bodrova & Osinsky Sec. II F).
 *  @param[in] mix copied; may be destroyed afterwards  @param[out] sim the new engine */
GRAN_EXTERN int gran_dsmc_create(const gran_mixture *mix, const int64_t *counts, const double *T0,
                                 const gran_dsmc_options *opt, gran_dsmc **sim) {
  GRAN_TRY {
    GRAN_CHECK_PTR(sim);
    *sim = nullptr;
    GRAN_CHECK_PTR(mix);
    GRAN_CHECK_PTR(opt);
    GRAN_CHECK(opt->selector != GRAN_SELECTOR_CELL, GRAN_ERR_ARG,
               "option 'selector' = GRAN_SELECTOR_CELL needs a time step and cells: use gran_dsmc_create_cell");
    return dsmc_create_impl(mix, counts, T0, opt, nullptr, sim);
  }
  GRAN_CATCH
}

namespace gran {
/* gran_dsmc_create, and gran_dsmc_create_cell (cell != NULL: positions and cells, cell.cpp) */
int dsmc_create_impl(const gran_mixture *mix, const int64_t *counts, const double *T0, const gran_dsmc_options *opt,
                     const gran_dsmc_cell_options *cell, gran_dsmc **sim) {
  {
    gran_dsmc *s = new gran_dsmc();
    int ierr = dsmc_alloc(mix, counts, opt, s);
    const int64_t M = s->M;
    std::vector<double> T((size_t)std::max<int64_t>(M, 1));
    if (ierr == GRAN_SUCCESS) {
      if (T0) {
        for (int64_t k = 0; k < M && ierr == GRAN_SUCCESS; k++)
          if (!(std::isfinite(T0[k]) && T0[k] >= 0))
            ierr = GRAN_ERROR(GRAN_ERR_ARG, "argument 'T0[" GRAN_I64_FMT "]' = %g must be finite and >= 0", k, T0[k]);
        if (ierr == GRAN_SUCCESS) T.assign(T0, T0 + M);
      } else if (mix->model == GRAN_RESTITUTION_VISCOELASTIC) {
        T.assign((size_t)M, 1.0); /* no HCS with constant ratios: equipartition (Bodrova & Osinsky App. A) */
      } else {
        double tau0;
        ierr = gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T.data(), &tau0);
      }
    }
    if (ierr != GRAN_SUCCESS) {
      gran_dsmc_destroy(&s);
      return ierr;
    }
    /* Maxwellian per species, then subtract the mass-weighted mean velocity of the gas (the
     * species that are not tracers; without tracers: of all particles) from every particle:
     * tracers are independent samples in the frame of the gas */
    gran_rng_seed(&s->rng, opt->seed);
    for (int l = 0; l < kRngLanes; l++) {
      gran_rng lane;
      gran_rng_stream(opt->seed, (uint64_t)(1 + l), &lane);
      for (int w = 0; w < 4; w++) s->vrng.s[w][l] = lane.s[w];
    }
    s->vrng.pos = kRngBuf;
    if (cell && cell->streams == GRAN_CELL_STREAMS_CELLS) { /* positions and velocities cell by cell (cell.cpp) */
      ierr = dsmc_cell_setup(s, cell);
      if (ierr == GRAN_SUCCESS) ierr = dsmc_cell_create_by_cells(s, T.data(), &s->e_initial);
      if (ierr != GRAN_SUCCESS) {
        gran_dsmc_destroy(&s);
        return ierr;
      }
    } else {
      double *v = dsmc_hv(s);
      double P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0}, mtot = 0;
      for (int64_t k = 0; k < M; k++) {
        const double sd = std::sqrt(T[(size_t)k] / s->mix.m[(size_t)k]), mk = s->mix.m[(size_t)k];
        const bool gas = !s->tracer[(size_t)k];
        dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++)
          for (int d = 0; d < 3; d++) {
            v[3 * j + d] = sd * rng_normal(&s->rng);
            if (gas) neumaier_add(P[d], Pc[d], mk * v[3 * j + d]);
          }
        });
        if (gas) mtot += mk * (double)s->count[(size_t)k];
      }
      if (mtot > 0) {
        const double u[3] = {(P[0] + Pc[0]) / mtot, (P[1] + Pc[1]) / mtot, (P[2] + Pc[2]) / mtot};
        for (int64_t k = 0; k < M; k++)
          dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
            for (int64_t j = ja; j < jb; j++)
              for (int d = 0; d < 3; d++) v[3 * j + d] -= u[d];
          });
      }
      double e = 0, ec = 0;
      for (int64_t k = 0; k < M; k++) {
        const double mk = s->mix.m[(size_t)k];
        dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
          for (int64_t j = ja; j < jb; j++)
            neumaier_add(e, ec, 0.5 * mk * (v[3 * j] * v[3 * j] + v[3 * j + 1] * v[3 * j + 1] + v[3 * j + 2] * v[3 * j + 2]));
        });
      }
      s->e_initial = e + ec;
    }
    dsmc_refresh_bounds(s);
    const bool agg = cell && (cell->e_agg > 0 || std::isfinite(cell->e_frag));
    ierr = dsmc_check_derived(s, agg, false); /* the masses (derived.cpp) */
    if (ierr != GRAN_SUCCESS) {
      gran_dsmc_destroy(&s);
      return ierr;
    }
    /* finite inputs can still overflow what is derived from them (T0 = 1e308: v^2 is inf) */
    bool finite = gran_derived_finite(s->e_initial) && gran_derived_finite(s->rate) && gran_derived_finite(s->cmax);
    for (int64_t k = 0; k < M && finite; k++) finite = gran_derived_finite(s->bound2[(size_t)k]);
    for (int r = 0; r < 3 && finite; r++) finite = gran_derived_finite(s->uv[r]);
    if (!finite) {
      const double rate = s->rate, e0 = s->e_initial;
      gran_dsmc_destroy(&s);
      return GRAN_ERROR(GRAN_ERR_DOMAIN,
                        "the initial state overflows (kinetic energy %g, collision rate bound %g): the temperatures "
                        "'T0' are too large for the masses and sizes of this mixture",
                        e0, rate);
    }
    ierr = dsmc_check_derived(s, agg, true); /* the speeds (derived.cpp); event aggregation: gran_dsmc_create_agg */
    if (ierr != GRAN_SUCCESS) {
      gran_dsmc_destroy(&s);
      return ierr;
    }
    if (s->opt.observe & GRAN_OBSERVE_TRAJECTORIES) dsmc_record_trajectories(s);
    if (cell) { /* GRAN_SELECTOR_CELL: positions, cells (cell.cpp) */
      const int st = dsmc_cell_init(s, cell);
      if (st != GRAN_SUCCESS) {
        gran_dsmc_destroy(&s);
        return st;
      }
    }
    *sim = s;
    return GRAN_SUCCESS;
  }
}
}  // namespace gran

/** @brief Release the engine; NULL-safe, sets *sim to NULL. */
GRAN_EXTERN int gran_dsmc_destroy(gran_dsmc **sim) {
  GRAN_TRY {
    if (!sim || !*sim) return GRAN_SUCCESS;
    gran_dsmc *s = *sim;
    dsmc_aggev_free(s); /* event selectors' aggregation (agg_event.cpp) */
    dsmc_cell_free(s);
    gran_particles_free(&s->p);
    for (int r = 0; r < 3; r++) {
      gran_segtree_free(&s->u[r]);
      gran_segtree_free(&s->v[r]);
    }
    gran_segtree_free(&s->ud); /* speed classes */
    delete s;
    *sim = nullptr;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

namespace {

DsmcLoopFn pick_loop(const gran_dsmc *s) {
  const int disp = (s->opt.observe & (GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_TRAJECTORIES)) != 0;
  const int counts = (s->opt.observe & GRAN_OBSERVE_COLLISION_COUNTS) != 0;
  if (s->classes) return dsmc_class_loop(s->paper, disp, counts, s->rest, s->has_tracers); /* speed classes */
  return s->selector == GRAN_SELECTOR_LOWRANK ? dsmc_lowrank_loop(s->paper, disp, counts, s->rest, s->has_tracers)
                                              : dsmc_bird_loop(s->paper, disp, counts, s->rest, s->has_tracers);
}

/* Run until t_end (time mode; elapsed since t_start, as every time inside the engine) or until
 * `coll_stop` collisions (t_end = DBL_MAX), stopping at every trajectory grid time on the way to
 * record the samples there. */
int advance_impl(gran_dsmc *s, double t_end, int64_t coll_stop) {
  const DsmcLoopFn fn = pick_loop(s);
  const bool traj = (s->opt.observe & GRAN_OBSERVE_TRAJECTORIES) != 0;
  for (;;) {
    double t_stop = t_end;
    bool at_grid = false;
    if (traj && s->traj_next < s->opt.traj_samples) {
      const double tg = (double)s->traj_next * s->opt.traj_dt;
      if (tg <= t_stop) {
        t_stop = tg;
        at_grid = true;
      }
    }
    fn(s, t_stop, coll_stop);
    if (s->collisions >= coll_stop) return GRAN_SUCCESS;
    if (at_grid) {
      s->t = t_stop;
      dsmc_record_trajectories(s);
      continue;
    }
    GRAN_CHECK(t_end < DBL_MAX, GRAN_ERR_STATE, "no collision can happen: the total collision rate is 0");
    s->t = t_end;
    return GRAN_SUCCESS;
  }
}

}  // namespace

/** @brief Simulate up to time t_end (>= the current time). */
GRAN_EXTERN int gran_dsmc_advance(gran_dsmc *sim, double t_end) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_FINITE(t_end);
    const double te = t_end - sim->opt.t_start;
    GRAN_CHECK(te >= sim->t, GRAN_ERR_ARG, "argument 't_end' = %.17g lies before the current time %.17g", t_end,
               sim->opt.t_start + sim->t);
    if (sim->cell) return dsmc_cell_advance(sim, te, INT64_MAX);
    if (sim->agg) return dsmc_aggev_advance(sim, te, INT64_MAX); /* agg_event.cpp */
    return advance_impl(sim, te, INT64_MAX);
  }
  GRAN_CATCH
}

/** @brief Simulate the next `ncollisions` accepted collisions; the time becomes that of the last. */
GRAN_EXTERN int gran_dsmc_advance_collisions(gran_dsmc *sim, int64_t ncollisions) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK(ncollisions >= 0, GRAN_ERR_ARG, "argument 'ncollisions' is negative (" GRAN_I64_FMT ")", ncollisions);
    if (ncollisions == 0) return GRAN_SUCCESS;
    GRAN_CHECK(sim->N >= 2, GRAN_ERR_STATE, "no collision can happen with " GRAN_I64_FMT " particle(s)", sim->N);
    GRAN_CHECK(sim->n_gas >= 1, GRAN_ERR_STATE,
               "no collision can happen: only tracers (n_k = 0) have particles, and tracers never collide with each other");
    GRAN_CHECK(ncollisions <= INT64_MAX - sim->collisions, GRAN_ERR_ARG, "argument 'ncollisions' is too large");
    if (sim->cell) return dsmc_cell_advance(sim, DBL_MAX, sim->collisions + ncollisions);
    if (sim->agg) return dsmc_aggev_advance(sim, DBL_MAX, sim->collisions + ncollisions); /* agg_event.cpp */
    return advance_impl(sim, DBL_MAX, sim->collisions + ncollisions);
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_dsmc_time(const gran_dsmc *sim, double *t) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(t);
    *t = sim->opt.t_start + sim->t;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Counters; acceptance = collisions/trials since the last tightening of the bounds (the
 *  last completed window when no trial happened since). */
GRAN_EXTERN int gran_dsmc_get_stats(const gran_dsmc *sim, gran_dsmc_stats *stats) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(stats);
    *stats = gran_dsmc_stats{};
    stats->nparticles = sim->N;
    stats->nspecies = sim->M;
    stats->collisions = sim->collisions;
    stats->trials = sim->trials;
    stats->bound_raises = sim->bound_raises;
    stats->bound_tightenings = sim->bound_tightenings;
    stats->volume = sim->volume;
    stats->time = sim->opt.t_start + sim->t;
    const int64_t dt = sim->trials - sim->trials_at_refresh;
    stats->class_moves = sim->class_moves;
    stats->class_rebuilds = sim->class_rebuilds;
    stats->acceptance = dt > 0 ? (double)(sim->collisions - sim->coll_at_refresh) / (double)dt : sim->acc_last;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_dsmc_counts(const gran_dsmc *sim, int64_t *counts) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(counts);
    for (int64_t k = 0; k < sim->M; k++) counts[k] = sim->count[(size_t)k];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_dsmc_particles(const gran_dsmc *sim, const gran_particles **p) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(p);
    if (sim->classes) GRAN_CALL(dsmc_class_view(const_cast<gran_dsmc *>(sim))); /* speed classes: filled now */
    *p = &sim->p;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_dsmc_species_offsets(const gran_dsmc *sim, int64_t *offsets) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(offsets);
    GRAN_CHECK(sim->agg == nullptr, GRAN_ERR_STATE,
               "with aggregation the particles are not grouped by species (see gran_dsmc_size_distribution)");
    for (int64_t k = 0; k <= sim->M; k++) offsets[k] = sim->offset[(size_t)k];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
