/* cooling.cpp - cooling rates xi_k (Bodrova & Osinsky Eq. 14-15, viscoelastic A7), inverse velocity
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
#include <vector>

#include "theory/theory_simd.h"

namespace {

using namespace gran;


using namespace gran_theory_simd;


/* Constant eps and g2: each unordered pair once, vectorised. */
void pass_fast(const gran_mixture *mix, const double *T, double *xi, double *d, double *l, double *nu) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  const double p = 0.5 * (1.0 + mix->eps), q = 0.5 * (1.0 - mix->eps);
  std::vector<double> a((size_t)M), iT((size_t)M);
  for (int64_t k = 0; k < M; k++) {
    a[(size_t)k] = T[k] / m[k];
    iT[(size_t)k] = 1.0 / T[k];
  }
  std::fill(xi, xi + M, 0.0);
  std::fill(d, d + M, 0.0);
  std::fill(nu, nu + M, 0.0);
  for (int64_t k = 0; k < M; k++) {
    const double mk = m[k], sk = s[k], Tk = T[k], ak = a[(size_t)k], iTk = iT[(size_t)k], nk = n[k];
    /* self pair: sigma_kk = s_k, mu = 1/2, B = q */
    {
      const double W = 0.5 * nk * sk * sk, S = std::sqrt(2.0 * ak);
      xi[k] += W * S * q;
      d[k] += W * (0.5 * ak * q / S + 0.5 * S * p);
      l[k] = W * (0.5 * ak * q / S - 0.5 * S * p);
      nu[k] += W * S;
    }
    vd vxi = {}, vd_ = {}, vnu = {};
    int64_t i = 0;
    for (; i + VW <= k; i += VW) {
      const vd si = vload(s + i), mi = vload(m + i), Ti = vload(T + i), ai = vload(a.data() + i),
               iTi = vload(iT.data() + i), ni = vload(n + i);
      const vd sg = sk + si;
      const vd sg2 = 0.25 * sg * sg;
      const vd S = vsqrt(ak + ai);
      const vd iS = 1.0 / S;
      const vd inv = 1.0 / (mi + mk);
      const vd E = (mi * Tk + mk * Ti) * inv, D = Tk - Ti;
      const vd Bki = (mk * inv * D + q * E) * iTk, Bik = (q * E - mi * inv * D) * iTi;
      const vd w = sg2 * inv;
      const vd Wki = ni * mi * w, Wik = nk * mk * w;
      vxi += Wki * S * Bki;
      vd_ += Wki * (0.5 * ak * Bki * iS + S * p * Ti * iTk * mk * inv);
      vnu += Wki * S;
      vstore(xi + i, vload(xi + i) + Wik * S * Bik);
      vstore(d + i, vload(d + i) + Wik * (0.5 * ai * Bik * iS + S * p * Tk * iTi * mi * inv));
      vstore(nu + i, vload(nu + i) + Wik * S);
    }
    double sxi = hsum(vxi), sd = hsum(vd_), snu = hsum(vnu);
    for (; i < k; i++) {
      const double sg = sk + s[i], sg2 = 0.25 * sg * sg, ai = a[(size_t)i], Ti = T[i], mi = m[i];
      const double S = std::sqrt(ak + ai), iS = 1.0 / S, inv = 1.0 / (mi + mk);
      const double E = (mi * Tk + mk * Ti) * inv, D = Tk - Ti;
      const double Bki = (mk * inv * D + q * E) * iTk, Bik = (q * E - mi * inv * D) * iT[(size_t)i];
      const double w = sg2 * inv, Wki = n[i] * mi * w, Wik = nk * mk * w;
      sxi += Wki * S * Bki;
      sd += Wki * (0.5 * ak * Bki * iS + S * p * Ti * iTk * mk * inv);
      snu += Wki * S;
      xi[i] += Wik * S * Bik;
      d[i] += Wik * (0.5 * ai * Bik * iS + S * p * Tk * iT[(size_t)i] * mi * inv);
      nu[i] += Wik * S;
    }
    xi[k] += sxi;
    d[k] += sd;
    nu[k] += snu;
  }
  const double C = C15 * mix->g2 * 2.0 * p, Cn = C15 * mix->g2;
  for (int64_t k = 0; k < M; k++) {
    xi[k] *= C;
    d[k] *= C;
    l[k] *= C;
    nu[k] *= Cn;
  }
}

/* Any restitution/g2 matrices: ordered pairs with the accessors. */
/* 1/tau_v,k for constant eps and g2: each unordered pair once, vectorised.
 * 1/tau_v,ki = C15 g2 p^2 n_i sigma_ki^2 S m_i E/((m_i+m_k) T_k), E = (m_i T_k + m_k T_i)/(m_i+m_k). */
void tau_fast(const gran_mixture *mix, const double *T, double *out) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  const double p = 0.5 * (1.0 + mix->eps);
  std::vector<double> a((size_t)M), iT((size_t)M);
  for (int64_t k = 0; k < M; k++) {
    a[(size_t)k] = T[k] / m[k];
    iT[(size_t)k] = 1.0 / T[k];
  }
  std::fill(out, out + M, 0.0);
  for (int64_t k = 0; k < M; k++) {
    const double mk = m[k], sk = s[k], Tk = T[k], ak = a[(size_t)k], iTk = iT[(size_t)k], nk = n[k];
    out[k] += 0.5 * nk * sk * sk * std::sqrt(2.0 * ak); /* self pair: sigma = s_k, mu = 1/2, Gamma = 1 */
    vd acc = {};
    int64_t i = 0;
    for (; i + VW <= k; i += VW) {
      const vd si = vload(s + i), mi = vload(m + i), Ti = vload(T + i), ai = vload(a.data() + i),
               iTi = vload(iT.data() + i), ni = vload(n + i);
      const vd sg = sk + si;
      const vd inv = 1.0 / (mi + mk);
      const vd w = 0.25 * sg * sg * vsqrt(ak + ai) * (mi * Tk + mk * Ti) * inv * inv;
      acc += ni * mi * w * iTk;
      vstore(out + i, vload(out + i) + nk * mk * w * iTi);
    }
    double sacc = hsum(acc);
    for (; i < k; i++) {
      const double sg = sk + s[i], inv = 1.0 / (m[i] + mk);
      const double w = 0.25 * sg * sg * std::sqrt(ak + a[(size_t)i]) * (m[i] * Tk + mk * T[i]) * inv * inv;
      sacc += n[i] * m[i] * w * iTk;
      out[i] += nk * mk * w * iT[(size_t)i];
    }
    out[k] += sacc;
  }
  const double C = C15 * mix->g2 * p * p;
  for (int64_t k = 0; k < M; k++) out[k] *= C;
}

void pass_general(const gran_mixture *mix, const double *T, double *xi_, double *d_, double *l_, double *nu_) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  for (int64_t k = 0; k < M; k++) {
    const double ak = T[k] / m[k], iTk = 1.0 / T[k], mk = m[k], sk = s[k];
    double xi = 0.0, d = 0.0, nu = 0.0, l = 0.0;
    for (int64_t i = 0; i < M; i++) {
      if (n[i] == 0.0) continue;
      const double sg = 0.5 * (sk + s[i]), ai = T[i] / m[i];
      const double S = std::sqrt(ak + ai), inv = 1.0 / (m[i] + mk);
      const double mu = m[i] * inv, omu = mk * inv, r = T[i] * iTk, omr = (T[k] - T[i]) * iTk;
      const double eps = mix_eps(mix, k, i), p = 0.5 * (1.0 + eps), q = 0.5 * (1.0 - eps);
      const double B = omu * omr + q * (mu + r * omu);
      const double g = C15 * n[i] * sg * sg * mix_g2(mix, k, i) * mu;
      const double W = g * 2.0 * p;
      xi += W * S * B;
      nu += g * S;
      const double t1 = 0.5 * B / S, t2 = S * p * r * omu;
      d += W * (ak * t1 + t2);
      if (i == k) l = W * (ai * t1 - t2);
    }
    xi_[k] = xi;
    d_[k] = d;
    l_[k] = l;
    nu_[k] = nu;
  }
}

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

void cooling_pass(const gran_mixture *mix, const double *T, double *xi, double *d, double *l, double *nu) {
  if (mix->model == GRAN_RESTITUTION_CONSTANT && mix->g2_mat.empty())
    pass_fast(mix, T, xi, d, l, nu);
  else
    pass_general(mix, T, xi, d, l, nu);
}

int cooling_rates(const gran_mixture *mix, const double *T, double *xi) {
  const int64_t M = mix->M;
  if (mix->model == GRAN_RESTITUTION_CONSTANT && mix->g2_mat.empty()) {
    std::vector<double> w((size_t)(3 * M));
    pass_fast(mix, T, xi, w.data(), w.data() + M, w.data() + 2 * M);
    return GRAN_SUCCESS;
  }
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
  if (mix->model == GRAN_RESTITUTION_CONSTANT && mix->g2_mat.empty()) {
    tau_fast(mix, T, inv_tv);
    return GRAN_SUCCESS;
  }
  for (int64_t k = 0; k < mix->M; k++) GRAN_CALL(inv_tau_v_one(mix, T, k, &inv_tv[k]));
  return GRAN_SUCCESS;
}

int inv_tau_v_one(const gran_mixture *mix, const double *T, int64_t k, double *out) {
  const int64_t M = mix->M;
  const double *m = mix->m.data(), *s = mix->sigma.data(), *n = mix->n.data();
  const bool visco = mix->model == GRAN_RESTITUTION_VISCOELASTIC;
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
      if (beta > 0.0) GRAN_CALL(visco_averages(std::sqrt(beta) * std::pow(2.0 * v2, 0.05), &q1, &q2));
      f = 1.0 + q2;
    }
    acc += n[i] * sg * sg * mix_g2(mix, k, i) * mu * Gam * std::sqrt(v2) * f;
  }
  *out = C15 * acc;
  return GRAN_SUCCESS;
}

} // namespace gran

using namespace gran;

/**
 * @brief Cooling rates xi_k = sum_i xi_ki (Bodrova & Osinsky Eq. 14-15; A7 for the viscoelastic model).
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
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(inv_tau_c);
    const double s1 = mix->sigma[0];
    *inv_tau_c = 4.0 * mix->n[0] * s1 * s1 * mix_g2(mix, 0, 0) * std::sqrt(M_PI * T[0] / mix->m[0]);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
