/* driven.cpp - partial temperatures of a driven mixture: Eq. 13 of Bodrova & Osinsky with a
 * heating term per species (the white-noise thermostat) and the energy exchanged in elastic
 * collisions with a Maxwellian bath held at T_b (the DSMC outline's Eq. 76 with the bath as a
 * species that does not change). Maxwellian level; docs/physics.md, "Bath heating and its first
 * Sonine correction", says what the first Sonine correction adds.
 *
 *   dT_k/dt = -xi_k(T, T_b) T_k + H_k,
 *
 * xi_k the cooling rate of species k in the mixture extended by the bath (pairs k-b elastic, g2 = 1,
 * contact diameter (sigma_k + sigma_b)/2): the same pair formulas as the free mixture. Variables
 * y_k = log T_k, independent variable t (a driven gas tends to a steady state, so the log-time
 * variable of ode.cpp is not needed); GSL odeiv2 msbdf with a forward-difference Jacobian up to
 * kImplicitMax species, rk8pd beyond. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

#include <algorithm>
#include <numeric>

namespace {

using namespace gran;

constexpr int64_t kImplicitMax = 256;

struct Driven {
  gran_mixture aug;       /* the mixture with the bath as species M (when bath) */
  int64_t M = 0;          /* the gas's species */
  bool bath = false;
  std::vector<double> H;  /* heating dT_k/dt */
  std::vector<double> T, xi; /* of the extended mixture (the bath's T stays T_b) */
  int status = GRAN_SUCCESS;
};

/* xi of every gas species at T = exp(y) (the bath at its own T) */
int rates(Driven &d, const double *y, std::vector<double> &T, std::vector<double> &xi) {
  for (int64_t k = 0; k < d.M; k++) {
    if (!std::isfinite(y[k])) return GSL_EBADFUNC;
    T[(size_t)k] = std::exp(y[k]);
  }
  const int st = cooling_rates(&d.aug, T.data(), xi.data());
  if (st) {
    d.status = st;
    return GSL_EBADFUNC;
  }
  return GSL_SUCCESS;
}

int rhs(double, const double y[], double f[], void *params) {
  Driven &d = *static_cast<Driven *>(params);
  const int st = rates(d, y, d.T, d.xi);
  if (st != GSL_SUCCESS) return st;
  for (int64_t k = 0; k < d.M; k++) f[k] = -d.xi[(size_t)k] + d.H[(size_t)k] / d.T[(size_t)k];
  return GSL_SUCCESS;
}

int jac(double t, const double y[], double *dfdy, double dfdt[], void *params) {
  Driven &d = *static_cast<Driven *>(params);
  const int64_t M = d.M;
  std::vector<double> f0((size_t)M), f1((size_t)M), yy(y, y + M);
  if (rhs(t, y, f0.data(), params) != GSL_SUCCESS) return GSL_EBADFUNC;
  for (int64_t j = 0; j < M; j++) {
    const double h = 1e-7 * std::max(1.0, std::fabs(y[j]));
    yy[(size_t)j] = y[j] + h;
    if (rhs(t, yy.data(), f1.data(), params) != GSL_SUCCESS) return GSL_EBADFUNC;
    yy[(size_t)j] = y[j];
    for (int64_t k = 0; k < M; k++) dfdy[k * M + j] = (f1[(size_t)k] - f0[(size_t)k]) / h;
  }
  for (int64_t k = 0; k < M; k++) dfdt[k] = 0.0;
  return GSL_SUCCESS;
}

/* The mixture extended by the bath as species M: n_b, m_b, sigma_b; restitution 1 and g2 1 for the
 * bath pairs (matrix forms of the gas's own restitution, beta and g2 where needed). */
void extend(const gran_mixture *mix, double nb, double mb, double sb, gran_mixture &a) {
  const int64_t M = mix->M, A = M + 1;
  a = *mix;
  a.M = A;
  a.m.push_back(mb);
  a.sigma.push_back(sb);
  a.n.push_back(nb);
  auto idx = [A](int64_t k, int64_t i) { return (size_t)(k * A + i); };
  if (mix->model != GRAN_RESTITUTION_VISCOELASTIC) {
    a.model = GRAN_RESTITUTION_MATRIX;
    a.eps_mat.assign((size_t)(A * A), 1.0);
    for (int64_t k = 0; k < M; k++)
      for (int64_t i = 0; i < M; i++) a.eps_mat[idx(k, i)] = mix_eps(mix, k, i);
  } else { /* beta = 0: eps = 1 */
    a.visco = GRAN_VISCO_MATRIX;
    a.beta_mat.assign((size_t)(A * A), 0.0);
    for (int64_t k = 0; k < M; k++)
      for (int64_t i = 0; i < M; i++) a.beta_mat[idx(k, i)] = mix_beta(mix, k, i);
  }
  a.g2_mat.assign((size_t)(A * A), 1.0);
  for (int64_t k = 0; k < M; k++)
    for (int64_t i = 0; i < M; i++) a.g2_mat[idx(k, i)] = mix_g2(mix, k, i);
}

}  // namespace

/**
 * @brief T_k(t) of a driven mixture: Eq. 13 with a heating rate per species and a Maxwellian bath.
 * @param[in] T0 M initial temperatures > 0
 * @param[in] heating M heating rates dT_k/dt >= 0 (the white-noise thermostat), or NULL for none
 * @param[in] bath_density bath number density n_b >= 0 (0: no bath; then the other bath values are not used)
 * @param[in] bath_mass bath particle mass m_b > 0, bath_T its temperature >= 0, bath_sigma its diameter >= 0
 * @param[in] ntimes >= 0 output times t >= 0 (any order)
 * @param[in] rtol relative error of T, in [1e-14, 0.1]
 * @param[out] T ntimes*M temperatures, row-major [time][species]
 */
GRAN_EXTERN int gran_theory_temperatures_driven(const gran_mixture *mix, const double *T0, const double *heating,
                                                double bath_density, double bath_mass, double bath_T,
                                                double bath_sigma, int64_t ntimes, const double *t, double rtol,
                                                double *T) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    const int64_t M = mix->M;
    GRAN_CALL(check_array(T0, M, "T0", 1));
    if (heating) {
      for (int64_t k = 0; k < M; k++)
        GRAN_CHECK(std::isfinite(heating[k]) && heating[k] >= 0, GRAN_ERR_ARG,
                   "argument 'heating'[%" PRId64 "] = %g must be finite and >= 0", k, heating[k]);
    }
    GRAN_CHECK(std::isfinite(bath_density) && bath_density >= 0, GRAN_ERR_ARG,
               "argument 'bath_density' = %g must be finite and >= 0", bath_density);
    const bool bath = bath_density > 0;
    if (bath) {
      GRAN_CHECK(std::isfinite(bath_mass) && bath_mass > 0, GRAN_ERR_ARG,
                 "argument 'bath_mass' = %g must be finite and > 0", bath_mass);
      GRAN_CHECK(std::isfinite(bath_T) && bath_T >= 0, GRAN_ERR_ARG, "argument 'bath_T' = %g must be finite and >= 0",
                 bath_T);
      GRAN_CHECK(std::isfinite(bath_sigma) && bath_sigma >= 0, GRAN_ERR_ARG,
                 "argument 'bath_sigma' = %g must be finite and >= 0", bath_sigma);
    }
    GRAN_CALL(check_output_times(ntimes, t, T, "T"));
    GRAN_CALL(check_rtol(rtol, "rtol"));
    if (ntimes == 0) return GRAN_SUCCESS;

    Driven d;
    d.M = M;
    d.bath = bath;
    if (bath) extend(mix, bath_density, bath_mass, bath_sigma, d.aug);
    else d.aug = *mix;
    d.H.assign((size_t)M, 0.0);
    if (heating) std::copy(heating, heating + M, d.H.begin());
    const size_t A = (size_t)d.aug.M;
    d.T.assign(A, bath ? bath_T : 0.0);
    d.xi.assign(A, 0.0);

    std::vector<int64_t> idx((size_t)ntimes);
    std::iota(idx.begin(), idx.end(), (int64_t)0);
    std::stable_sort(idx.begin(), idx.end(), [&](int64_t a, int64_t b) { return t[a] < t[b]; });
    std::vector<double> y((size_t)M);
    for (int64_t k = 0; k < M; k++) y[(size_t)k] = std::log(T0[k]);
    gsl_odeiv2_system sys = {rhs, jac, (size_t)M, &d};
    const bool implicit = M <= kImplicitMax;
    /* the local tolerance is rtol/100 (absolute in log T): the global error of a gas heated over
     * 1e3 of its own heating times stays below rtol (t420) */
    const double tol = std::max(1e-15, 0.01 * rtol);
    gsl_odeiv2_driver *drv = gsl_odeiv2_driver_alloc_y_new(&sys, implicit ? gsl_odeiv2_step_msbdf : gsl_odeiv2_step_rk8pd,
                                                           1e-6, tol, 0.0);
    GRAN_CHECK(drv != nullptr, GRAN_ERR_NOMEM, "cannot allocate the ODE driver for %" PRId64 " species", M);
    gsl_odeiv2_driver_set_nmax(drv, 100000000);
    double tc = 0.0;
    int st = GRAN_SUCCESS;
    for (int64_t j = 0; j < ntimes && st == GRAN_SUCCESS; j++) {
      const int64_t o = idx[(size_t)j];
      if (t[o] > tc) {
        const int g = gsl_odeiv2_driver_apply(drv, &tc, t[o], y.data());
        if (g != GSL_SUCCESS)
          st = d.status != GRAN_SUCCESS ? d.status
                                        : GRAN_ERROR(GRAN_ERR_NUMERIC, "driven temperatures: the ODE failed at t = %g (GSL %d)", tc, g);
      }
      for (int64_t k = 0; k < M && st == GRAN_SUCCESS; k++) {
        const double v = std::exp(y[(size_t)k]);
        if (!std::isfinite(v) || v <= 0) st = GRAN_ERROR(GRAN_ERR_NUMERIC, "driven temperatures: T_%" PRId64 " = %g at t = %g", k + 1, v, t[o]);
        T[o * M + k] = v;
      }
    }
    gsl_odeiv2_driver_free(drv);
    return st;
  }
  GRAN_CATCH
}
