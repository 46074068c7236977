/* collisions.cpp - collision statistics of the DSMC outline (Eqs. 57-63) for comparison with the DSMC
 * engines' per-pair collision counters, the reduced times of Bodrova & Osinsky Eq. 6, and the tracer-limit
 * formulas of Bodrova & Osinsky Sec. II F (Eqs. 33-35).
 *
 *  <|g_ij|> = sqrt(8/pi (T_i/m_i + T_j/m_j))                                   (Eq. 60)
 *  rate_ij  = n_i n_j pi sigma_ij^2 g2_ij <|g_ij|> / (1 + delta_ij)            (Eq. 57 per unit V, dt)
 * with the cross-section pi (R_i + R_j)^2 = pi sigma_ij^2 (Eq. 54 corrected: docs/physics.md,
 * "Corrections to the sources") and
 * each unordered pair counted once (a like pair i-i once, hence 1/2): the total is the sum over
 * i <= j; the collision frequency per particle of species k is sum_j (1 + delta_kj) rate_kj / n_k,
 * for one species 2 rate/n = 4 sqrt(pi) n sigma^2 g2 sqrt(T/m) (the DSMC outline Eq. 35;
 * docs/physics.md, "Oracles for tests").
 * The DSMC outline's Eqs. 58 and 61 as printed are half of this total: Eq. 57 already halves the
 * sum over ordered pairs and Eq. 58 halves it again (for one species they contradict Eq. 35).
 *  counts_ij(t) = V int_0^t rate_ij(T(t')) dt'  along the cooling from T0 (ode.cpp dense output,
 * GSL fixed Gauss-Legendre, 8 points, on every node interval: all pairs share the nodes). */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <numeric>

using namespace gran;

namespace {

void rates_at(const gran_mixture *mix, const double *T, double *rates) {
  const int64_t M = mix->M;
  for (int64_t i = 0; i < M; i++) {
    const double ai = T[i] / mix->m[(size_t)i];
    for (int64_t j = i; j < M; j++) {
      const double g = std::sqrt(8.0 / M_PI * (ai + T[j] / mix->m[(size_t)j]));
      const double sg = mix_sigma_pair(mix, i, j);
      double r = mix->n[(size_t)i] * mix->n[(size_t)j] * M_PI * sg * sg * mix_g2(mix, i, j) * g;
      if (i == j) r *= 0.5;
      rates[i * M + j] = rates[j * M + i] = r;
    }
  }
}

} // namespace

/**
 * @brief Mean relative speeds <|g_ij|> (the DSMC outline Eq. 60) for Maxwellian species at temperatures T.
 * @param[out] g M*M, symmetric
 */
GRAN_EXTERN int gran_theory_mean_relative_speed(const gran_mixture *mix, const double *T, double *g) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(g);
    const int64_t M = mix->M;
    for (int64_t i = 0; i < M; i++)
      for (int64_t j = 0; j < M; j++)
        g[i * M + j] = std::sqrt(8.0 / M_PI * (T[i] / mix->m[(size_t)i] + T[j] / mix->m[(size_t)j]));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Collisions per unit volume and time between species i and j (the DSMC outline Eq. 57).
 * @param[out] rates M*M, symmetric, each unordered pair once (diagonal: like pairs, factor 1/2)
 */
GRAN_EXTERN int gran_theory_collision_rates(const gran_mixture *mix, const double *T, double *rates) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(rates);
    rates_at(mix, T, rates);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Expected numbers of collisions in volume V from 0 to t while the mixture cools from T0.
 * @param[in] volume V > 0; t ntimes times >= 0; rtol ODE tolerance in [1e-14, 0.1]
 * @param[out] counts ntimes*M*M, [time][i][j], convention of gran_theory_collision_rates
 */
GRAN_EXTERN int gran_theory_collision_counts(const gran_mixture *mix, const double *T0, double volume,
                                             int64_t ntimes, const double *t, double rtol, double *counts) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T0, mix->M, "T0", 1));
    GRAN_CHECK(std::isfinite(volume) && volume > 0.0, GRAN_ERR_ARG, "argument 'volume' = %g must be finite and > 0",
               volume);
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' = %" PRId64 " is negative", ntimes);
    GRAN_CALL(check_rtol(rtol, "rtol"));
    if (ntimes == 0) return GRAN_SUCCESS;
    GRAN_CALL(check_times(t, ntimes, "t"));
    GRAN_CHECK_PTR(counts);
    const int64_t M = mix->M, MM = M * M;
    Traj tr;
    GRAN_CALL(traj_init(tr, mix, T0, false));
    std::vector<int64_t> idx((size_t)ntimes);
    std::iota(idx.begin(), idx.end(), (int64_t)0);
    std::stable_sort(idx.begin(), idx.end(), [&](int64_t a, int64_t b) { return t[a] < t[b]; });
    const double smax = traj_s_of_t(tr, t[idx[(size_t)(ntimes - 1)]]);
    const double hmax = std::min(0.25, std::max(1e-3, 0.5 * std::pow(rtol, 0.25)));
    GRAN_CALL(traj_run(tr, 0, nullptr, nullptr, std::max(1e-14, 0.1 * rtol), true, hmax, smax));
    gsl_integration_glfixed_table *gl = gsl_integration_glfixed_table_alloc(8);
    GRAN_CHECK(gl != nullptr, GRAN_ERR_NOMEM, "cannot allocate a Gauss-Legendre table");
    std::vector<double> acc((size_t)MM, 0.0), r((size_t)MM), T((size_t)M);
    /* integrate V rate(T(s)) ts e^s ds over [a, b] and add to acc */
    auto add = [&](double a, double b) {
      for (size_t q = 0; q < 8; q++) {
        double x = 0.0, w = 0.0;
        gsl_integration_glfixed_point(a, b, q, &x, &w, gl);
        traj_temperatures(tr, x, T.data());
        rates_at(mix, T.data(), r.data());
        const double f = w * volume * tr.ts * std::exp(x);
        for (int64_t p = 0; p < MM; p++) acc[(size_t)p] += f * r[(size_t)p];
      }
    };
    size_t node = 0;
    double sprev = 0.0;
    for (int64_t jj = 0; jj < ntimes; jj++) {
      const int64_t j = idx[(size_t)jj];
      const double s = traj_s_of_t(tr, t[j]);
      /* whole node intervals up to s, then the partial one */
      while (node + 1 < tr.s.size() && tr.s[node + 1] <= s) {
        add(std::max(sprev, tr.s[node]), tr.s[node + 1]);
        sprev = tr.s[node + 1];
        node++;
      }
      if (s > sprev) {
        add(sprev, s);
        sprev = s;
      }
      std::copy(acc.begin(), acc.end(), counts + j * MM);
    }
    gsl_integration_glfixed_table_free(gl);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Reduced times tau_k(t) = int_0^t sqrt(T_k/T_k(0)) dt' / tau_c(0) (Bodrova & Osinsky Eq. 6, 7).
 * @param[out] tau ntimes*M. In the HCS this is Eq. 18: tau0/tau_c(0) log(1 + t/tau0) for every k.
 */
GRAN_EXTERN int gran_theory_reduced_time(const gran_mixture *mix, const double *T0, int64_t ntimes, const double *t,
                                         double rtol, double *tau) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T0, mix->M, "T0", 1));
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' = %" PRId64 " is negative", ntimes);
    GRAN_CALL(check_rtol(rtol, "rtol"));
    GRAN_CHECK(mix->n[0] > 0.0, GRAN_ERR_DOMAIN,
               "Eq. 7 uses species 1, which is a tracer (n_1 = 0) in 'mix': tau_c(0) is infinite");
    if (ntimes == 0) return GRAN_SUCCESS;
    GRAN_CALL(check_times(t, ntimes, "t"));
    GRAN_CHECK_PTR(tau);
    const int64_t M = mix->M;
    const double s1 = mix->sigma[0];
    const double inv_tc = 4.0 * mix->n[0] * s1 * s1 * mix_g2(mix, 0, 0) * std::sqrt(M_PI * T0[0] / mix->m[0]);
    Traj tr;
    GRAN_CALL(traj_init(tr, mix, T0, true));
    std::vector<int64_t> idx((size_t)ntimes);
    std::iota(idx.begin(), idx.end(), (int64_t)0);
    std::stable_sort(idx.begin(), idx.end(), [&](int64_t a, int64_t b) { return t[a] < t[b]; });
    std::vector<double> so((size_t)ntimes), Y((size_t)(ntimes * 2 * M));
    for (int64_t j = 0; j < ntimes; j++) so[(size_t)j] = traj_s_of_t(tr, t[idx[(size_t)j]]);
    GRAN_CALL(traj_run(tr, ntimes, so.data(), Y.data(), std::max(1e-14, 0.1 * rtol), false, HUGE_VAL, 0.0));
    for (int64_t j = 0; j < ntimes; j++)
      for (int64_t k = 0; k < M; k++) tau[idx[(size_t)j] * M + k] = Y[(size_t)(j * 2 * M + M + k)] * inv_tc;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Tracer temperature ratio gamma = T_tracer/T_1 by the mu >> 1 approximation (Eqs. 34-35):
 * gamma = (1 + eps_12)/(2 (1 - b)), b = mu/(2 sqrt 2) (1 - eps_11^2)/(1 + eps_12)
 * sigma_1^2 g2_11/(sigma_12^2 g2_12), mu = m_tracer/m_1. (Eq. 35 as printed has the sigma and g2
 * factors garbled; this is the form that follows from Eq. 15 with xi_21 = xi_11 at mu >> 1, gamma << mu.)
 * GRAN_ERR_DOMAIN when b >= 1: no positive ratio, the approximation does not apply (e.g. Fig. 5).
 */
GRAN_EXTERN int gran_theory_tracer_gamma_approx(const gran_mixture *mix, int64_t tracer, double *gamma) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(gamma);
    GRAN_CHECK(tracer >= 1 && tracer < mix->M, GRAN_ERR_RANGE,
               "argument 'tracer' = %" PRId64 " outside [1, %" PRId64 ") (species 0 is the gas)", tracer, mix->M);
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "Eqs. 34-35 need constant restitution (mixture 'mix' is viscoelastic)");
    GRAN_CHECK(mix->n[0] > 0.0, GRAN_ERR_DOMAIN, "the gas (species 1 of 'mix') has n = 0");
    for (int64_t k = 1; k < mix->M; k++)
      GRAN_CHECK(mix->n[(size_t)k] == 0.0, GRAN_ERR_DOMAIN,
                 "Eqs. 34-35 assume a monodisperse gas with tracers: species %" PRId64 " has n = %g", k + 1,
                 mix->n[(size_t)k]);
    const double e11 = mix_eps(mix, 0, 0), e12 = mix_eps(mix, 0, tracer);
    const double mu = mix->m[(size_t)tracer] / mix->m[0];
    const double s1 = mix->sigma[0], s12 = mix_sigma_pair(mix, 0, tracer);
    const double b = mu / (2.0 * std::sqrt(2.0)) * (1.0 - e11) * (1.0 + e11) / (1.0 + e12) * s1 * s1 *
                     mix_g2(mix, 0, 0) / (s12 * s12 * mix_g2(mix, 0, tracer));
    GRAN_CHECK(b < 1.0, GRAN_ERR_DOMAIN,
               "Eq. 35 gives b = %g >= 1: the mu >> 1 approximation has no positive temperature ratio here "
               "(use gran_theory_hcs with n_tracer = 0)", b);
    *gamma = (1.0 + e12) / (2.0 * (1.0 - b));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Eq. 33: tau_v,tracer(0)/tau_c(0) = 6 sigma_1^2 (1+mu)^2 gamma sqrt(mu) g2_11 /
 * (sqrt 2 sigma_12^2 (mu + gamma)^(3/2) (1 + eps_12)^2 g2_12) for a given gamma = T_tracer/T_1.
 */
GRAN_EXTERN int gran_theory_tracer_tau_v_hat(const gran_mixture *mix, int64_t tracer, double gamma,
                                             double *tau_v_hat) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(tau_v_hat);
    GRAN_CHECK(tracer >= 1 && tracer < mix->M, GRAN_ERR_RANGE,
               "argument 'tracer' = %" PRId64 " outside [1, %" PRId64 ") (species 0 is the gas)", tracer, mix->M);
    GRAN_CHECK(std::isfinite(gamma) && gamma > 0.0, GRAN_ERR_ARG, "argument 'gamma' = %g must be finite and > 0",
               gamma);
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "Eq. 33 needs constant restitution (mixture 'mix' is viscoelastic)");
    const double e12 = mix_eps(mix, 0, tracer);
    const double mu = mix->m[(size_t)tracer] / mix->m[0];
    const double s1 = mix->sigma[0], s12 = mix_sigma_pair(mix, 0, tracer);
    *tau_v_hat = 6.0 * s1 * s1 * (1.0 + mu) * (1.0 + mu) * gamma * std::sqrt(mu) * mix_g2(mix, 0, 0) /
                 (std::sqrt(2.0) * s12 * s12 * std::pow(mu + gamma, 1.5) * (1.0 + e12) * (1.0 + e12) *
                  mix_g2(mix, 0, tracer));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
