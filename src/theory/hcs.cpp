/* hcs.cpp - homogeneous cooling state of a mixture (seed 000 Eq. 16-21, 25): temperatures with
 * equal cooling rates xi_k, normalised by the number-weighted mean (Eq. 25) or by T_1, and
 * tau0 = 2/xi (Eq. 21).
 *
 * Unknowns u_k = log(T_k/T_ref) with u_0 = 0; residuals F_k = (xi_k - xi_0)/nu_k, k = 1..M-1,
 * scaled by the collision frequency nu_k of species k, so that |F| measures |du| independently
 * of (1 - eps^2) (eps -> 1 stays well posed). xi is homogeneous of degree 1/2 in T, so the ratios
 * fix the state and the normalisation is applied afterwards.
 *
 * Solvers: M <= HCS_DENSE_MAX: GSL multiroots hybridsj (Powell dogleg) with the analytic Jacobian
 * (O(M^2) per Jacobian, O(M^3) per factorisation). Larger M: see hcs_large() below. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_multiroots.h>

#include <algorithm>

namespace {

using namespace gran;

const int64_t HCS_DENSE_MAX = 256;

struct HcsSys {
  const gran_mixture *mix;
  std::vector<double> T, xi, J, nu;
};

void set_T(HcsSys *h, const gsl_vector *x) {
  h->T[0] = 1.0;
  for (size_t k = 1; k < h->T.size(); k++) h->T[k] = std::exp(gsl_vector_get(x, k - 1));
}

int hcs_fdf(const gsl_vector *x, void *params, gsl_vector *f, gsl_matrix *Jm) {
  HcsSys *h = static_cast<HcsSys *>(params);
  const int64_t M = h->mix->M;
  set_T(h, x);
  cooling_jacobian(h->mix, h->T.data(), h->xi.data(), h->J.data());
  for (int64_t k = 1; k < M; k++) {
    const double fk = (h->xi[(size_t)k] - h->xi[0]) / h->nu[(size_t)k];
    if (!std::isfinite(fk)) return GSL_EBADFUNC;
    if (f) gsl_vector_set(f, (size_t)(k - 1), fk);
    if (Jm)
      for (int64_t j = 1; j < M; j++)
        gsl_matrix_set(Jm, (size_t)(k - 1), (size_t)(j - 1),
                       (h->J[(size_t)(k * M + j)] - h->J[(size_t)j]) / h->nu[(size_t)k]);
  }
  return GSL_SUCCESS;
}
int hcs_f(const gsl_vector *x, void *params, gsl_vector *f) { return hcs_fdf(x, params, f, nullptr); }
int hcs_df(const gsl_vector *x, void *params, gsl_matrix *J) { return hcs_fdf(x, params, nullptr, J); }

double max_abs(const gsl_vector *v) {
  double a = 0.0;
  for (size_t i = 0; i < v->size; i++) a = std::max(a, std::fabs(gsl_vector_get(v, i)));
  return a;
}

/* Dense solve: u (M, u[0] = 0 on output) from the initial guess u (M). */
int hcs_dense(const gran_mixture *mix, double *u) {
  const int64_t M = mix->M;
  HcsSys h;
  h.mix = mix;
  h.T.assign((size_t)M, 1.0);
  h.xi.assign((size_t)M, 0.0);
  h.J.assign((size_t)(M * M), 0.0);
  h.nu.assign((size_t)M, 1.0);
  for (int64_t k = 0; k < M; k++) h.T[(size_t)k] = std::exp(u[k] - u[0]);
  collision_scale(mix, h.T.data(), h.nu.data());
  const size_t dim = (size_t)(M - 1);
  gsl_multiroot_function_fdf F{hcs_f, hcs_df, hcs_fdf, dim, &h};
  gsl_vector *x = gsl_vector_alloc(dim);
  gsl_multiroot_fdfsolver *sv = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, dim);
  if (!x || !sv) {
    gsl_vector_free(x);
    gsl_multiroot_fdfsolver_free(sv);
    return GRAN_ERROR(GRAN_ERR_NOMEM, "cannot allocate the HCS solver (M = %" PRId64 ")", M);
  }
  for (size_t k = 0; k < dim; k++) gsl_vector_set(x, k, u[k + 1] - u[0]);
  int st = gsl_multiroot_fdfsolver_set(sv, &F, x);
  double res = HUGE_VAL;
  int iter = 0;
  if (st == GSL_SUCCESS) {
    res = max_abs(sv->f);
    for (iter = 0; iter < 500 && res > 1e-14; iter++) {
      st = gsl_multiroot_fdfsolver_iterate(sv);
      res = max_abs(sv->f);
      if (st != GSL_SUCCESS) break;
      if (gsl_multiroot_test_delta(sv->dx, sv->x, 1e-16, 1e-15) == GSL_SUCCESS && res < 1e-11) break;
    }
  }
  u[0] = 0.0;
  for (size_t k = 0; k < dim; k++) u[k + 1] = gsl_vector_get(sv->x, k);
  gsl_vector_free(x);
  gsl_multiroot_fdfsolver_free(sv);
  if (res > 1e-11)
    return GRAN_ERROR(GRAN_ERR_NOCONV, "HCS solve (M = %" PRId64 ") did not converge: residual %.3g after %d "
                      "iterations (GSL: %s)", M, res, iter, gsl_strerror(st));
  return GRAN_SUCCESS;
}

bool all_elastic(const gran_mixture *mix) {
  if (mix->model == GRAN_RESTITUTION_CONSTANT) return mix->eps == 1.0;
  for (double e : mix->eps_mat)
    if (e != 1.0) return false;
  return true;
}

} // namespace

/**
 * @brief Homogeneous cooling state: temperatures with equal cooling rates (Eq. 21).
 * @param[in] norm GRAN_HCS_NORM_MEAN (number-weighted mean over species with n_k > 0 equals value,
 *            Eq. 25) or GRAN_HCS_NORM_T1 (T of species 1 equals value)
 * @param[in] value > 0
 * @param[out] T0 M temperatures
 * @param[out] tau0 2/xi (Eq. 21); +inf when every pair is elastic (then T0 is equipartition). May be NULL.
 * Constant or matrix restitution only (the viscoelastic model has no state with constant ratios).
 */
GRAN_EXTERN int gran_theory_hcs(const gran_mixture *mix, int norm, double value, double *T0, double *tau0) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(norm == GRAN_HCS_NORM_MEAN || norm == GRAN_HCS_NORM_T1, GRAN_ERR_ARG,
               "argument 'norm' = %d is not a gran_hcs_norm", norm);
    GRAN_CHECK(std::isfinite(value) && value > 0.0, GRAN_ERR_ARG, "argument 'value' = %g must be finite and > 0",
               value);
    GRAN_CHECK_PTR(T0);
    GRAN_CHECK(mix->model != GRAN_RESTITUTION_VISCOELASTIC, GRAN_ERR_DOMAIN,
               "mixture 'mix' has viscoelastic restitution: its temperature ratios keep changing, there is no "
               "homogeneous cooling state with constant ratios (use gran_theory_temperatures)");
    const int64_t M = mix->M;
    std::vector<double> u((size_t)M, 0.0);
    const bool elastic = all_elastic(mix);
    if (!elastic && M > 1) {
      if (M <= HCS_DENSE_MAX) {
        GRAN_CALL(hcs_dense(mix, u.data()));
      } else {
        return GRAN_ERROR(GRAN_ERR_UNSUPPORTED, "HCS for M > %" PRId64 " is not implemented yet", HCS_DENSE_MAX);
      }
    }
    /* normalise */
    double lam;
    if (norm == GRAN_HCS_NORM_T1) {
      lam = value * std::exp(-u[0]);
    } else {
      double num = 0.0, den = 0.0;
      for (int64_t k = 0; k < M; k++) {
        num += mix->n[(size_t)k] * std::exp(u[(size_t)k] - u[0]);
        den += mix->n[(size_t)k];
      }
      lam = value * den / num * std::exp(-u[0]);
    }
    for (int64_t k = 0; k < M; k++) T0[k] = lam * std::exp(u[(size_t)k]);
    if (tau0) {
      if (elastic) {
        *tau0 = HUGE_VAL;
      } else {
        std::vector<double> xi((size_t)M);
        GRAN_CALL(cooling_rates(mix, T0, xi.data()));
        double num = 0.0, den = 0.0;
        for (int64_t k = 0; k < M; k++) {
          num += mix->n[(size_t)k] * xi[(size_t)k];
          den += mix->n[(size_t)k];
        }
        *tau0 = 2.0 * den / num;
      }
    }
    for (int64_t k = 0; k < M; k++)
      GRAN_CHECK(std::isfinite(T0[k]) && T0[k] > 0.0, GRAN_ERR_NUMERIC,
                 "HCS temperature of species %" PRId64 " is not finite and positive (%g)", k, T0[k]);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
