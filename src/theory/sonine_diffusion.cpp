/* sonine_diffusion.cpp - velocity autocorrelation, diffusion coefficient and MSD of species k beyond
 * the single exponential of the Maxwellian level: the two-moment (second Sonine) closure of the
 * Boltzmann-Lorentz operator. Derivation, sources and checks: docs/physics-sonine.md, Sec. 5.
 *
 * In the thermal units w = v/sqrt(T_k/m_k) the conditional moments m = (<w0_x w_x>, <w0_x w_x w^2>)
 * of a tagged particle of species k obey, projected on span{w f_k, w w^2 f_k} (the span of the second
 * Sonine trial function w [1, S_3/2(w^2/2)] of V. Garzo and J. M. Montanero, Phys. Rev. E 69, 021301
 * (2004), with the first Sonine f_k of the species as the weight),
 *   dm/dt = -Lam m,   Lam = -K G^-1 - (zeta_k/2) diag(1, 3),
 * with K_ba = int phi_b J_ki[f_k phi_a] (phi_1 = v, phi_2 = v v^2; the partners' Sonine f_i at T_i),
 * G_ab = int phi_a phi_b f_k = [[a, 5a^2 (1 + a2_k)], [5a^2 (1 + a2_k), 35a^3 (1 + 3 a2_k)]]
 * (a = a_k = T_k/m_k) and the cooling term from the scaling of w (degrees 1 and 3). Per partner i,
 * with A = mu (1 + eps_ki), s^2 = a_k + a_i and pre = -(4/3) sqrt(2 pi) n_i sigma_ki^2 g2 A (sympy,
 * Gaussian moments as in sonine.cpp), K = K^(0) + a2_i K^(i) + a2_k K^(k) to first order in a2
 * (K^(i), K^(k) in the loop below; derivation and quadrature check: docs/tools/sonine_diffusion_a2.py); K^(0):
 *   K11 = pre a_k s
 *   K12 = pre a_k^2 (5 a_i + 6 a_k)/s
 *   K21 = pre a_k [4 A^2 s^4 - A (5 a_i^2 + 19 a_i a_k + 14 a_k^2) + 15 a_i a_k + 18 a_k^2]/s
 *   K22 = pre a_k^2 [4 A^2 s^4 (5 a_i + 8 a_k) - A (25 a_i^3 + 153 a_i^2 a_k + 240 a_i a_k^2 + 112 a_k^3)
 *                    + a_k (105 a_i^2 + 252 a_i a_k + 144 a_k^2)]/s^3.
 * K11/G11 = -nu_k, the momentum-transfer rate: one mode gives the Maxwellian Eq. 11, 1/tau_v = nu - xi/2.
 * The start h(0) = v_x f_k is in the span (alpha(0) = (1, 0)): m(0) = G e_1 = (1, 5 (1 + a2_k)) in
 * thermal units; the correlation is m_1(tau) = c_1 e^(-lam_1 tau) + c_2 e^(-lam_2 tau)
 * (lam_j the eigenvalues of Lam, c_1 + c_2 = 1), and every result of Eq. 4 is the c-weighted sum of
 * the Maxwellian result with 1/tau_v -> lam_j. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <cmath>
#include <complex>

namespace gran {

/* g(y) = y - 1 + exp(-y) for complex y (series below |y| = 1, as g_fun) */
cd g_cplx(cd y) {
  if (!(std::abs(y) < 1.0)) return y - 1.0 + std::exp(-y);
  cd term = 0.5 * y * y, sum = 0.0;
  for (int n = 2; n < 40 && std::abs(term) > 1e-17 * std::abs(sum); n++) {
    sum += term;
    term *= -y / (double)(n + 1);
  }
  return sum;
}

int sonine_modes(const gran_mixture *mix, const double *T, int64_t k, double zeta_k, const double *a2, cd lam[2],
                 cd c[2]) {
  const int64_t M = mix->M;
  const double mk = mix->m[(size_t)k], ak = T[k] / mk, sk = mix->sigma[(size_t)k], a2k = a2 ? a2[k] : 0.0;
  const double SQ2PI = 2.5066282746310002;
  double K11 = 0.0, K12 = 0.0, K21 = 0.0, K22 = 0.0, xi = 0.0;
  for (int64_t i = 0; i < M; i++) {
    const double ni = mix->n[(size_t)i];
    if (ni == 0.0) continue;
    const double mi = mix->m[(size_t)i], ai = T[i] / mi, sg = 0.5 * (sk + mix->sigma[(size_t)i]);
    const double eps = mix_eps(mix, k, i), inv = 1.0 / (mi + mk), mu = mi * inv, omu = mk * inv;
    const double A = mu * (1.0 + eps), s2 = ak + ai, s = std::sqrt(s2), s4 = s2 * s2;
    const double w = ni * sg * sg * mix_g2(mix, k, i), pre = -(4.0 / 3.0) * SQ2PI * w * A;
    K11 += pre * ak * s;
    K12 += pre * ak * ak * (5.0 * ai + 6.0 * ak) / s;
    K21 += pre * ak * (4.0 * A * A * s4 - A * ((5.0 * ai + 19.0 * ak) * ai + 14.0 * ak * ak) + (15.0 * ai + 18.0 * ak) * ak) / s;
    K22 += pre * ak * ak *
           (4.0 * A * A * s4 * (5.0 * ai + 8.0 * ak) -
            A * (((25.0 * ai + 153.0 * ak) * ai + 240.0 * ak * ak) * ai + 112.0 * ak * ak * ak) +
            ak * ((105.0 * ai + 252.0 * ak) * ai + 144.0 * ak * ak)) /
           (s2 * s);
    const double a2i = a2 ? a2[i] : 0.0;
    if (a2i != 0.0) { /* the partner's Sonine f_i, first order in a2_i */
      const double ai2 = ai * ai, s3 = s2 * s, s5 = s3 * s2, q = 2.0 * ak + 5.0 * ai, pa = pre * a2i * ai2 / 8.0;
      K11 -= pa * ak / s3;
      K12 -= pa * ak * ak * (5.0 * ai + 2.0 * ak) / s5;
      K21 += 3.0 * pa * ak * (4.0 * A * A * s4 - A * s2 * q - ak * q) / s5;
      K22 += 3.0 * pa * ak * ak *
             (4.0 * A * A * s4 * (4.0 * ak + 5.0 * ai) - A * s2 * ((8.0 * ak + 24.0 * ai) * ak + 25.0 * ai * ai) -
              ak * ((8.0 * ak + 28.0 * ai) * ak + 35.0 * ai * ai)) /
             (s5 * s2);
    }
    if (a2k != 0.0) { /* the weight f_k of the trial functions, first order in a2_k */
      const double s3 = s2 * s, s5 = s3 * s2, pb = pre * a2k * ak * ak / 8.0;
      const double c0 = ((90.0 * ak + 231.0 * ai) * ak + 184.0 * ai * ai) * ak + 40.0 * ai * ai * ai;
      K11 += pb * (3.0 * ak + 4.0 * ai) / s3;
      K12 += pb * c0 / s5;
      K21 += 3.0 * pb *
             (4.0 * A * A * s4 * (5.0 * ak + 4.0 * ai) - A * s2 * (7.0 * ak + 4.0 * ai) * (10.0 * ak + 11.0 * ai) + c0) /
             s5;
      K22 += pb *
             (4.0 * A * A * s4 * (((280.0 * ak + 555.0 * ai) * ak + 312.0 * ai * ai) * ak + 40.0 * ai * ai * ai) -
              A * s2 *
                  ((((3920.0 * ak + 10880.0 * ai) * ak + 10059.0 * ai * ai) * ak + 3272.0 * ai * ai * ai) * ak +
                   200.0 * ai * ai * ai * ai) +
              9.0 * ak *
                  ((((560.0 * ak + 2020.0 * ai) * ak + 2659.0 * ai * ai) * ak + 1484.0 * ai * ai * ai) * ak +
                   280.0 * ai * ai * ai * ai)) /
             (s5 * s2);
    }
    if (std::isnan(zeta_k)) { /* Maxwellian xi_k (cooling.cpp's form, cancellation-free) */
      const double r = T[i] / T[k], Bm = omu * (1.0 - r) + 0.5 * (1.0 - eps) * (mu + r * omu);
      xi += (8.0 / 3.0) * SQ2PI * w * A * s * Bm;
    }
  }
  const double z = std::isnan(zeta_k) ? xi : zeta_k;
  /* the Gram matrix of the weight f_k: <c^6>_k = (105/8)(1 + 3 a2_k) */
  const double G12 = 5.0 * ak * ak * (1.0 + a2k), G22 = 35.0 * ak * ak * ak * (1.0 + 3.0 * a2k);
  const double det = a2k == 0.0 ? 10.0 * ak * ak * ak * ak : ak * G22 - G12 * G12;
  const double g11 = G22 / det, g12 = -G12 / det, g22 = ak / det;
  const double L11 = -(K11 * g11 + K12 * g12) - 0.5 * z, L12 = -(K11 * g12 + K12 * g22);
  const double L21 = -(K21 * g11 + K22 * g12), L22 = -(K21 * g12 + K22 * g22) - 1.5 * z;
  const double tr = L11 + L22, dt = L11 * L22 - L12 * L21, disc = 0.25 * tr * tr - dt;
  GRAN_CHECK(std::isfinite(disc) && tr > 0.0 && dt > 0.0, GRAN_ERR_DOMAIN,
             "two-moment velocity correlation of species %" PRId64 " does not decay (trace %g, determinant %g)", k,
             tr, dt);
  /* disc < 0 (strong inelasticity): a damped oscillation, lam_1 = conj(lam_0). A double root is
   * split by 1e-6 tr: the results are divided differences, changed by O(1e-12). */
  cd sq = disc >= 0.0 ? cd(std::sqrt(disc), 0.0) : cd(0.0, std::sqrt(-disc));
  if (std::abs(sq) < 1e-6 * tr) sq = cd(1e-6 * tr, 0.0);
  lam[1] = 0.5 * tr + sq;
  lam[0] = dt / lam[1]; /* the smaller root without cancellation */
  /* m(0) = (a, 5 a^2 (1 + a2_k)) in v units (alpha(0) = (1, 0)); (Lam m0)_1 / a = L11 + L12 5 a (1 + a2_k) */
  const double Lm = L11 + L12 * 5.0 * ak * (1.0 + a2k);
  c[0] = (Lm - lam[1]) / (lam[0] - lam[1]);
  c[1] = 1.0 - c[0];
  GRAN_CHECK(std::isfinite(std::abs(c[0])) && std::isfinite(std::abs(lam[0])), GRAN_ERR_NUMERIC,
             "two-moment velocity correlation of species %" PRId64 " is not finite", k);
  return GRAN_SUCCESS;
}

} // namespace gran

using namespace gran;

namespace {

/* The HCS state of the Sonine approximation shared by the MSD and TAMSD calls: argument checks,
 * zeta_k tau0/2 = 1 (tau0 = inf: elastic at equipartition) and the two modes of every species. */
int sonine_hcs_modes(const gran_mixture *mix, const double *T0, const double *a2, double tau0, std::vector<cd> &lam,
                     std::vector<cd> &c) {
  GRAN_CALL(check_hcs_args(mix, T0, tau0));
  const int64_t M = mix->M;
  std::vector<double> b((size_t)M, 0.0), zeta((size_t)M);
  if (a2) {
    for (int64_t k = 0; k < M; k++)
      GRAN_CHECK(std::isfinite(a2[k]) && std::fabs(a2[k]) < 1.0, GRAN_ERR_ARG,
                 "argument 'a2'[%" PRId64 "] = %g: the first Sonine approximation needs |a2| < 1", k, a2[k]);
    b.assign(a2, a2 + M);
  }
  GRAN_CALL(gran_theory_sonine_rates(mix, T0, b.data(), zeta.data(), nullptr));
  lam.assign((size_t)(2 * M), 0.0);
  c.assign((size_t)(2 * M), 0.0);
  for (int64_t k = 0; k < M; k++) {
    if (std::isinf(tau0)) {
      GRAN_CALL(sonine_modes(mix, T0, k, 0.0, a2 ? b.data() : nullptr, &lam[(size_t)(2 * k)], &c[(size_t)(2 * k)]));
      GRAN_CHECK(std::fabs(zeta[(size_t)k]) <= 1e-3 * std::abs(lam[(size_t)(2 * k)]), GRAN_ERR_DOMAIN,
                 "tau0 = inf needs an elastic mixture at equipartition, but species %" PRId64
                 " has zeta tau_v = %g (use gran_theory_hcs_approx)",
                 k, zeta[(size_t)k] / std::abs(lam[(size_t)(2 * k)]));
    } else {
      GRAN_CHECK(std::fabs(0.5 * zeta[(size_t)k] * tau0 - 1.0) <= 1e-3, GRAN_ERR_DOMAIN,
                 "T0, a2, tau0 are not a homogeneous cooling state of the Sonine rates: species %" PRId64
                 " has zeta tau0/2 = %.6g (tolerance 1e-3; use gran_theory_hcs_approx)",
                 k, 0.5 * zeta[(size_t)k] * tau0);
      GRAN_CALL(sonine_modes(mix, T0, k, zeta[(size_t)k], a2 ? b.data() : nullptr, &lam[(size_t)(2 * k)],
                             &c[(size_t)(2 * k)]));
    }
  }
  return GRAN_SUCCESS;
}

/* Re sum_j c_j g(lam_j tau0 log1p(a e^-v))/lam_j^2 e^v: the TAMSD integrand of tamsd.cpp with the
 * two modes (a = lag/tau0) */
struct TP2 {
  const cd *lam, *c;
  double tau0, a;
};
double tamsd2_integrand(double v, void *p) {
  const TP2 *q = static_cast<const TP2 *>(p);
  const double l = q->tau0 * std::log1p(q->a * std::exp(-v));
  cd sum = 0.0;
  for (int j = 0; j < 2; j++) sum += q->c[j] * g_cplx(q->lam[j] * l) / (q->lam[j] * q->lam[j]);
  return sum.real() * std::exp(v);
}

} // namespace

/**
 * @brief MSD in the HCS in the Maxwellian (Eq. 22, gran_theory_msd_hcs) or the Sonine approximation:
 * the HCS of the first Sonine approximation (T0, a2, tau0 from gran_theory_hcs_approx) and the
 * two-moment velocity correlation, MSD_k = 6 (T_k/m_k) sum_j c_j g(tau0 lam_j log(1 + t/tau0))/lam_j^2.
 * @param[in] a2 M Sonine coefficients of the HCS (NULL: 0); ignored at the Maxwellian level
 * @param[out] msd ntimes*M; msd_total ntimes or NULL (number-weighted, tracers excluded)
 */
GRAN_EXTERN int gran_theory_msd_hcs_approx(const gran_mixture *mix, int approximation, const double *T0,
                                           const double *a2, double tau0, int64_t ntimes, const double *t, double *msd,
                                           double *msd_total) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(approximation == GRAN_THEORY_MAXWELLIAN || approximation == GRAN_THEORY_SONINE, GRAN_ERR_ARG,
               "argument 'approximation' = %d is not a gran_theory_approximation (0 Maxwellian, 1 Sonine)",
               approximation);
    if (approximation == GRAN_THEORY_MAXWELLIAN)
      return gran_theory_msd_hcs(mix, T0, tau0, ntimes, t, msd, msd_total);
    const int64_t M = mix->M;
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' = %" PRId64 " is negative", ntimes);
    if (ntimes > 0) {
      GRAN_CALL(check_times(t, ntimes, "t"));
      GRAN_CHECK_PTR(msd);
    }
    std::vector<cd> lam, c;
    GRAN_CALL(sonine_hcs_modes(mix, T0, a2, tau0, lam, c));
    for (int64_t j = 0; j < ntimes; j++)
      for (int64_t k = 0; k < M; k++) {
        cd sum = 0.0;
        const double L = std::isinf(tau0) ? t[j] : tau0 * std::log1p(t[j] / tau0); /* reduced time */
        for (int q = 0; q < 2; q++) {
          const cd l = lam[(size_t)(2 * k + q)];
          sum += c[(size_t)(2 * k + q)] * g_cplx(l * L) / (l * l);
        }
        msd[j * M + k] = 6.0 * T0[k] / mix->m[(size_t)k] * sum.real();
        GRAN_CHECK(std::isfinite(msd[j * M + k]), GRAN_ERR_NUMERIC,
                   "Sonine MSD of species %" PRId64 " at t = %g is not finite", k, t[j]);
      }
    if (msd_total && ntimes > 0) {
      double ntot = 0.0;
      for (int64_t k = 0; k < M; k++) ntot += mix->n[(size_t)k];
      for (int64_t j = 0; j < ntimes; j++) {
        double s = 0.0;
        for (int64_t k = 0; k < M; k++)
          if (mix->n[(size_t)k] > 0.0) s += mix->n[(size_t)k] * msd[j * M + k];
        msd_total[j] = s / ntot;
      }
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Diffusion coefficients D_k = (T_k/m_k) sum_j c_j/lam_j at temperatures T (a2 may be NULL),
 * zeta the cooling rates (NULL: the Maxwellian xi_k at T) in the Sonine approximation; the
 * Maxwellian level gives D_k = T_k tau_v,k/m_k (Eq. 8 with Eq. 11).
 */
GRAN_EXTERN int gran_theory_diffusion_approx(const gran_mixture *mix, int approximation, const double *T,
                                             const double *a2, const double *zeta, double *D) {
  GRAN_TRY {
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(approximation == GRAN_THEORY_MAXWELLIAN || approximation == GRAN_THEORY_SONINE, GRAN_ERR_ARG,
               "argument 'approximation' = %d is not a gran_theory_approximation (0 Maxwellian, 1 Sonine)",
               approximation);
    GRAN_CALL(check_array(T, mix->M, "T", 1));
    GRAN_CHECK_PTR(D);
    const int64_t M = mix->M;
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "mixture 'mix' has viscoelastic restitution: the diffusion coefficients here are for constant or "
               "matrix restitution (use gran_theory_msd)");
    if (approximation == GRAN_THEORY_MAXWELLIAN) {
      GRAN_CALL(inv_tau_v(mix, T, D));
      for (int64_t k = 0; k < M; k++) D[k] = T[k] / (mix->m[(size_t)k] * D[k]);
      return GRAN_SUCCESS;
    }
    for (int64_t k = 0; k < M; k++) {
      GRAN_CHECK(!a2 || (std::isfinite(a2[k]) && std::fabs(a2[k]) < 1.0), GRAN_ERR_ARG,
                 "argument 'a2'[%" PRId64 "] = %g: the first Sonine approximation needs |a2| < 1", k, a2[k]);
      GRAN_CHECK(!zeta || std::isfinite(zeta[k]), GRAN_ERR_ARG, "argument 'zeta'[%" PRId64 "] = %g is not finite", k,
                 zeta[k]);
    }
    for (int64_t k = 0; k < M; k++) {
      cd lam[2], c[2];
      GRAN_CALL(sonine_modes(mix, T, k, zeta ? zeta[k] : NAN, a2, lam, c));
      D[k] = T[k] / mix->m[(size_t)k] * (c[0] / lam[0] + c[1] / lam[1]).real();
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief TAMSD in the HCS (Eq. 26-27) in either approximation: Maxwellian = gran_theory_tamsd;
 * Sonine: T0, a2, tau0 of gran_theory_hcs_approx and the two-moment velocity correlation,
 *   TAMSD_k = 6 (T_k/m_k) tau0/(t - D) int_0^V Re sum_j c_j g(lam_j tau0 log1p((D/tau0) e^-v))/lam_j^2 e^v dv
 * (GSL QAG, V = log1p((t - D)/tau0)); D = t gives MSD(t); tau0 = inf: MSD(D).
 * @param[out] tamsd nlag*M, row-major [lag][species]
 */
GRAN_EXTERN int gran_theory_tamsd_approx(const gran_mixture *mix, int approximation, const double *T0,
                                         const double *a2, double tau0, double t_meas, int64_t nlag,
                                         const double *lag, double rtol, double *tamsd) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(approximation == GRAN_THEORY_MAXWELLIAN || approximation == GRAN_THEORY_SONINE, GRAN_ERR_ARG,
               "argument 'approximation' = %d is not a gran_theory_approximation (0 Maxwellian, 1 Sonine)",
               approximation);
    if (approximation == GRAN_THEORY_MAXWELLIAN)
      return gran_theory_tamsd(mix, T0, tau0, t_meas, nlag, lag, rtol, tamsd);
    GRAN_CALL(check_tamsd_args(mix, T0, tau0, t_meas, nlag, lag, rtol)); /* the Maxwellian TAMSD's checks */
    if (nlag > 0) GRAN_CHECK_PTR(tamsd);
    std::vector<cd> lam, c;
    GRAN_CALL(sonine_hcs_modes(mix, T0, a2, tau0, lam, c));
    const int64_t M = mix->M;
    gsl_integration_workspace *w = gsl_integration_workspace_alloc(1000);
    GRAN_CHECK(w != nullptr, GRAN_ERR_NOMEM, "cannot allocate a GSL integration workspace");
    int ret = GRAN_SUCCESS;
    for (int64_t j = 0; j < nlag && ret == GRAN_SUCCESS; j++) {
      const double dl = lag[j], rest = t_meas - dl;
      for (int64_t k = 0; k < M && ret == GRAN_SUCCESS; k++) {
        const cd *L = &lam[(size_t)(2 * k)], *C = &c[(size_t)(2 * k)];
        const double pref = 6.0 * T0[k] / mix->m[(size_t)k];
        auto msd_of = [&](double red) { /* 6 (T/m) Re sum c g(lam red)/lam^2 */
          cd sum = 0.0;
          for (int q = 0; q < 2; q++) sum += C[q] * g_cplx(L[q] * red) / (L[q] * L[q]);
          return pref * sum.real();
        };
        double val = 0.0;
        if (dl == 0.0) {
          val = 0.0;
        } else if (std::isinf(tau0)) {
          val = msd_of(dl);
        } else {
          const double V = std::log1p(rest / tau0);
          if (rest <= 0.0 || V <= 0.0) {
            val = msd_of(tau0 * std::log1p(dl / tau0)); /* lag = t_meas: MSD(t_meas) */
          } else {
            TP2 P{L, C, tau0, dl / tau0};
            gsl_function F{tamsd2_integrand, &P};
            double r = 0.0, err = 0.0;
            int st = gsl_integration_qag(&F, 0.0, V, 0.0, std::max(rtol, 2e-14), w->limit, GSL_INTEG_GAUSS21, w, &r,
                                         &err);
            if (st == GSL_EROUND) st = GSL_SUCCESS;
            if (st != GSL_SUCCESS)
              ret = GRAN_ERROR(GRAN_ERR_NOCONV, "Sonine TAMSD quadrature (species %" PRId64 ", lag %g) failed: %s", k,
                               dl, gsl_strerror(st));
            val = 6.0 * T0[k] / mix->m[(size_t)k] * tau0 * r / rest;
          }
        }
        if (ret == GRAN_SUCCESS && !std::isfinite(val))
          ret = GRAN_ERROR(GRAN_ERR_NUMERIC, "Sonine TAMSD of species %" PRId64 " at lag %g is not finite", k, dl);
        if (ret == GRAN_SUCCESS) tamsd[j * M + k] = val;
      }
    }
    gsl_integration_workspace_free(w);
    return ret;
  }
  GRAN_CATCH
}
