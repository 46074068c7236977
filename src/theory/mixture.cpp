/* mixture.cpp - the mixture of the kinetic theory: species, restitution model, g2 (Bodrova & Osinsky Sec. II).
 * Pair matrices are stored only when a matrix is given; otherwise pair values come from scalars. */
#include "theory/theory_impl.h"

#include <gsl/gsl_errno.h>

#include <cinttypes>
#include <cstdio>

namespace gran {

int check_mixture(const gran_mixture *mix, const char *name) {
  if (mix == nullptr) return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s' (mixture) is NULL", name);
  if (mix->M < 1) return GRAN_ERROR(GRAN_ERR_ARG, "mixture '%s' is empty (M = 0)", name);
  return GRAN_SUCCESS;
}

int check_array(const double *a, int64_t n, const char *name, int positive) {
  if (a == nullptr) return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s' is NULL", name);
  for (int64_t i = 0; i < n; i++) {
    const double v = a[i];
    if (!std::isfinite(v))
      return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s[%" PRId64 "]' is not finite (%g)", name, i, v);
    if (positive ? !(v > 0.0) : !(v >= 0.0))
      return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s[%" PRId64 "]' = %g must be %s", name, i, v,
                        positive ? "> 0" : ">= 0");
  }
  return GRAN_SUCCESS;
}

int check_times(const double *t, int64_t n, const char *name) { return check_array(t, n, name, 0); }

int check_output_times(int64_t ntimes, const double *t, const void *out, const char *out_name) {
  if (ntimes < 0) return GRAN_ERROR(GRAN_ERR_ARG, "argument 'ntimes' = %" PRId64 " is negative", ntimes);
  if (ntimes == 0) return GRAN_SUCCESS;
  GRAN_CALL(check_times(t, ntimes, "t"));
  if (!out) return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s' is NULL", out_name);
  return GRAN_SUCCESS;
}

int check_rtol(double rtol, const char *name) {
  if (!(std::isfinite(rtol) && rtol >= 1e-14 && rtol <= 0.1))
    return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s' = %g must lie in [1e-14, 0.1]", name, rtol);
  return GRAN_SUCCESS;
}

} // namespace gran

using namespace gran;

namespace {

int check_symmetric(const double *a, int64_t M, const char *name, double lo, double hi, int lo_open) {
  for (int64_t i = 0; i < M; i++)
    for (int64_t k = 0; k < M; k++) {
      const double v = a[i * M + k];
      if (!std::isfinite(v))
        return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s[%" PRId64 "*M+%" PRId64 "]' is not finite (%g)", name,
                          i, k, v);
      if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi))
        return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s[%" PRId64 "*M+%" PRId64 "]' = %g outside %s%g, %g]",
                          name, i, k, v, lo_open ? "(" : "[", lo, hi);
      if (k < i && v != a[k * M + i])
        return GRAN_ERROR(GRAN_ERR_ARG, "argument '%s' is not symmetric at (%" PRId64 ", %" PRId64 ")", name, i,
                          k);
    }
  return GRAN_SUCCESS;
}

} // namespace

/**
 * @brief Create a mixture of M species.
 * @param[in] nspecies M >= 1
 * @param[in] mass M masses > 0, or NULL for m_k = k (k = 1..M)
 * @param[in] sigma M diameters > 0, or NULL for sigma_k = k^(1/3)
 * @param[in] density M number densities >= 0 (0 marks a tracer); at least one > 0
 * @param[out] mix new mixture (eps = 1, g2 = 1); release with gran_mixture_destroy
 */
GRAN_EXTERN int gran_mixture_create(int64_t nspecies, const double *mass, const double *sigma,
                                    const double *density, gran_mixture **mix) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CHECK_PTR(mix);
    *mix = nullptr;
    GRAN_CHECK(nspecies >= 1, GRAN_ERR_ARG, "argument 'nspecies' = %" PRId64 ": the mixture is empty (need >= 1)",
               nspecies);
    GRAN_CHECK(nspecies <= (int64_t)1 << 40, GRAN_ERR_ARG, "argument 'nspecies' = %" PRId64 " is too large",
               nspecies);
    if (mass) GRAN_CALL(check_array(mass, nspecies, "mass", 1));
    if (sigma) GRAN_CALL(check_array(sigma, nspecies, "sigma", 1));
    GRAN_CALL(check_array(density, nspecies, "density", 0));
    double ntot = 0.0;
    for (int64_t k = 0; k < nspecies; k++) ntot += density[k];
    GRAN_CHECK(ntot > 0.0, GRAN_ERR_ARG,
               "argument 'density': all densities are zero (at least one species needs n_k > 0)");
    gran_mixture *x = new gran_mixture();
    x->M = nspecies;
    x->m.resize((size_t)nspecies);
    x->sigma.resize((size_t)nspecies);
    x->n.assign(density, density + nspecies);
    for (int64_t k = 0; k < nspecies; k++) {
      x->m[(size_t)k] = mass ? mass[k] : (double)(k + 1);
      x->sigma[(size_t)k] = sigma ? sigma[k] : std::cbrt((double)(k + 1));
    }
    x->model = GRAN_RESTITUTION_CONSTANT;
    x->eps = 1.0;
    x->visco = GRAN_VISCO_CONSTANT;
    x->beta = 0.0;
    x->matA = x->matY = x->matNu = x->rho_pref = 0.0;
    x->g2 = 1.0;
    *mix = x;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Mixture with n_k = n1 k^-theta, m_k = k m1, sigma_k = sigma1 k^(1/3) (k = 1..M).
 */
GRAN_EXTERN int gran_mixture_create_powerlaw(int64_t nspecies, double m1, double sigma1, double n1, double theta,
                                             gran_mixture **mix) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CHECK_PTR(mix);
    *mix = nullptr;
    GRAN_CHECK(nspecies >= 1, GRAN_ERR_ARG, "argument 'nspecies' = %" PRId64 ": the mixture is empty (need >= 1)",
               nspecies);
    GRAN_CHECK(std::isfinite(m1) && m1 > 0, GRAN_ERR_ARG, "argument 'm1' = %g must be finite and > 0", m1);
    GRAN_CHECK(std::isfinite(sigma1) && sigma1 > 0, GRAN_ERR_ARG, "argument 'sigma1' = %g must be finite and > 0",
               sigma1);
    GRAN_CHECK(std::isfinite(n1) && n1 > 0, GRAN_ERR_ARG, "argument 'n1' = %g must be finite and > 0", n1);
    GRAN_CHECK(std::isfinite(theta), GRAN_ERR_ARG, "argument 'theta' is not finite (%g)", theta);
    std::vector<double> m((size_t)nspecies), s((size_t)nspecies), n((size_t)nspecies);
    for (int64_t k = 0; k < nspecies; k++) {
      const double kk = (double)(k + 1);
      m[(size_t)k] = kk * m1;
      s[(size_t)k] = sigma1 * std::cbrt(kk);
      n[(size_t)k] = n1 * std::pow(kk, -theta);
    }
    return gran_mixture_create(nspecies, m.data(), s.data(), n.data(), mix);
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_mixture_destroy(gran_mixture **mix) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    if (mix == nullptr) return GRAN_SUCCESS;
    delete *mix;
    *mix = nullptr;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_mixture_nspecies(const gran_mixture *mix, int64_t *nspecies) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(nspecies);
    *nspecies = mix->M;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_mixture_get(const gran_mixture *mix, double *mass, double *sigma, double *density) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    const size_t bytes = sizeof(double) * (size_t)mix->M;
    if (mass) std::memcpy(mass, mix->m.data(), bytes);
    if (sigma) std::memcpy(sigma, mix->sigma.data(), bytes);
    if (density) std::memcpy(density, mix->n.data(), bytes);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief One eps in [0, 1] for every pair (GRAN_RESTITUTION_CONSTANT). */
GRAN_EXTERN int gran_mixture_set_restitution(gran_mixture *mix, double eps) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(std::isfinite(eps) && eps >= 0.0 && eps <= 1.0, GRAN_ERR_ARG,
               "argument 'eps' = %g outside [0, 1]", eps);
    mix->model = GRAN_RESTITUTION_CONSTANT;
    mix->eps = eps;
    mix->eps_mat.clear();
    mix->eps_mat.shrink_to_fit();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Symmetric M*M matrix of eps_ij in [0, 1] (GRAN_RESTITUTION_MATRIX); copied. */
GRAN_EXTERN int gran_mixture_set_restitution_matrix(gran_mixture *mix, const double *eps) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(eps);
    GRAN_CALL(check_symmetric(eps, mix->M, "eps", 0.0, 1.0, 0));
    mix->eps_mat.assign(eps, eps + mix->M * mix->M);
    mix->model = GRAN_RESTITUTION_MATRIX;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Viscoelastic restitution with one beta >= 0 for every pair. */
GRAN_EXTERN int gran_mixture_set_viscoelastic(gran_mixture *mix, double beta) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(std::isfinite(beta) && beta >= 0.0, GRAN_ERR_ARG, "argument 'beta' = %g must be finite and >= 0",
               beta);
    mix->model = GRAN_RESTITUTION_VISCOELASTIC;
    mix->visco = GRAN_VISCO_CONSTANT;
    mix->beta = beta;
    mix->beta_mat.clear();
    mix->beta_mat.shrink_to_fit();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Viscoelastic restitution with a symmetric M*M matrix beta_ij >= 0; copied. */
GRAN_EXTERN int gran_mixture_set_viscoelastic_matrix(gran_mixture *mix, const double *beta) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(beta);
    GRAN_CALL(check_symmetric(beta, mix->M, "beta", 0.0, HUGE_VAL, 0));
    mix->beta_mat.assign(beta, beta + mix->M * mix->M);
    mix->model = GRAN_RESTITUTION_VISCOELASTIC;
    mix->visco = GRAN_VISCO_MATRIX;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Viscoelastic restitution of one material: beta_ij = (3/2) A (rho/m_eff)^(2/5),
 * rho = 2 Y sqrt(R_eff)/(3 (1 - nu^2)), R_eff = sigma_i sigma_j/(2 (sigma_i + sigma_j)) (radius R = sigma/2).
 * @param[in] A dissipative constant >= 0 (Bodrova & Osinsky Eq. A2); Y Young's modulus > 0; nu Poisson ratio in (-1, 0.5]
 */
GRAN_EXTERN int gran_mixture_set_viscoelastic_material(gran_mixture *mix, double A, double Y, double nu) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(std::isfinite(A) && A >= 0.0, GRAN_ERR_ARG, "argument 'A' = %g must be finite and >= 0", A);
    GRAN_CHECK(std::isfinite(Y) && Y > 0.0, GRAN_ERR_ARG, "argument 'Y' = %g must be finite and > 0", Y);
    GRAN_CHECK(std::isfinite(nu) && nu > -1.0 && nu <= 0.5, GRAN_ERR_ARG, "argument 'nu' = %g outside (-1, 0.5]",
               nu);
    /* beta_ij <= (3/2) A (rho_pref sqrt(max sigma / 2) / (min m / 2))^(2/5) (R_eff <= sigma/2,
     * m_eff >= m/2): finite inputs whose beta overflows are refused here, not as NaN later */
    {
      double smax = 0, mmin = HUGE_VAL;
      for (int64_t k = 0; k < mix->M; k++) {
        smax = std::fmax(smax, mix->sigma[(size_t)k]);
        mmin = std::fmin(mmin, mix->m[(size_t)k]);
      }
      const double rho_pref = 2.0 * Y / (3.0 * (1.0 - nu) * (1.0 + nu));
      const double bmax = 1.5 * A * std::pow(rho_pref * std::sqrt(0.5 * smax) / (0.5 * mmin), 0.4);
      GRAN_CHECK(std::isfinite(rho_pref) && std::isfinite(bmax), GRAN_ERR_DOMAIN,
                 "arguments 'A' = %g, 'Y' = %g, 'nu' = %g give a viscoelastic beta that overflows (%g)", A, Y, nu, bmax);
    }
    mix->model = GRAN_RESTITUTION_VISCOELASTIC;
    mix->visco = GRAN_VISCO_MATERIAL;
    mix->matA = A;
    mix->matY = Y;
    mix->matNu = nu;
    mix->rho_pref = 2.0 * Y / (3.0 * (1.0 - nu) * (1.0 + nu));
    mix->beta_mat.clear();
    mix->beta_mat.shrink_to_fit();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Contact value of the pair correlation, g2 > 0, for every pair. */
GRAN_EXTERN int gran_mixture_set_g2(gran_mixture *mix, double g2) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(std::isfinite(g2) && g2 > 0.0, GRAN_ERR_ARG, "argument 'g2' = %g must be finite and > 0", g2);
    mix->g2 = g2;
    mix->g2_mat.clear();
    mix->g2_mat.shrink_to_fit();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Symmetric M*M matrix of g2_ij > 0; copied. */
GRAN_EXTERN int gran_mixture_set_g2_matrix(gran_mixture *mix, const double *g2) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(g2);
    GRAN_CALL(check_symmetric(g2, mix->M, "g2", 0.0, HUGE_VAL, 1));
    mix->g2_mat.assign(g2, g2 + mix->M * mix->M);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_mixture_restitution_model(const gran_mixture *mix, int *model) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK_PTR(model);
    *model = mix->model;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/**
 * @brief Parameters of the pair (i, k), 0-based.
 * @param[out] eps restitution (constant/matrix models); NaN for the viscoelastic model, whose eps
 *             depends on v_n (gran_viscoelastic_eps_vn)
 * @param[out] beta viscoelastic beta_ik (0 for the other models)
 * @param[out] g2 contact value; any output may be NULL
 */
GRAN_EXTERN int gran_mixture_pair(const gran_mixture *mix, int64_t i, int64_t k, double *eps, double *beta,
                                  double *g2) {
  GRAN_TRY {
    gsl_set_error_handler_off();
    GRAN_CALL(check_mixture(mix, "mix"));
    GRAN_CHECK(i >= 0 && i < mix->M, GRAN_ERR_RANGE, "argument 'i' = %" PRId64 " outside [0, %" PRId64 ")", i,
               mix->M);
    GRAN_CHECK(k >= 0 && k < mix->M, GRAN_ERR_RANGE, "argument 'k' = %" PRId64 " outside [0, %" PRId64 ")", k,
               mix->M);
    if (eps) *eps = mix->model == GRAN_RESTITUTION_VISCOELASTIC ? NAN : mix_eps(mix, i, k);
    if (beta) *beta = mix_beta(mix, i, k);
    if (g2) *g2 = mix_g2(mix, i, k);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
