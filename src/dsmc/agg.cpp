/* agg.cpp - aggregation and fragmentation (the DSMC outline steps 10a-10d with the corrections of
 * docs/physics.md), shared by every selector: species are cluster sizes (species k-1 = k-mer, mass
 * k m_1, diameter sigma_1 k^(1/3)), the size tables grow on demand (nothing M x M), particles are
 * unordered. The collision rules are in agg_impl.h (used by cell.cpp and agg_event.cpp); here: the
 * checks at creation, the cell selector's bookkeeping at the end of a step, the observables and
 * the public cluster API. */
#include "cell_impl.h"

#include <algorithm>
#include <cmath>

namespace gran {

void dsmc_agg_grow(DsmcAgg *c, int64_t k) {
  const int64_t have = (int64_t)c->nsize.size();
  if (k <= have) return;
  const int64_t n = std::max(k, 2 * have);
  c->nsize.resize((size_t)n, 0);
  c->sigk.resize((size_t)n);
  for (int64_t q = have; q < n; q++) c->sigk[(size_t)q] = c->sigma1 * std::cbrt((double)(q + 1));
}

int dsmc_agg_setup(gran_dsmc *s, DsmcAgg *c) {
  const gran_mixture *x = &s->mix;
  const int64_t M = s->M;
  GRAN_CHECK(M <= INT32_MAX / 2, GRAN_ERR_ARG, "aggregation: mixture 'mix' has too many species");
  c->m1 = x->m[0];
  c->sigma1 = x->sigma[0];
  for (int64_t k = 0; k < M; k++) {
    const double mk = (double)(k + 1) * c->m1, sk = c->sigma1 * std::cbrt((double)(k + 1));
    GRAN_CHECK(std::fabs(x->m[(size_t)k] - mk) <= 1e-12 * mk && std::fabs(x->sigma[(size_t)k] - sk) <= 1e-12 * sk,
               GRAN_ERR_ARG,
               "aggregation needs species k-1 of mixture 'mix' to be the k-mer (m_k = k m_1, sigma_k = sigma_1 "
               "k^(1/3)): species " GRAN_I64_FMT " has m = %g, sigma = %g (expected %g, %g)",
               k, x->m[(size_t)k], x->sigma[(size_t)k], mk, sk);
  }
  GRAN_CHECK(s->rest == kRestConst, GRAN_ERR_UNSUPPORTED,
             "aggregation and fragmentation need one constant restitution coefficient and a uniform g2 "
             "(cluster sizes appear during the run)");
  GRAN_CHECK((s->opt.observe & (GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_TRAJECTORIES | GRAN_OBSERVE_COLLISION_COUNTS)) ==
                 0,
             GRAN_ERR_UNSUPPORTED,
             "aggregation and fragmentation: displacements, trajectories and per-pair collision counts are not "
             "defined (clusters appear and vanish); use gran_dsmc_get_cluster_stats");
  dsmc_agg_grow(c, std::max<int64_t>(M, 1));
  for (int64_t k = 0; k < M; k++) c->sigk[(size_t)k] = x->sigma[(size_t)k]; /* the mixture's values */
  c->kmax = 0;
  c->monomers = 0;
  for (int64_t k = 0; k < M; k++) {
    c->nsize[(size_t)k] = s->count[(size_t)k];
    if (s->count[(size_t)k] > 0) c->kmax = k + 1;
    c->monomers += (k + 1) * s->count[(size_t)k];
  }
  c->agg = 1;
  s->agg = c;
  return GRAN_SUCCESS;
}

void dsmc_agg_end_step(gran_dsmc *s) {
  DsmcCell *c = s->cell;
  gran_particles *p = &s->p;
  if (c->ndead > 0) {
    int64_t j = 0;
    while (j < p->n) {
      if (p->species[j] < 0)
        gran_particles_swap_remove(p, j); /* the last particle moves into j: look at j again */
      else
        j++;
    }
    c->ndead = 0;
  }
  s->N = p->n;
  s->n_gas = p->n;
  while (c->kmax > 0 && c->nsize[(size_t)c->kmax - 1] == 0) c->kmax--;
  for (int64_t k = 0; k < s->M; k++) {
    s->count[(size_t)k] = c->nsize[(size_t)k];
    s->bound2[(size_t)k] = c->vmax2;
    s->bound[(size_t)k] = std::sqrt(c->vmax2);
  }
}

/* momentum and mass of all clusters */
void dsmc_agg_mean_flow(const gran_dsmc *s, double u[3]) {
  double P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0};
  const double *v = s->p.v;
  const int32_t *sp = s->p.species;
  for (int64_t j = 0; j < s->N; j++) {
    const double m = (double)(sp[j] + 1);
    for (int d = 0; d < 3; d++) neumaier_add(P[d], Pc[d], m * v[3 * j + d]);
  }
  const double mt = (double)s->agg->monomers;
  for (int d = 0; d < 3; d++) u[d] = mt > 0 ? (P[d] + Pc[d]) / mt : 0.0;
}

/* T_k (and a2_k) of the sizes 1..M of the mixture; NaN where none is present */
int dsmc_agg_temperatures(const gran_dsmc *s, double *T, double *a2) {
  const int64_t M = s->M;
  double u[3];
  dsmc_agg_mean_flow(s, u);
  std::vector<double> s2((size_t)M, 0.0), c2((size_t)M, 0.0);
  std::vector<double> cmax(a2 ? (size_t)M : 0, 0.0);
  std::vector<int64_t> n((size_t)M, 0);
  const double *v = s->p.v;
  const int32_t *sp = s->p.species;
  for (int64_t j = 0; j < s->N; j++) {
    const int64_t k = sp[j];
    if (k >= M) continue;
    const double a = v[3 * j] - u[0], b = v[3 * j + 1] - u[1], e = v[3 * j + 2] - u[2];
    neumaier_add(s2[(size_t)k], c2[(size_t)k], a * a + b * b + e * e);
    if (a2) cmax[(size_t)k] = std::fmax(cmax[(size_t)k], std::fmax(std::fabs(a), std::fmax(std::fabs(b), std::fabs(e))));
    n[(size_t)k]++;
  }
  for (int64_t k = 0; k < M; k++) {
    const double nk = (double)n[(size_t)k], m2 = (s2[(size_t)k] + c2[(size_t)k]) / nk;
    if (T) T[k] = nk > 0 ? (double)(k + 1) * s->agg->m1 * m2 / 3.0 : NAN;
    GRAN_CHECK(!T || nk == 0 || std::isfinite(T[k]), GRAN_ERR_NUMERIC,
               "gran_dsmc_temperatures: the temperature of cluster size %lld is %g: a velocity of the gas is no longer "
               "finite or its square overflows",
               (long long)(k + 1), T[k]);
  }
  if (!a2) return GRAN_SUCCESS;
  for (int64_t k = 0; k < M; k++) {
    const double c = cmax[(size_t)k];
    GRAN_CHECK(n[(size_t)k] == 0 || (std::isfinite(c) && c > 0), GRAN_ERR_NUMERIC,
               "gran_dsmc_sonine_a2: cluster size %lld %s: its a2 is undefined", (long long)(k + 1),
               std::isfinite(c) ? "has no thermal motion (every velocity equals the mean flow)"
                                : "has a velocity that is not finite");
  }
  /* the moments of c / max|c| per size: no underflow of c^4 in a cold gas */
  std::vector<double> q2((size_t)M, 0.0), e2((size_t)M, 0.0), q4((size_t)M, 0.0), e4((size_t)M, 0.0);
  for (int64_t j = 0; j < s->N; j++) {
    const int64_t k = sp[j];
    if (k >= M) continue;
    const double w = 1.0 / cmax[(size_t)k];
    const double a = (v[3 * j] - u[0]) * w, b = (v[3 * j + 1] - u[1]) * w, e = (v[3 * j + 2] - u[2]) * w;
    const double q = a * a + b * b + e * e;
    neumaier_add(q2[(size_t)k], e2[(size_t)k], q);
    neumaier_add(q4[(size_t)k], e4[(size_t)k], q * q);
  }
  for (int64_t k = 0; k < M; k++) {
    const double nk = (double)n[(size_t)k];
    if (nk == 0) {
      a2[k] = NAN;
      continue;
    }
    const double m2 = (q2[(size_t)k] + e2[(size_t)k]) / nk, m4 = (q4[(size_t)k] + e4[(size_t)k]) / nk;
    a2[k] = 0.6 * m4 / (m2 * m2) - 1.0;
  }
  return GRAN_SUCCESS;
}

void dsmc_agg_energy_momentum(const gran_dsmc *s, double *e_kin, double p[3]) {
  double e = 0, ec = 0, P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0};
  const double *v = s->p.v;
  const int32_t *sp = s->p.species;
  const double m1 = s->agg->m1;
  for (int64_t j = 0; j < s->N; j++) {
    const double m = (double)(sp[j] + 1) * m1;
    const double *x = v + 3 * j;
    if (e_kin) neumaier_add(e, ec, 0.5 * m * (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]));
    if (p)
      for (int d = 0; d < 3; d++) neumaier_add(P[d], Pc[d], m * x[d]);
  }
  if (e_kin) *e_kin = e + ec;
  if (p)
    for (int d = 0; d < 3; d++) p[d] = P[d] + Pc[d];
}

}  // namespace gran

using namespace gran;

static int check_agg(const gran_dsmc *sim) {
  GRAN_CALL(dsmc_check(sim, "sim"));
  GRAN_CHECK(sim->agg != nullptr, GRAN_ERR_STATE,
             "engine 'sim' has no aggregation or fragmentation (e_agg > 0 or a finite e_frag)");
  return GRAN_SUCCESS;
}

/** @brief Clusters, mass, sizes, counters of merges / breakups / bounces and the ledger parts of
 *  an aggregating engine (any selector). */
GRAN_EXTERN int gran_dsmc_get_cluster_stats(const gran_dsmc *sim, gran_dsmc_cluster_stats *st) {
  GRAN_TRY {
    GRAN_CALL(check_agg(sim));
    GRAN_CHECK_PTR(st);
    const DsmcAgg *c = sim->agg;
    *st = gran_dsmc_cluster_stats{};
    st->nclusters = sim->N;
    st->mass = c->monomers;
    st->largest = c->kmax;
    int64_t ns = 0;
    for (int64_t k = 0; k < c->kmax; k++) ns += c->nsize[(size_t)k] > 0;
    st->nsizes = ns;
    st->mean_size = sim->N > 0 ? (double)c->monomers / (double)sim->N : 0.0;
    st->merges = c->merges;
    st->breakups = c->breakups;
    st->bounces = c->bounces;
    st->e_bounce = sim->e_diss + sim->e_diss_c;
    st->e_merge = c->e_merge + c->e_merge_c;
    st->e_break = c->e_break + c->e_break_c;
    st->e_heat = sim->cell ? sim->cell->e_heat + sim->cell->e_heat_c : 0.0;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Sparse size distribution: the sizes present in increasing order (at most cap of them),
 *  their cluster counts and (T may be NULL) temperatures T_k = k m_1 <|v - u|^2>/3. */
GRAN_EXTERN int gran_dsmc_size_distribution(const gran_dsmc *sim, int64_t cap, int64_t *nsizes, int64_t *sizes,
                                            int64_t *counts, double *T) {
  GRAN_TRY {
    GRAN_CALL(check_agg(sim));
    GRAN_CHECK_PTR(nsizes);
    GRAN_CHECK(cap >= 0, GRAN_ERR_ARG, "argument 'cap' is negative (" GRAN_I64_FMT ")", cap);
    GRAN_CHECK(cap == 0 || (sizes && counts), GRAN_ERR_ARG, "arguments 'sizes' and 'counts' must not be NULL when cap > 0");
    const DsmcAgg *c = sim->agg;
    int64_t ns = 0;
    for (int64_t k = 0; k < c->kmax; k++) ns += c->nsize[(size_t)k] > 0;
    *nsizes = ns;
    GRAN_CHECK(cap == 0 || cap >= ns, GRAN_ERR_RANGE,
               "argument 'cap' = " GRAN_I64_FMT " is smaller than the " GRAN_I64_FMT " sizes present", cap, ns);
    if (cap == 0) return GRAN_SUCCESS;
    std::vector<int64_t> slot((size_t)c->kmax, -1);
    int64_t q = 0;
    for (int64_t k = 0; k < c->kmax; k++)
      if (c->nsize[(size_t)k] > 0) {
        slot[(size_t)k] = q;
        sizes[q] = k + 1;
        counts[q] = c->nsize[(size_t)k];
        q++;
      }
    if (T) {
      double u[3];
      dsmc_agg_mean_flow(sim, u);
      std::vector<double> s2((size_t)ns, 0.0), c2((size_t)ns, 0.0);
      const double *v = sim->p.v;
      for (int64_t j = 0; j < sim->N; j++) {
        const int64_t r = slot[(size_t)sim->p.species[j]];
        const double a = v[3 * j] - u[0], b = v[3 * j + 1] - u[1], e = v[3 * j + 2] - u[2];
        neumaier_add(s2[(size_t)r], c2[(size_t)r], a * a + b * b + e * e);
      }
      for (int64_t r = 0; r < ns; r++)
        T[r] = (double)sizes[r] * c->m1 * (s2[(size_t)r] + c2[(size_t)r]) / (3.0 * (double)counts[r]);
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
