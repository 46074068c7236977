/* msd.cpp - mean-squared displacements (Bodrova & Osinsky Sec. II A, C, F):
 *  - HCS closed form Eq. 22, written as MSD_k = 6 D_k tau_v,k g(beta_k log(1 + t/tau0)) with
 *    g(y) = y - 1 + e^-y (no cancellation for t << tau_v, none for huge beta); elastic limit
 *    (tau0 = inf): y = t/tau_v. Total MSD Eq. 3 (number-weighted, tracers excluded).
 *  - Eq. 31 (monodisperse gas, or gas species 1 with tracers only) with tau0, tau_v, D from
 *    Eqs. 7, 8, 29, 30: an independent route to Eq. 22 for M = 1.
 *  - General Eq. 4 from any start and any restitution model: the temperature ODE (ode.cpp) is
 *    integrated once with u_k = int sqrt(T_k/T_k(0)) dt (Eq. 6), dense output by cubic Hermite
 *    interpolation in s = log(1 + t/ts) with steps capped so the interpolation error stays below
 *    the requested tolerance; then for each species and time GSL QAG (Gauss-Kronrod 21) in s1:
 *      MSD_k(t) = 6 int_0^s D_k(s1) [1 - exp(-(u_k(t) - u_k(s1))/w_k(s1))] (ts e^s1) ds1,
 *    w_k = tau_v,k sqrt(T_k/T_k(0)) (Eq. 5 times tau_c(0)); 1 - e^-x as -expm1(-x). The integrand
 *    has a boundary layer of width ~ 1/beta in s at s1 -> s; the interval is split where x = 50. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>
#include <numeric>
#include <string>

namespace gran {

int hcs_state(const gran_mixture *mix, const double *T0, double tau0, double *D, double *tau_v) {
  const int64_t M = mix->M;
  if (mix->model == GRAN_RESTITUTION_VISCOELASTIC)
    return GRAN_ERROR(GRAN_ERR_DOMAIN, "mixture 'mix' is viscoelastic: it has no homogeneous cooling state "
                                      "(use gran_theory_msd, Eq. 4)");
  std::vector<double> xi((size_t)M), d((size_t)M), l((size_t)M), nu((size_t)M);
  cooling_pass(mix, T0, xi.data(), d.data(), l.data(), nu.data());
  if (std::isinf(tau0)) {
    for (int64_t k = 0; k < M; k++)
      if (!(std::fabs(xi[(size_t)k]) <= 1e-3 * nu[(size_t)k]))
        return GRAN_ERROR(GRAN_ERR_DOMAIN, "tau0 = inf needs an elastic mixture at equipartition, but species %" PRId64
                          " has xi/nu = %g (use gran_theory_hcs)", k, xi[(size_t)k] / nu[(size_t)k]);
  } else {
    for (int64_t k = 0; k < M; k++)
      if (!(std::fabs(0.5 * xi[(size_t)k] * tau0 - 1.0) <= 1e-3))
        return GRAN_ERROR(GRAN_ERR_DOMAIN, "T0, tau0 are not a homogeneous cooling state: species %" PRId64
                          " has xi tau0/2 = %.6g (tolerance 1e-3; use gran_theory_hcs)", k, 0.5 * xi[(size_t)k] * tau0);
  }
  GRAN_CALL(inv_tau_v(mix, T0, tau_v));
  for (int64_t k = 0; k < M; k++) {
    tau_v[k] = 1.0 / tau_v[k];
    if (D) D[k] = T0[k] * tau_v[k] / mix->m[(size_t)k];
  }
  return GRAN_SUCCESS;
}

int check_hcs_args(const gran_mixture *mix, const double *T0, double tau0) {
  GRAN_CALL(check_mixture(mix, "mix"));
  GRAN_CALL(check_array(T0, mix->M, "T0", 1));
  GRAN_CHECK(!std::isnan(tau0) && tau0 > 0.0, GRAN_ERR_ARG, "argument 'tau0' = %g must be > 0 (inf: elastic)", tau0);
  return GRAN_SUCCESS;
}

} // namespace gran

using namespace gran;

namespace {

void total(const gran_mixture *mix, int64_t ntimes, const double *msd, double *msd_total) {
  const int64_t M = mix->M;
  double ntot = 0.0;
  for (int64_t k = 0; k < M; k++) ntot += mix->n[(size_t)k];
  for (int64_t j = 0; j < ntimes; j++) {
    double s = 0.0;
    for (int64_t k = 0; k < M; k++)
      if (mix->n[(size_t)k] > 0.0) s += mix->n[(size_t)k] * msd[j * M + k];
    msd_total[j] = s / ntot;
  }
}

/* ---- Eq. 4 ---------------------------------------------------------------------------------- */
/* Eq. 4 levels: the Maxwellian tau_v,k; the two-moment correlation (sonine_modes) at the Maxwellian
 * T(t1) with xi_k and a2 = 0; the first Sonine trajectory (z, u, a2) with the modes at T(t1) and
 * the Sonine zeta_k(t1) (the scaling term -(1/2) dlog T_k/dt of that trajectory), the a2_i(t1) in
 * the correlation (collision integrals and m(0)) when correlation_a2; the second Sonine trajectory (z, u, a2,
 * a3) likewise, with its zeta_k(t1) (a3 enters the cooling rate, not the correlation). */
enum { EQ4_MAXWELL = 0, EQ4_MODES = 1, EQ4_SONINE = 2, EQ4_SONINE2 = 3 };
struct Eq4 {
  const Traj *tr;
  const gran_mixture *mix;
  int64_t k;
  double Ut; /* u_k at the output time */
  std::vector<double> T;
  int status;
  int mode = EQ4_MAXWELL;
  std::vector<double> a2, a3;  /* EQ4_SONINE, EQ4_SONINE2: a2_i(t1) (and a3_i(t1)) */
  bool correlation_a2 = false; /* EQ4_SONINE, EQ4_SONINE2: a2_i(t1) in the correlation */
  std::string message;         /* of the first failure of sonine_modes */
};

/* x(s1) and the integrand at s1 */
double eq4_x(Eq4 *c, double s1, double *val) {
  const Traj &tr = *c->tr;
  const size_t j = traj_locate(tr, s1);
  for (int64_t i = 0; i < tr.M; i++)
    c->T[(size_t)i] = tr.T0[(size_t)i] * std::exp(traj_eval_at(tr, j, s1, (int)i) - 2.0 * s1);
  const double yk = traj_eval_at(tr, j, s1, (int)c->k) - 2.0 * s1; /* log(T_k/T_k(0)) */
  const double uk = traj_eval_at(tr, j, s1, (int)(tr.M + c->k));
  if (c->mode != EQ4_MAXWELL) {
    cd lam[2], cw[2];
    double zk = NAN;
    const double *a2c = nullptr; /* the a2_i(t1) in the correlation (K and m(0)) */
    if (c->mode == EQ4_SONINE || c->mode == EQ4_SONINE2) {
      for (int64_t i = 0; i < tr.M; i++) c->a2[(size_t)i] = traj_eval_at(tr, j, s1, (int)(2 * tr.M + i));
      if (c->mode == EQ4_SONINE2) {
        for (int64_t i = 0; i < tr.M; i++) c->a3[(size_t)i] = traj_eval_at(tr, j, s1, (int)(3 * tr.M + i));
        zk = sonine2_zeta_one(c->mix, c->T.data(), c->a2.data(), c->a3.data(), c->k);
      } else {
        zk = sonine_zeta_one(c->mix, c->T.data(), c->a2.data(), c->k);
      }
      if (c->correlation_a2) a2c = c->a2.data();
    }
    const int st = sonine_modes(c->mix, c->T.data(), c->k, zk, a2c, lam, cw);
    if (st) {
      if (!c->status) c->message = gran_last_error_message(); /* before the quadrature reports its own */
      c->status = st;
      if (val) *val = NAN;
      return NAN;
    }
    const double xr = std::max(0.0, (c->Ut - uk) * std::exp(-0.5 * yk)); /* reduced time since t1 */
    cd sum = 0.0;
    for (int q = 0; q < 2; q++) {
      const cd z = lam[q] * xr; /* 1 - e^-z without cancellation at small z */
      sum += cw[q] / lam[q] * (std::abs(z) < 1e-4 ? z * (1.0 - z * (0.5 - z / 6.0)) : 1.0 - std::exp(-z));
    }
    if (val) *val = c->T[(size_t)c->k] / c->mix->m[(size_t)c->k] * sum.real() * tr.ts * std::exp(s1);
    return xr * std::min(lam[0].real(), lam[1].real());
  }
  double itv = 0.0;
  const int st = inv_tau_v_one(c->mix, c->T.data(), c->k, &itv);
  if (st) {
    if (!c->status) c->message = gran_last_error_message();
    c->status = st;
    if (val) *val = NAN;
    return NAN;
  }
  const double tv = 1.0 / itv;
  const double w = tv * std::exp(0.5 * yk);
  const double x = std::max(0.0, (c->Ut - uk) / w);
  if (val) {
    const double D = c->T[(size_t)c->k] * tv / c->mix->m[(size_t)c->k];
    *val = D * -std::expm1(-x) * tr.ts * std::exp(s1);
  }
  return x;
}

double eq4_integrand(double s1, void *p) {
  double v = 0.0;
  eq4_x(static_cast<Eq4 *>(p), s1, &v);
  return v;
}

int qag(gsl_function *F, double a, double b, double rtol, gsl_integration_workspace *w, double *res) {
  double r = 0.0, err = 0.0;
  *res = 0.0;
  if (!(b > a)) return GRAN_SUCCESS;
  /* GSL accepts epsrel >= 50 DBL_EPSILON only */
  int st = gsl_integration_qag(F, a, b, 0.0, std::max(rtol, 2e-14), w->limit, GSL_INTEG_GAUSS21, w, &r, &err);
  if (st == GSL_EROUND) st = GSL_SUCCESS; /* accuracy limited by rounding: result still usable */
  if (st != GSL_SUCCESS)
    return GRAN_ERROR(GRAN_ERR_NOCONV, "GSL QAG on [%g, %g] failed: %s (estimate %g, error %g)", a, b,
                      gsl_strerror(st), r, err);
  *res = r;
  return GRAN_SUCCESS;
}

} // namespace

/**
 * @brief MSD in the HCS, closed form Eq. 22 (and the total Eq. 3).
 * @param[in] T0 HCS temperatures, tau0 its relaxation time (from gran_theory_hcs; checked:
 *            |xi_k tau0/2 - 1| <= 1e-3, so rounded published values are accepted); tau0 = inf for an
 *            elastic mixture at equipartition
 * @param[out] msd ntimes*M; msd_total ntimes or NULL (number-weighted, tracers excluded)
 */
GRAN_EXTERN int gran_theory_msd_hcs(const gran_mixture *mix, const double *T0, double tau0, int64_t ntimes,
                                    const double *t, double *msd, double *msd_total) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_hcs_args(mix, T0, tau0));
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' = %" PRId64 " is negative", ntimes);
    if (ntimes == 0) return GRAN_SUCCESS;
    GRAN_CALL(check_times(t, ntimes, "t"));
    GRAN_CHECK_PTR(msd);
    const int64_t M = mix->M;
    std::vector<double> D((size_t)M), tv((size_t)M);
    GRAN_CALL(hcs_state(mix, T0, tau0, D.data(), tv.data()));
    for (int64_t j = 0; j < ntimes; j++) {
      for (int64_t k = 0; k < M; k++) {
        const double y = std::isinf(tau0) ? t[j] / tv[(size_t)k] : tau0 / tv[(size_t)k] * std::log1p(t[j] / tau0);
        msd[j * M + k] = 6.0 * D[(size_t)k] * tv[(size_t)k] * g_fun(y);
      }
    }
    if (msd_total) total(mix, ntimes, msd, msd_total);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief MSD of species 1 by Eq. 31 for a monodisperse gas (M = 1, or species 2..M tracers with
 * n_k = 0), constant eps_11: tau_c from Eq. 7, tau0 = 6 tau_c/(1 - eps^2) (Eq. 29),
 * tau_v = 6 tau_c/(1 + eps)^2 (Eq. 30), D = T tau_v/m (Eq. 8).
 * @param[in] T1 temperature of species 1 at t = 0 (> 0)
 * @param[out] msd ntimes values; tau0 (may be NULL): Eq. 29 (inf for eps = 1)
 */
GRAN_EXTERN int gran_theory_msd_mono(const gran_mixture *mix, double T1, int64_t ntimes, const double *t,
                                     double *msd, double *tau0) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(std::isfinite(T1) && T1 > 0.0, GRAN_ERR_ARG, "argument 'T1' = %g must be finite and > 0", T1);
    GRAN_CALL(check_output_times(ntimes, t, msd, "msd"));
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "Eq. 31 needs a constant restitution coefficient (mixture 'mix' is viscoelastic)");
    GRAN_CHECK(mix->n[0] > 0.0, GRAN_ERR_DOMAIN, "Eq. 31: species 1 of 'mix' must have n_1 > 0");
    for (int64_t k = 1; k < mix->M; k++)
      GRAN_CHECK(mix->n[(size_t)k] == 0.0, GRAN_ERR_DOMAIN,
                 "Eq. 31 holds for a monodisperse gas: species %" PRId64 " of 'mix' has n = %g (must be a tracer)", k + 1,
                 mix->n[(size_t)k]);
    const double eps = mix_eps(mix, 0, 0), s1 = mix->sigma[0], m1 = mix->m[0];
    const double tc = 1.0 / (4.0 * mix->n[0] * s1 * s1 * mix_g2(mix, 0, 0) * std::sqrt(M_PI * T1 / m1)); /* Eq. 7 */
    const double omeps2 = (1.0 - eps) * (1.0 + eps);
    const double t0 = omeps2 > 0.0 ? 6.0 * tc / omeps2 : HUGE_VAL;            /* Eq. 29 */
    const double tv = 6.0 * tc / ((1.0 + eps) * (1.0 + eps));                  /* Eq. 30 */
    const double D = T1 * tv / m1;                                            /* Eq. 8 */
    if (tau0) *tau0 = t0;
    /* Eq. 31: 36 D tc [L/(1-eps^2) + ((1+t/tau0)^(-(1+eps)^2/(1-eps^2)) - 1)/(1+eps)^2]
     *       = 36 D tc/(1+eps)^2 g(y),  y = (1+eps)/(1-eps) L,  L = log(1 + t/tau0) */
    for (int64_t j = 0; j < ntimes; j++) {
      const double y = std::isinf(t0) ? t[j] / tv : (1.0 + eps) / (1.0 - eps) * std::log1p(t[j] / t0);
      msd[j] = 36.0 * D * tc / ((1.0 + eps) * (1.0 + eps)) * g_fun(y);
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief MSD by numerical integration of Eq. 4 from any start T0 and any restitution model.
 * @param[in] rtol relative tolerance of the ODE and of the quadrature, in [1e-14, 0.1]
 * @param[out] msd ntimes*M; msd_total ntimes or NULL
 */
namespace {
int msd_eq4(const gran_mixture *mix, const double *T0, int64_t ntimes, const double *t, double rtol, double *msd,
            double *msd_total, int mode, const double *a20, bool correlation_a2, const double *a30 = nullptr);
}

GRAN_EXTERN int gran_theory_msd(const gran_mixture *mix, const double *T0, int64_t ntimes, const double *t,
                                double rtol, double *msd, double *msd_total) {
  return msd_eq4(mix, T0, ntimes, t, rtol, msd, msd_total, EQ4_MAXWELL, nullptr, false);
}

/**
 * @brief MSD by Eq. 4 in either approximation: GRAN_THEORY_SONINE replaces the single relaxation
 * time tau_v,k(t1) by the two-moment correlation at T(t1) (sonine_diffusion.cpp), T_k(t) Maxwellian.
 */
GRAN_EXTERN int gran_theory_msd_approx(const gran_mixture *mix, int approximation, const double *T0, int64_t ntimes,
                                       const double *t, double rtol, double *msd, double *msd_total) {
  GRAN_TRY {
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(approximation == GRAN_THEORY_MAXWELLIAN || approximation == GRAN_THEORY_SONINE, GRAN_ERR_ARG,
               "argument 'approximation' = %d is not a gran_theory_approximation (0 Maxwellian, 1 Sonine)",
               approximation);
    GRAN_CHECK(approximation == GRAN_THEORY_MAXWELLIAN || mix->model != GRAN_RESTITUTION_VISCOELASTIC,
               GRAN_ERR_DOMAIN,
               "mixture 'mix' has viscoelastic restitution: the Sonine MSD is implemented for constant or matrix "
               "restitution only");
    return msd_eq4(mix, T0, ntimes, t, rtol, msd, msd_total,
                   approximation == GRAN_THEORY_SONINE ? EQ4_MODES : EQ4_MAXWELL, nullptr, false);
  }
  GRAN_CATCH
}

/**
 * @brief MSD by Eq. 4 on the first Sonine trajectory: T_k(t) and a2_k(t) from (T0, a20) as
 * gran_theory_temperatures_approx, the two-moment correlation at T(t1) with the Sonine zeta_k(t1)
 * and, when correlation_a2 = 1, the a2_i(t1) of all species in it (the partners' Sonine f_i and the
 * weight f_k in its collision integrals, a2_k(t1) in its initial fourth moment; 0: a2 = 0 in the
 * correlation). From a Sonine HCS with correlation_a2 = 1 it equals gran_theory_msd_hcs_approx.
 * @param[in] a20 M start values, |a2_k| < 1 (NULL: 0, a Maxwellian start)
 * @param[in] correlation_a2 0 or 1
 */
GRAN_EXTERN int gran_theory_msd_sonine(const gran_mixture *mix, const double *T0, const double *a20,
                                       int correlation_a2, int64_t ntimes, const double *t, double rtol, double *msd,
                                       double *msd_total) {
  GRAN_TRY {
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(correlation_a2 == 0 || correlation_a2 == 1, GRAN_ERR_ARG,
               "argument 'correlation_a2' = %d must be 0 or 1", correlation_a2);
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "mixture 'mix' has viscoelastic restitution: the Sonine MSD is implemented for constant or matrix "
               "restitution only");
    if (a20)
      for (int64_t k = 0; k < mix->M; k++)
        GRAN_CHECK(std::isfinite(a20[k]) && std::fabs(a20[k]) < 1.0, GRAN_ERR_ARG,
                   "argument 'a20'[%" PRId64 "] = %g: the first Sonine approximation needs |a2| < 1", k, a20[k]);
    return msd_eq4(mix, T0, ntimes, t, rtol, msd, msd_total, EQ4_SONINE, a20, correlation_a2 == 1);
  }
  GRAN_CATCH
}

/**
 * @brief MSD by Eq. 4 on the second Sonine trajectory: T_k(t), a2_k(t), a3_k(t) as
 * gran_theory_temperatures_sonine2 from (T0, a20, a30), the two-moment correlation at T(t1) with the
 * second-level zeta_k(t1) and, when correlation_a2 = 1, the a2_i(t1) in it (as gran_theory_msd_sonine;
 * a3 enters through the temperatures and the cooling rate).
 * @param[in] a20, a30 M start values each, |a| < 1 (NULL: 0)
 * @param[in] correlation_a2 0 or 1
 */
GRAN_EXTERN int gran_theory_msd_sonine2(const gran_mixture *mix, const double *T0, const double *a20,
                                        const double *a30, int correlation_a2, int64_t ntimes, const double *t,
                                        double rtol, double *msd, double *msd_total) {
  GRAN_TRY {
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(correlation_a2 == 0 || correlation_a2 == 1, GRAN_ERR_ARG,
               "argument 'correlation_a2' = %d must be 0 or 1", correlation_a2);
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "mixture 'mix' has viscoelastic restitution: the second Sonine MSD is implemented for constant or "
               "matrix restitution only");
    if (a20) GRAN_CALL(sonine2_check_coeffs(a20, mix->M, "a20"));
    if (a30) GRAN_CALL(sonine2_check_coeffs(a30, mix->M, "a30"));
    return msd_eq4(mix, T0, ntimes, t, rtol, msd, msd_total, EQ4_SONINE2, a20, correlation_a2 == 1, a30);
  }
  GRAN_CATCH
}

namespace {
int msd_eq4(const gran_mixture *mix, const double *T0, int64_t ntimes, const double *t, double rtol, double *msd,
            double *msd_total, int mode, const double *a20, bool correlation_a2, const double *a30) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CALL(check_array(T0, mix->M, "T0", 1));
    GRAN_CHECK(ntimes >= 0, GRAN_ERR_ARG, "argument 'ntimes' = %" PRId64 " is negative", ntimes);
    GRAN_CALL(check_rtol(rtol, "rtol"));
    if (ntimes == 0) return GRAN_SUCCESS;
    GRAN_CALL(check_times(t, ntimes, "t"));
    GRAN_CHECK_PTR(msd);
    const int64_t M = mix->M;
    Traj tr;
    if (mode == EQ4_SONINE || mode == EQ4_SONINE2) { /* the time scale of traj_init: the shortest collision time at T0 */
      std::vector<double> nu((size_t)M);
      collision_scale(mix, T0, nu.data());
      const double numax = *std::max_element(nu.begin(), nu.end());
      GRAN_CHECK(numax > 0.0 && std::isfinite(numax), GRAN_ERR_NUMERIC,
                 "collision frequencies at T0 are not finite and positive");
      tr.ts = 1.0 / numax;
    } else {
      GRAN_CALL(traj_init(tr, mix, T0, true));
    }
    double smax = 0.0;
    for (int64_t j = 0; j < ntimes; j++) smax = std::max(smax, traj_s_of_t(tr, t[j]));
    /* step cap: cubic Hermite error ~ h^4/384 |y''''|; keep it ~ rtol/10 */
    double hmax = std::min(0.25, std::max(1e-3, 0.5 * std::pow(rtol, 0.25)));
    const double maxnodes = 3e7 / (4.0 * (double)M); /* ~240 MB of dense output */
    if (smax / hmax > maxnodes) {
      hmax = smax / maxnodes;
      gran_warning_add("gran_theory_msd: dense output limited to %.0f nodes (M = %" PRId64 "): step cap %g in log-time",
                       maxnodes, M, hmax);
    }
    const double ode_rtol = std::max(1e-14, 0.1 * rtol);
    if (mode == EQ4_SONINE) GRAN_CALL(sonine_traj_dense(tr, mix, T0, a20, tr.ts, ode_rtol, hmax, smax));
    else if (mode == EQ4_SONINE2) GRAN_CALL(sonine2_traj_dense(tr, mix, T0, a20, a30, tr.ts, ode_rtol, hmax, smax));
    else GRAN_CALL(traj_run(tr, 0, nullptr, nullptr, ode_rtol, true, hmax, smax));
    gsl_integration_workspace *w = gsl_integration_workspace_alloc(2000);
    GRAN_CHECK(w != nullptr, GRAN_ERR_NOMEM, "cannot allocate a GSL integration workspace");
    Eq4 c{&tr, mix, 0, 0.0, std::vector<double>((size_t)M), 0, mode, std::vector<double>((size_t)M, 0.0),
          std::vector<double>((size_t)M, 0.0), correlation_a2, std::string()};
    gsl_function F{eq4_integrand, &c};
    int ret = GRAN_SUCCESS;
    for (int64_t j = 0; j < ntimes && ret == GRAN_SUCCESS; j++) {
      const double s = traj_s_of_t(tr, t[j]);
      for (int64_t k = 0; k < M && ret == GRAN_SUCCESS; k++) {
        c.k = k;
        c.Ut = traj_eval(tr, s, (int)(M + k));
        if (!(s > 0.0)) {
          msd[j * M + k] = 0.0;
          continue;
        }
        /* split where x = 50 (x decreases from x(0) to x(s) = 0) */
        double sc = 0.0;
        const double x0 = eq4_x(&c, 0.0, nullptr);
        if (x0 > 50.0) {
          double lo = 0.0, hi = s;
          for (int it = 0; it < 200 && hi - lo > 1e-15 * s; it++) {
            const double mid = 0.5 * (lo + hi);
            if (eq4_x(&c, mid, nullptr) > 50.0) lo = mid;
            else hi = mid;
          }
          sc = lo;
        }
        double r1 = 0.0, r2 = 0.0;
        ret = qag(&F, 0.0, sc, rtol, w, &r1);
        if (ret == GRAN_SUCCESS && !c.status) ret = qag(&F, sc, s, rtol, w, &r2);
        if (c.status) ret = GRAN_ERROR(c.status, "%s (Eq. 4 at t = %g)", c.message.c_str(), t[j]);
        msd[j * M + k] = 6.0 * (r1 + r2);
        if (ret == GRAN_SUCCESS && !std::isfinite(msd[j * M + k]))
          ret = GRAN_ERROR(GRAN_ERR_NUMERIC, "Eq. 4: non-finite MSD for species %" PRId64 " at t = %g", k, t[j]);
      }
    }
    gsl_integration_workspace_free(w);
    if (ret != GRAN_SUCCESS) return ret;
    if (msd_total) total(mix, ntimes, msd, msd_total);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
}  // namespace
