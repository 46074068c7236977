/* cooling.cpp - cooling rates xi_k (seed 000 Eq. 14-15, viscoelastic A7), inverse velocity
 * correlation times (Eq. 10-11, A6), diffusion coefficients (Eq. 8), collision time (Eq. 7).
 *
 * Pair terms are written without cancellation (eps -> 1, T_i -> T_k):
 *   xi_ki = (16/3) sqrt(2 pi) n_i sigma_ki^2 g2 S mu p [ (1-mu)(1 - r) + (1 - p) Gamma ]
 * with S = sqrt(T_k/m_k + T_i/m_i), mu = m_i/(m_i+m_k), p = (1+eps)/2, 1 - p = (1-eps)/2,
 * r = T_i/T_k and Gamma = (T_k m_i + T_i m_k)/(T_k (m_i+m_k)) = mu + r (1 - mu), since
 * 1 - p Gamma = (1 - Gamma) + (1 - p) Gamma and 1 - Gamma = (1 - mu)(1 - r).
 *   1/tau_v,ki = (8/3) sqrt(2 pi) n_i sigma_ki^2 g2 mu Gamma S p^2 (A6: p^2 -> 1 + q2).
 * Viscoelastic (A7): p (1 - p Gamma) -> (1 - Gamma) + q1 - Gamma q2 with the collision-weighted
 * averages q1, q2 of viscoelastic.cpp (A6's prefactor is 8 sqrt(2 pi)/3 as in Eq. 11, so that
 * both agree for beta = 0). */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>

#include <algorithm>

namespace {

const double C15 = 8.0 / 3.0 * 2.5066282746310002; /* (8/3) sqrt(2 pi) */

} // namespace

namespace gran {

void collision_scale(const gran_mixture *mix, const double *T, double *nu) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  for (int64_t k = 0; k < M; k++) {
    const double ak = T[k] / m[k];
    double acc = 0.0;
    for (int64_t i = 0; i < M; i++) {
      if (n[i] == 0.0) continue;
      const double sg = 0.5 * (s[k] + s[i]);
      acc += n[i] * sg * sg * mix_g2(mix, k, i) * std::sqrt(ak + T[i] / m[i]) * m[i] / (m[i] + m[k]);
    }
    nu[k] = C15 * acc;
  }
}

int cooling_rates(const gran_mixture *mix, const double *T, double *xi) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  const bool visco = mix->model == GRAN_RESTITUTION_VISCOELASTIC;
  for (int64_t k = 0; k < M; k++) {
    const double ak = T[k] / m[k], iTk = 1.0 / T[k], mk = m[k], sk = s[k];
    double acc = 0.0;
    for (int64_t i = 0; i < M; i++) {
      if (n[i] == 0.0) continue;
      const double sg = 0.5 * (sk + s[i]);
      const double v2 = ak + T[i] / m[i];
      const double S = std::sqrt(v2);
      const double inv = 1.0 / (m[i] + mk);
      const double mu = m[i] * inv, omu = mk * inv;
      const double r = T[i] * iTk;
      const double oneminusr = (T[k] - T[i]) * iTk;
      const double Gam = mu + r * omu;
      double bracket;
      if (!visco) {
        const double eps = mix_eps(mix, k, i);
        const double p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
        bracket = 2.0 * p * (omu * oneminusr + q * Gam);
      } else {
        const double beta = mix_beta(mix, k, i);
        double q1 = 0.0, q2 = 0.0;
        if (beta > 0.0) {
          const double z = std::sqrt(beta) * std::pow(2.0 * v2, 0.05);
          GRAN_CALL(visco_averages(z, &q1, &q2));
        }
        bracket = 2.0 * (omu * oneminusr + q1 - Gam * q2);
      }
      acc += n[i] * sg * sg * mix_g2(mix, k, i) * S * mu * bracket;
    }
    xi[k] = C15 * acc;
  }
  return GRAN_SUCCESS;
}

/* xi_k and J_kj = d xi_k / d log T_j (row-major M*M); constant/matrix restitution only. */
void cooling_jacobian(const gran_mixture *mix, const double *T, double *xi, double *J) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  std::fill(J, J + M * M, 0.0);
  for (int64_t k = 0; k < M; k++) {
    const double ak = T[k] / m[k], iTk = 1.0 / T[k], mk = m[k], sk = s[k];
    double acc = 0.0, dk = 0.0;
    double *Jk = J + k * M;
    for (int64_t i = 0; i < M; i++) {
      if (n[i] == 0.0) continue;
      const double sg = 0.5 * (sk + s[i]);
      const double ai = T[i] / m[i];
      const double S = std::sqrt(ak + ai);
      const double inv = 1.0 / (m[i] + mk);
      const double mu = m[i] * inv, omu = mk * inv;
      const double r = T[i] * iTk;
      const double omr = (T[k] - T[i]) * iTk;
      const double eps = mix_eps(mix, k, i);
      const double p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
      const double B = omu * omr + q * (mu + r * omu);
      const double W = C15 * n[i] * sg * sg * mix_g2(mix, k, i) * mu * 2.0 * p;
      acc += W * S * B;
      const double t1 = 0.5 * B / S, t2 = S * p * r * omu;
      Jk[i] += W * (ai * t1 - t2);
      dk += W * (ak * t1 + t2);
    }
    xi[k] = acc;
    Jk[k] += dk;
  }
}

int inv_tau_v(const gran_mixture *mix, const double *T, double *inv_tv) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  const bool visco = mix->model == GRAN_RESTITUTION_VISCOELASTIC;
  for (int64_t k = 0; k < M; k++) {
    const double ak = T[k] / m[k], iTk = 1.0 / T[k], mk = m[k], sk = s[k];
    double acc = 0.0;
    for (int64_t i = 0; i < M; i++) {
      if (n[i] == 0.0) continue;
      const double sg = 0.5 * (sk + s[i]);
      const double v2 = ak + T[i] / m[i];
      const double inv = 1.0 / (m[i] + mk);
      const double mu = m[i] * inv, omu = mk * inv;
      const double Gam = mu + T[i] * iTk * omu;
      double f;
      if (!visco) {
        const double p = 0.5 * (1.0 + mix_eps(mix, k, i));
        f = p * p;
      } else {
        const double beta = mix_beta(mix, k, i);
        double q1 = 0.0, q2 = 0.0;
        if (beta > 0.0) {
          const double z = std::sqrt(beta) * std::pow(2.0 * v2, 0.05);
          GRAN_CALL(visco_averages(z, &q1, &q2));
        }
        f = 1.0 + q2;
      }
      acc += n[i] * sg * sg * mix_g2(mix, k, i) * mu * Gam * std::sqrt(v2) * f;
    }
    inv_tv[k] = C15 * acc;
  }
  return GRAN_SUCCESS;
}

} // namespace gran

using namespace gran;

/**
 * @brief Cooling rates xi_k = sum_i xi_ki (seed 000 Eq. 14-15; A7 for the viscoelastic model).
 * @param[in] T M temperatures > 0
 * @param[out] xi M cooling rates (dT_k/dt = -xi_k T_k)
 */
GRAN_EXTERN int gran_theory_cooling_rates(const gran_mixture *mix, const double *T, double *xi) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(xi);
    return cooling_rates(mix, T, xi);
  }
  GRAN_CATCH
}

/**
 * @brief Velocity correlation times tau_v,k (Eq. 10-11; A6 for the viscoelastic model).
 */
GRAN_EXTERN int gran_theory_tau_v(const gran_mixture *mix, const double *T, double *tau_v) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(tau_v);
    GRAN_CALL(inv_tau_v(mix, T, tau_v));
    for (int64_t k = 0; k < mix->M; k++) tau_v[k] = 1.0 / tau_v[k];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Diffusion coefficients D_k = T_k tau_v,k / m_k (Eq. 8).
 */
GRAN_EXTERN int gran_theory_diffusion(const gran_mixture *mix, const double *T, double *D) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(D);
    GRAN_CALL(inv_tau_v(mix, T, D));
    for (int64_t k = 0; k < mix->M; k++) D[k] = T[k] / (mix->m[(size_t)k] * D[k]);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Inverse mean collision time of species 1 (Eq. 7): 4 n_1 sigma_1^2 g2_11 sqrt(pi T_1/m_1).
 * @param[in] T M temperatures (only T[0] is used; all are checked)
 */
GRAN_EXTERN int gran_theory_collision_rate1(const gran_mixture *mix, const double *T, double *inv_tau_c) {
  GRAN_TRY {
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(inv_tau_c);
    const double s1 = mix->sigma[0];
    *inv_tau_c = 4.0 * mix->n[0] * s1 * s1 * mix_g2(mix, 0, 0) * std::sqrt(M_PI * T[0] / mix->m[0]);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
