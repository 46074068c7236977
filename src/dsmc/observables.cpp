/* observables.cpp - what the DSMC engine measures: temperatures, MSD, Sonine a2, energy ledger,
 * momentum, collision counts, trajectories. Displacements are evaluated lazily (Eq. 45):
 * R_j(t) = r_j + v_j (t - t_last_j), without modifying the state. */
#include "dsmc_impl.h"
#include "cell_impl.h"
#include "agg_impl.h"

#include <algorithm>

namespace gran {

/* Mean flow u = P / sum m of the gas: the species that are not tracers (0 up to rounding: the
 * engine conserves the gas's momentum; tracers exchange momentum with the bath, their frame is
 * the gas's). Without tracers: of all particles. */
void dsmc_mean_flow(const gran_dsmc *s, double u[3]) {
  if (s->agg) return dsmc_agg_mean_flow(s, u); /* cell selector: clusters */
  double P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0}, mt = 0;
  const double *v = dsmc_hv(s);
  for (int64_t k = 0; k < s->M; k++) {
    if (s->tracer[(size_t)k]) continue;
    const double mk = s->mix.m[(size_t)k];
    dsmc_species_ranges(s, k, [&](int64_t ja, int64_t jb) {
      for (int64_t j = ja; j < jb; j++)
        for (int d = 0; d < 3; d++) neumaier_add(P[d], Pc[d], mk * v[3 * j + d]);
    });
    mt += mk * (double)s->count[(size_t)k];
  }
  for (int d = 0; d < 3; d++) u[d] = mt > 0 ? (P[d] + Pc[d]) / mt : 0.0;
}

void dsmc_record_trajectories(gran_dsmc *s) {
  const int64_t S = s->opt.traj_samples, g = s->traj_next;
  if (g >= S) return;
  const double t = s->t; /* elapsed since t_start (the engine's clock) */
  for (int64_t q = 0; q < s->ntraj; q++) {
    const int64_t j = s->traj_index[(size_t)q];
    double *x = &s->traj_xyz[(size_t)((q * S + g) * 3)];
    if (s->classes) { /* speed classes: the particle's slot; t_last = t_start */
      const int64_t h = s->cslot[(size_t)j];
      for (int d = 0; d < 3; d++) x[d] = s->cr[(size_t)(3 * h + d)] + s->cv[(size_t)(3 * h + d)] * t;
      continue;
    }
    const double dt = t - (s->p.t_last[j] - s->opt.t_start);
    for (int d = 0; d < 3; d++) x[d] = s->p.r[3 * j + d] + s->p.v[3 * j + d] * dt;
  }
  s->traj_next = g + 1;
}

}  // namespace gran

using namespace gran;

/** @brief Partial temperatures T_k = m_k <|v - u|^2> / 3 with u the mean flow of the gas (all
 *  species but tracers; 0 up to rounding, since its momentum is conserved); NaN for an empty species;
 *  GRAN_ERR_NUMERIC when an occupied species' temperature is not finite. */
GRAN_EXTERN int gran_dsmc_temperatures(const gran_dsmc *sim, double *T) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(T);
    if (sim->agg) return dsmc_agg_temperatures(sim, T, nullptr); /* clusters */
    double u[3];
    dsmc_mean_flow(sim, u);
    const double *v = dsmc_hv(sim);
    for (int64_t k = 0; k < sim->M; k++) {
      double s2 = 0, c = 0;
      dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++) {
          const double a = v[3 * j] - u[0], b = v[3 * j + 1] - u[1], e = v[3 * j + 2] - u[2];
          neumaier_add(s2, c, a * a + b * b + e * e);
        }
      });
      const int64_t n = sim->count[(size_t)k];
      T[k] = n > 0 ? sim->mix.m[(size_t)k] * (s2 + c) / (3.0 * (double)n) : NAN;
      GRAN_CHECK(n == 0 || std::isfinite(T[k]), GRAN_ERR_NUMERIC,
                 "gran_dsmc_temperatures: the temperature of species %lld is %g: a velocity of the gas is no longer "
                 "finite or its square overflows",
                 (long long)k, T[k]);
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Partial MSD <R_k^2> at the current time and the number-weighted total (Eq. 3);
 *  needs GRAN_OBSERVE_DISPLACEMENT. Either output may be NULL; NaN for an empty species. */
GRAN_EXTERN int gran_dsmc_msd(const gran_dsmc *sim, double *msd, double *msd_total) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK(msd || msd_total, GRAN_ERR_ARG, "arguments 'msd' and 'msd_total' are both NULL");
    GRAN_CHECK(dsmc_hr(sim) != nullptr, GRAN_ERR_STATE,
               "MSD needs displacements: create the engine with GRAN_OBSERVE_DISPLACEMENT");
    const double t = sim->t, t0 = sim->opt.t_start, *v = dsmc_hv(sim), *r = dsmc_hr(sim);
    const double *tl = sim->classes ? nullptr : sim->p.t_last; /* speed classes: t_last = t_start */
    double tot = 0, totc = 0;
    for (int64_t k = 0; k < sim->M; k++) {
      double s2 = 0, c = 0;
      dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++) {
          const double dt = tl ? t - (tl[j] - t0) : t; /* t: elapsed since t_start; t_last: absolute */
          const double a = r[3 * j] + v[3 * j] * dt, b = r[3 * j + 1] + v[3 * j + 1] * dt,
                       e = r[3 * j + 2] + v[3 * j + 2] * dt;
          neumaier_add(s2, c, a * a + b * b + e * e);
        }
      });
      const int64_t n = sim->count[(size_t)k];
      if (msd) msd[k] = n > 0 ? (s2 + c) / (double)n : NAN;
      neumaier_add(tot, totc, s2 + c);
    }
    if (msd_total) *msd_total = sim->N > 0 ? (tot + totc) / (double)sim->N : NAN;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Collisions per species pair, symmetric M*M (counts[i*M+k] = collisions between species
 *  i and k; the diagonal counts i-i collisions once); needs GRAN_OBSERVE_COLLISION_COUNTS. */
GRAN_EXTERN int gran_dsmc_collision_counts(const gran_dsmc *sim, int64_t *counts) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(counts);
    GRAN_CHECK(!sim->ccount.empty(), GRAN_ERR_STATE,
               "collision counts were not recorded: create the engine with GRAN_OBSERVE_COLLISION_COUNTS");
    const int64_t M = sim->M;
    for (int64_t i = 0; i < M; i++)
      for (int64_t k = i; k < M; k++) counts[i * M + k] = counts[k * M + i] = sim->ccount[(size_t)(i * M + k)];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Sonine coefficient a2 = (3/5) <c^4>/<c^2>^2 - 1 per species, c = v - u; NaN when empty. The
 *  moments are taken of c / max|c_i| (per species), so that a cold gas (T ~ 1e-300, where c^4
 *  underflows) gives its a2; GRAN_ERR_NUMERIC when a species has no thermal motion (every c = 0:
 *  a2 is undefined) or a velocity is not finite. */
GRAN_EXTERN int gran_dsmc_sonine_a2(const gran_dsmc *sim, double *a2) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(a2);
    if (sim->agg) return dsmc_agg_temperatures(sim, nullptr, a2); /* clusters */
    double u[3];
    dsmc_mean_flow(sim, u);
    const double *v = dsmc_hv(sim);
    for (int64_t k = 0; k < sim->M; k++) {
      double cmax = 0;
      dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++)
          for (int d = 0; d < 3; d++) cmax = std::fmax(cmax, std::fabs(v[3 * j + d] - u[d]));
      });
      const double n = (double)sim->count[(size_t)k];
      if (n == 0) {
        a2[k] = NAN;
        continue;
      }
      GRAN_CHECK(std::isfinite(cmax) && cmax > 0, GRAN_ERR_NUMERIC,
                 "gran_dsmc_sonine_a2: species %lld %s: its a2 is undefined", (long long)k,
                 std::isfinite(cmax) ? "has no thermal motion (every velocity equals the mean flow)"
                                     : "has a velocity that is not finite");
      const double w = 1.0 / cmax;
      double s2 = 0, c2 = 0, s4 = 0, c4 = 0;
      dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++) {
          const double a = (v[3 * j] - u[0]) * w, b = (v[3 * j + 1] - u[1]) * w, e = (v[3 * j + 2] - u[2]) * w;
          const double q = a * a + b * b + e * e;
          neumaier_add(s2, c2, q);
          neumaier_add(s4, c4, q * q);
        }
      });
      const double m2 = (s2 + c2) / n, m4 = (s4 + c4) / n;
      a2[k] = 0.6 * m4 / (m2 * m2) - 1.0;
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Energy ledger: kinetic energy now (compensated sum), at creation, and dissipated by the
 *  collisions so far (compensated sum of (1 - eps^2) mu g_n^2 / 2). Any output may be NULL. */
GRAN_EXTERN int gran_dsmc_energy(const gran_dsmc *sim, double *e_kin, double *e_initial, double *e_dissipated) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    if (e_kin && sim->agg) { /* clusters */
      dsmc_agg_energy_momentum(sim, e_kin, nullptr);
      e_kin = nullptr;
    }
    if (e_kin) {
      double e = 0, c = 0;
      const double *v = dsmc_hv(sim);
      for (int64_t k = 0; k < sim->M; k++) {
        const double mk = sim->mix.m[(size_t)k];
        dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
          for (int64_t j = ja; j < jb; j++)
            neumaier_add(e, c, 0.5 * mk * (v[3 * j] * v[3 * j] + v[3 * j + 1] * v[3 * j + 1] + v[3 * j + 2] * v[3 * j + 2]));
        });
      }
      *e_kin = e + c;
      GRAN_CHECK(std::isfinite(*e_kin), GRAN_ERR_NUMERIC,
                 "gran_dsmc_energy: the kinetic energy is %g: a velocity of the gas is no longer finite", *e_kin);
    }
    if (e_initial) *e_initial = sim->e_initial;
    if (e_dissipated) *e_dissipated = sim->e_diss + sim->e_diss_c;
    if (e_dissipated && sim->agg) /* aggregation (any selector): merges, breakups */
      *e_dissipated += (sim->agg->e_merge + sim->agg->e_merge_c) + (sim->agg->e_break + sim->agg->e_break_c);
    if (e_dissipated && sim->cell) /* cell selector: minus the thermostat's heat */
      *e_dissipated -= sim->cell->e_heat + sim->cell->e_heat_c;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Total momentum sum_j m_j v_j over all particles, tracers included (compensated).
 *  Conserved without tracers; a tracer collision changes only the tracer (momentum exchanged
 *  with the bath), so with tracers only the gas's part is conserved. */
GRAN_EXTERN int gran_dsmc_momentum(const gran_dsmc *sim, double p[3]) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK_PTR(p);
    if (sim->agg) return dsmc_agg_energy_momentum(sim, nullptr, p), GRAN_SUCCESS; /* clusters */
    double P[3] = {0, 0, 0}, Pc[3] = {0, 0, 0};
    const double *v = dsmc_hv(sim);
    for (int64_t k = 0; k < sim->M; k++) {
      const double mk = sim->mix.m[(size_t)k];
      dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
        for (int64_t j = ja; j < jb; j++)
          for (int d = 0; d < 3; d++) neumaier_add(P[d], Pc[d], mk * v[3 * j + d]);
      });
    }
    for (int d = 0; d < 3; d++) p[d] = P[d] + Pc[d];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Copies the velocities of species k (counts[k] x 3 doubles) into v, in the order of the
 *  view of gran_dsmc_particles without trajectories. Unlike that view, which with speed classes is
 *  a copy of every particle kept by the engine (60 B per particle with displacements), this needs
 *  no memory beyond v: the run driver's velocity histograms use it. */
GRAN_EXTERN int gran_dsmc_species_velocities(const gran_dsmc *sim, int64_t k, double *v) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK(sim->agg == nullptr, GRAN_ERR_STATE,
               "with aggregation the particles are not grouped by species (see gran_dsmc_size_distribution)");
    GRAN_CHECK(k >= 0 && k < sim->M, GRAN_ERR_ARG, "argument 'k' = " GRAN_I64_FMT " is not a species in [0, " GRAN_I64_FMT
               ")", k, sim->M);
    if (sim->count[(size_t)k] == 0) return GRAN_SUCCESS;
    GRAN_CHECK_PTR(v);
    const double *hv = dsmc_hv(sim);
    int64_t at = 0;
    dsmc_species_ranges(sim, k, [&](int64_t ja, int64_t jb) {
      std::copy(hv + 3 * ja, hv + 3 * jb, v + 3 * at);
      at += jb - ja;
    });
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Borrowed trajectories of the tracers (the first traj_per_species particles of each
 *  species): xyz[(q*nsamples + s)*3 + d] is the displacement of tracer q at t_start + s traj_dt,
 *  NaN for times not reached yet; nsamples = traj_samples. Needs GRAN_OBSERVE_TRAJECTORIES.
 *  Any output may be NULL. */
GRAN_EXTERN int gran_dsmc_trajectories(const gran_dsmc *sim, int64_t *ntraj, int64_t *nsamples, const double **xyz,
                                       const int32_t **species) {
  GRAN_TRY {
    GRAN_CALL(dsmc_check(sim, "sim"));
    GRAN_CHECK(sim->opt.observe & GRAN_OBSERVE_TRAJECTORIES, GRAN_ERR_STATE,
               "trajectories were not recorded: create the engine with GRAN_OBSERVE_TRAJECTORIES");
    if (ntraj) *ntraj = sim->ntraj;
    if (nsamples) *nsamples = sim->opt.traj_samples;
    if (xyz) *xyz = sim->traj_xyz.empty() ? nullptr : sim->traj_xyz.data();
    if (species) *species = sim->traj_species.empty() ? nullptr : sim->traj_species.data();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
