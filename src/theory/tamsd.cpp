/* tamsd.cpp - time-averaged MSD in the HCS (Bodrova & Osinsky Sec. II E, Eqs. 26-28).
 *
 * The mean squared increment over [t', t' + D] in the HCS (Eq. 4 started at t') is
 *   I(t', D) = 6 D_k tau_v,k g(beta_k l),  l = log(1 + D/(tau0 + t')),  g(y) = y - 1 + e^-y,
 * whose two parts 6 D_k tau0 l and 6 D_k tau_v,k (e^(-beta l) - 1) are the integrands of delta0^2
 * and Xi in Eq. 27. Their sum cancels at lags D << tau_v (ballistic regime: I ~ D^2 while each
 * part ~ D), so the TAMSD is computed as one positive integral of g (GSL QAG), in the variable
 * v = log(1 + t'/tau0) in which the integrand is smooth over any number of decades:
 *   TAMSD = 6 D tau_v tau0/(t - D) int_0^V g(beta log1p((D/tau0) e^-v)) e^v dv,  V = log1p((t-D)/tau0).
 * gran_theory_tamsd_parts returns the two terms separately: delta0^2 in closed form, rewritten
 * without cancellation for D << t (and, by the symmetry D <-> t - D of the bracket, for D -> t):
 *   [...] = d L(t) - B phi2(d/B) - tau0 phi1(d/tau0),  d = min(D, t - D), B = tau0 + t - d,
 *   phi1(z) = (1+z) log1p(z) - z,  phi2(w) = w - log1p(w)  (series for small arguments),
 * and Xi by QAG of expm1(-beta l) in the same variable v. tau0 = inf (eps = 1): I = 6 D tau_v
 * g(D/tau_v) for every t', so TAMSD = MSD(D) exactly (ergodic). */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_integration.h>

#include <algorithm>

namespace {

using namespace gran;

/* (1+z) log1p(z) - z = sum_{n>=2} (-1)^n z^n/(n(n-1)) */
double phi1(double z) {
  if (z > 0.25) return (1.0 + z) * std::log1p(z) - z;
  double zn = z * z, sum = 0.0;
  for (int n = 2; n < 60; n++) {
    const double term = zn / (n * (n - 1.0));
    sum += (n % 2 == 0) ? term : -term;
    if (term < 1e-18 * sum) break;
    zn *= z;
  }
  return sum;
}

/* w - log1p(w) = sum_{n>=2} (-1)^n w^n/n */
double phi2(double w) {
  if (w > 0.25) return w - std::log1p(w);
  double wn = w * w, sum = 0.0;
  for (int n = 2; n < 60; n++) {
    const double term = wn / n;
    sum += (n % 2 == 0) ? term : -term;
    if (term < 1e-18 * sum) break;
    wn *= w;
  }
  return sum;
}

/* delta0^2 / (6 D tau0) (Eq. 27, first term) */
double delta0_unit(double tau0, double t, double lag) {
  if (lag <= 0.0) return 0.0;
  const double d = std::min(lag, t - lag);
  const double B = tau0 + t - d;
  const double L = std::log1p(t / tau0);
  if (d <= 0.0) return L; /* lag = t: MSD(t) term */
  const double br = d * L - B * phi2(d / B) - tau0 * phi1(d / tau0);
  return br / (t - lag);
}

struct TParams {
  double beta, a; /* a = lag/tau0 */
  int which;      /* 0: g (total), 1: expm1 (Xi) */
};

double t_integrand(double v, void *p) {
  const TParams *q = static_cast<const TParams *>(p);
  const double l = std::log1p(q->a * std::exp(-v));
  const double y = q->beta * l;
  const double f = q->which == 0 ? g_fun(y) : std::expm1(-y);
  return f * std::exp(v);
}

int integrate(TParams &P, double V, double rtol, gsl_integration_workspace *w, double *res) {
  gsl_function F{t_integrand, &P};
  double r = 0.0, err = 0.0;
  /* GSL accepts epsrel >= 50 DBL_EPSILON only */
  int st = gsl_integration_qag(&F, 0.0, V, 0.0, std::max(rtol, 2e-14), w->limit, GSL_INTEG_GAUSS21, w, &r, &err);
  if (st == GSL_EROUND) st = GSL_SUCCESS;
  if (st != GSL_SUCCESS)
    return GRAN_ERROR(GRAN_ERR_NOCONV, "TAMSD quadrature (beta = %g, lag/tau0 = %g) failed: %s", P.beta, P.a,
                      gsl_strerror(st));
  *res = r;
  return GRAN_SUCCESS;
}

/* What every TAMSD function needs: the HCS diffusion coefficients D_k and velocity correlation
 * times tau_v,k (hcs_state), and a GSL quadrature workspace (released with the struct). */
struct HcsTamsd {
  std::vector<double> D, tv;
  gsl_integration_workspace *w = nullptr;
  HcsTamsd() = default;
  HcsTamsd(const HcsTamsd &) = delete;
  HcsTamsd &operator=(const HcsTamsd &) = delete;
  ~HcsTamsd() {
    if (w) gsl_integration_workspace_free(w);
  }
  int setup(const gran_mixture *mix, const double *T0, double tau0) {
    D.resize((size_t)mix->M);
    tv.resize((size_t)mix->M);
    GRAN_CALL(hcs_state(mix, T0, tau0, D.data(), tv.data()));
    w = gsl_integration_workspace_alloc(1000);
    GRAN_CHECK(w != nullptr, GRAN_ERR_NOMEM, "cannot allocate a GSL integration workspace");
    return GRAN_SUCCESS;
  }
};

}  // namespace
namespace gran {
int check_tamsd_args(const gran_mixture *mix, const double *T0, double tau0, double t_meas, int64_t nlag,
                     const double *lag, double rtol) {
  GRAN_CALL(check_hcs_args(mix, T0, tau0));
  GRAN_CHECK(std::isfinite(t_meas) && t_meas > 0.0, GRAN_ERR_ARG, "argument 't_meas' = %g must be finite and > 0",
             t_meas);
  GRAN_CHECK(nlag >= 0, GRAN_ERR_ARG, "argument 'nlag' = %" PRId64 " is negative", nlag);
  GRAN_CALL(check_rtol(rtol, "rtol"));
  if (nlag > 0) {
    GRAN_CALL(check_times(lag, nlag, "lag"));
    for (int64_t j = 0; j < nlag; j++)
      GRAN_CHECK(lag[j] <= t_meas, GRAN_ERR_ARG, "argument 'lag[%" PRId64 "]' = %g exceeds t_meas = %g", j, lag[j],
                 t_meas);
  }
  return GRAN_SUCCESS;
}
}  // namespace gran
namespace {

/* Mean squared increment of species k over [t', t' + D] in the HCS (Eq. 4 started at t'). */
inline double increment(double pref, double beta, double tau0, double tv, double tp, double D) {
  if (std::isinf(tau0)) return pref * g_fun(D / tv);
  return pref * g_fun(beta * std::log1p(D / (tau0 + tp)));
}

/* Direct sums up to this many terms; Euler-Maclaurin beyond (its error there is below 1e-12). */
const int64_t kDirectMax = 1 << 16;

} // namespace

/**
 * @brief TAMSD in the HCS as a simulation measures it: averaged over the sample times
 *        t_j = j dt (j = 0 .. nsamples-1) instead of Eq. 27's integral over t'.
 *
 *   <delta^2(L dt)> = 1/(n) sum_{j=0}^{n-1} I(j dt, L dt),  n = nsamples - L,
 * with I the mean squared increment (see the top of this file). Up to 2^16 terms the sum is taken
 * as written; beyond, by Euler-Maclaurin: (1/dt) int_0^{(n-1) dt} I + (I_0 + I_{n-1})/2 +
 * dt/12 (I'_{n-1} - I'_0) (the integral from the same quadrature as gran_theory_tamsd). As dt -> 0 at
 * fixed t_meas = (nsamples-1) dt it tends to Eq. 27 (the difference is about dt/(2 tau0) at small lags).
 * @param[in] dt sampling interval > 0; nsamples >= 2; lag nlag lags in samples, 0 <= lag < nsamples
 * @param[out] tamsd nlag*M, row-major [lag][species]
 */
GRAN_EXTERN int gran_theory_tamsd_sampled(const gran_mixture *mix, const double *T0, double tau0, double dt,
                                          int64_t nsamples, int64_t nlag, const int64_t *lag, double rtol,
                                          double *tamsd) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CHECK(std::isfinite(dt) && dt > 0.0, GRAN_ERR_ARG, "argument 'dt' = %g must be finite and > 0", dt);
    GRAN_CHECK(nsamples >= 2, GRAN_ERR_ARG, "argument 'nsamples' = %" PRId64 " must be >= 2", nsamples);
    const double t_meas = dt * (double)(nsamples - 1);
    GRAN_CALL(check_tamsd_args(mix, T0, tau0, t_meas, 0, nullptr, rtol));
    GRAN_CHECK(nlag >= 0, GRAN_ERR_ARG, "argument 'nlag' = %" PRId64 " is negative", nlag);
    if (nlag == 0) return GRAN_SUCCESS;
    GRAN_CHECK_PTR(lag);
    GRAN_CHECK_PTR(tamsd);
    for (int64_t j = 0; j < nlag; j++)
      GRAN_CHECK(lag[j] >= 0 && lag[j] < nsamples, GRAN_ERR_ARG,
                 "argument 'lag[%" PRId64 "]' = %" PRId64 " outside [0, nsamples = %" PRId64 ")", j, lag[j], nsamples);
    const int64_t M = mix->M;
    HcsTamsd st;
    GRAN_CALL(st.setup(mix, T0, tau0));
    const std::vector<double> &D = st.D, &tv = st.tv;
    gsl_integration_workspace *const w = st.w;
    int ret = GRAN_SUCCESS;
    for (int64_t j = 0; j < nlag && ret == GRAN_SUCCESS; j++) {
      const int64_t L = lag[j], n = nsamples - L;
      const double Dl = dt * (double)L, rest = dt * (double)(n - 1);
      for (int64_t k = 0; k < M && ret == GRAN_SUCCESS; k++) {
        const double pref = 6.0 * D[(size_t)k] * tv[(size_t)k], tvk = tv[(size_t)k];
        const double beta = std::isinf(tau0) ? 0.0 : tau0 / tvk;
        double val = 0.0;
        if (L == 0) {
          val = 0.0;
        } else if (n <= kDirectMax || std::isinf(tau0)) {
          if (std::isinf(tau0)) {
            val = increment(pref, beta, tau0, tvk, 0.0, Dl); /* stationary: every term is the same */
          } else {
            double sum = 0.0, c = 0.0; /* Neumaier */
            for (int64_t i = 0; i < n; i++) {
              const double x = increment(pref, beta, tau0, tvk, dt * (double)i, Dl), t = sum + x;
              c += std::fabs(sum) >= std::fabs(x) ? (sum - t) + x : (x - t) + sum;
              sum = t;
            }
            val = (sum + c) / (double)n;
          }
        } else {
          TParams P{beta, Dl / tau0, 0};
          double J = 0.0;
          ret = integrate(P, std::log1p(rest / tau0), rtol, w, &J);
          const double integral = pref * tau0 * J; /* int_0^rest I(t', Dl) dt' */
          const double i0 = increment(pref, beta, tau0, tvk, 0.0, Dl);
          const double i1 = increment(pref, beta, tau0, tvk, rest, Dl);
          const double h = 1e-4 * (tau0 + rest);
          auto dI = [&](double tp) {
            return (increment(pref, beta, tau0, tvk, tp + h, Dl) - increment(pref, beta, tau0, tvk, std::max(tp - h, 0.0), Dl)) /
                   (tp + h - std::max(tp - h, 0.0));
          };
          val = (integral / dt + 0.5 * (i0 + i1) + dt / 12.0 * (dI(rest) - dI(0.0))) / (double)n;
        }
        tamsd[j * M + k] = val;
      }
    }
    return ret;
  }
  GRAN_CATCH
}

/**
 * @brief TAMSD in the HCS (Eq. 26-27) over the measurement time t_meas, for nlag lags.
 * @param[in] T0, tau0 HCS (gran_theory_hcs; tau0 = inf for an elastic mixture)
 * @param[in] lag nlag lags in [0, t_meas]
 * @param[in] rtol relative tolerance of the GSL quadrature, in [1e-14, 0.1]
 * @param[out] tamsd nlag*M, row-major [lag][species]
 */
GRAN_EXTERN int gran_theory_tamsd(const gran_mixture *mix, const double *T0, double tau0, double t_meas, int64_t nlag,
                                  const double *lag, double rtol, double *tamsd) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_tamsd_args(mix, T0, tau0, t_meas, nlag, lag, rtol));
    if (nlag == 0) return GRAN_SUCCESS;
    GRAN_CHECK_PTR(tamsd);
    const int64_t M = mix->M;
    HcsTamsd st;
    GRAN_CALL(st.setup(mix, T0, tau0));
    const std::vector<double> &D = st.D, &tv = st.tv;
    gsl_integration_workspace *const w = st.w;
    int ret = GRAN_SUCCESS;
    for (int64_t j = 0; j < nlag && ret == GRAN_SUCCESS; j++) {
      const double dl = lag[j], rest = t_meas - dl;
      for (int64_t k = 0; k < M && ret == GRAN_SUCCESS; k++) {
        const double pref = 6.0 * D[(size_t)k] * tv[(size_t)k];
        double val;
        if (dl == 0.0) {
          val = 0.0;
        } else if (std::isinf(tau0)) {
          val = pref * g_fun(dl / tv[(size_t)k]);
        } else {
          const double beta = tau0 / tv[(size_t)k];
          const double V = std::log1p(rest / tau0);
          TParams P{beta, dl / tau0, 0};
          if (rest <= 0.0 || V <= 0.0) {
            val = pref * g_fun(beta * std::log1p(P.a)); /* lag = t_meas: MSD(t_meas) */
          } else {
            double J = 0.0;
            ret = integrate(P, V, rtol, w, &J);
            val = pref * tau0 * J / rest;
          }
        }
        tamsd[j * M + k] = val;
      }
    }
    return ret;
  }
  GRAN_CATCH
}

/**
 * @brief The two terms of Eq. 27 separately: delta0^2 (closed form) and Xi (GSL QAG).
 * @param[out] delta0, xi nlag*M each (either may be NULL)
 */
GRAN_EXTERN int gran_theory_tamsd_parts(const gran_mixture *mix, const double *T0, double tau0, double t_meas,
                                        int64_t nlag, const double *lag, double rtol, double *delta0, double *xi) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_tamsd_args(mix, T0, tau0, t_meas, nlag, lag, rtol));
    if (nlag == 0 || (!delta0 && !xi)) return GRAN_SUCCESS;
    const int64_t M = mix->M;
    HcsTamsd st;
    GRAN_CALL(st.setup(mix, T0, tau0));
    const std::vector<double> &D = st.D, &tv = st.tv;
    gsl_integration_workspace *const w = st.w;
    int ret = GRAN_SUCCESS;
    for (int64_t j = 0; j < nlag && ret == GRAN_SUCCESS; j++) {
      const double dl = lag[j], rest = t_meas - dl;
      for (int64_t k = 0; k < M && ret == GRAN_SUCCESS; k++) {
        double d0, x;
        if (dl == 0.0) {
          d0 = x = 0.0;
        } else if (std::isinf(tau0)) { /* tau0 -> inf: delta0 -> 6 D lag, Xi -> 6 D tau_v (e^(-lag/tau_v) - 1) */
          d0 = 6.0 * D[(size_t)k] * dl;
          x = 6.0 * D[(size_t)k] * tv[(size_t)k] * std::expm1(-dl / tv[(size_t)k]);
        } else {
          const double beta = tau0 / tv[(size_t)k];
          d0 = 6.0 * D[(size_t)k] * tau0 * delta0_unit(tau0, t_meas, dl);
          const double V = std::log1p(rest / tau0);
          TParams P{beta, dl / tau0, 1};
          if (rest <= 0.0 || V <= 0.0) {
            x = 6.0 * D[(size_t)k] * tv[(size_t)k] * std::expm1(-beta * std::log1p(P.a));
          } else {
            double J = 0.0;
            if (xi) ret = integrate(P, V, rtol, w, &J);
            x = 6.0 * D[(size_t)k] * tv[(size_t)k] * tau0 * J / rest;
          }
        }
        if (delta0) delta0[j * M + k] = d0;
        if (xi) xi[j * M + k] = x;
      }
    }
    return ret;
  }
  GRAN_CATCH
}
