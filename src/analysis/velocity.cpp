/* velocity.cpp - observables of the velocity distribution: Sonine coefficient a2 and the
 * normalised speed histogram. Velocities are 3n doubles, interleaved (v[3i], v[3i+1], v[3i+2]),
 * taken relative to the mean flow. */
#include "granary_impl.h"

namespace {

int check_velocities(int64_t n, const double *v) {
  GRAN_CHECK(n >= 1, GRAN_ERR_ARG, "argument 'n' = " GRAN_I64_FMT " must be >= 1", n);
  GRAN_CHECK(n <= INT64_MAX / 3, GRAN_ERR_ARG, "argument 'n' = " GRAN_I64_FMT " is too large", n);
  GRAN_CHECK_PTR(v);
  for (int64_t i = 0; i < 3 * n; i++)
    GRAN_CHECK(std::isfinite(v[i]), GRAN_ERR_ARG, "v[" GRAN_I64_FMT "] = %g is not finite", i, v[i]);
  return GRAN_SUCCESS;
}

}  // namespace

/** @brief Sonine coefficient a2 = (3/5) <E^2> / <E>^2 - 1, E_i = m_i |v_i - u|^2, averages over
 *  particles, u = sum m_i v_i / sum m_i (the mean flow). With mass == NULL (or equal masses) this
 *  is (3/5)<c^4>/<c^2>^2 - 1 (docs/physics.md, "Oracles for tests"); with masses a mixture whose species are
 *  Maxwellian at one temperature has a2 = 0 (m c^2 / T is chi-square(3) for every species).
 *  @param[in] n >= 1  @param[in] v 3n velocities  @param[in] mass n masses > 0, or NULL
 *  @param[out] a2  @return GRAN_ERR_DOMAIN when every velocity equals the mean flow */
GRAN_EXTERN int gran_sonine_a2(int64_t n, const double *v, const double *mass, double *a2) {
  GRAN_CALL(check_velocities(n, v));
  GRAN_CHECK_PTR(a2);
  if (mass)
    for (int64_t i = 0; i < n; i++)
      GRAN_CHECK(std::isfinite(mass[i]) && mass[i] > 0.0, GRAN_ERR_ARG,
                 "mass[" GRAN_I64_FMT "] = %g must be finite and > 0", i, mass[i]);
  double msum = 0.0, p[3] = {0.0, 0.0, 0.0};
  for (int64_t i = 0; i < n; i++) {
    const double m = mass ? mass[i] : 1.0;
    msum += m;
    for (int c = 0; c < 3; c++) p[c] += m * v[3 * i + c];
  }
  const double u[3] = {p[0] / msum, p[1] / msum, p[2] / msum};
  double e1 = 0.0, e2 = 0.0;
  for (int64_t i = 0; i < n; i++) {
    const double m = mass ? mass[i] : 1.0;
    const double cx = v[3 * i] - u[0], cy = v[3 * i + 1] - u[1], cz = v[3 * i + 2] - u[2];
    const double e = m * (cx * cx + cy * cy + cz * cz);
    e1 += e;
    e2 += e * e;
  }
  GRAN_CHECK(e1 > 0.0, GRAN_ERR_DOMAIN, "all n = " GRAN_I64_FMT " velocities equal the mean flow: a2 is undefined",
             n);
  e1 /= (double)n;
  e2 /= (double)n;
  const double r = 0.6 * e2 / (e1 * e1) - 1.0;
  GRAN_CHECK(std::isfinite(r), GRAN_ERR_NUMERIC, "a2 overflowed (velocities too large)");
  *a2 = r;
  return GRAN_SUCCESS;
}

/** @brief Normalised histogram of the reduced speed c = |v_i - u| / scale (u the mean velocity)
 *  on [0, cmax) in nbins equal bins of width dc = cmax/nbins:
 *  hist[k] = (particles with k dc <= c < (k+1) dc) / (n dc), so sum_k hist[k] dc is the fraction
 *  of particles below cmax and hist approximates the speed density f(c) (for a Maxwellian and
 *  scale = sqrt(2T/m): f(c) = 4 pi^(-1/2) c^2 exp(-c^2)).
 *  @param[in] scale > 0  @param[in] nbins >= 1  @param[in] cmax > 0  @param[out] hist nbins
 *  @param[out] nbeyond particles with c >= cmax (may be NULL) */
GRAN_EXTERN int gran_speed_histogram(int64_t n, const double *v, double scale, int64_t nbins, double cmax,
                                     double *hist, int64_t *nbeyond) {
  GRAN_CALL(check_velocities(n, v));
  GRAN_CHECK(std::isfinite(scale) && scale > 0.0, GRAN_ERR_ARG, "argument 'scale' = %g must be finite and > 0", scale);
  GRAN_CHECK(nbins >= 1, GRAN_ERR_ARG, "argument 'nbins' = " GRAN_I64_FMT " must be >= 1", nbins);
  GRAN_CHECK(std::isfinite(cmax) && cmax > 0.0, GRAN_ERR_ARG, "argument 'cmax' = %g must be finite and > 0", cmax);
  GRAN_CHECK_PTR(hist);
  double u[3] = {0.0, 0.0, 0.0};
  for (int64_t i = 0; i < n; i++)
    for (int c = 0; c < 3; c++) u[c] += v[3 * i + c];
  for (int c = 0; c < 3; c++) u[c] /= (double)n;
  for (int64_t k = 0; k < nbins; k++) hist[k] = 0.0;
  const double inv_dc = (double)nbins / cmax;
  int64_t beyond = 0;
  for (int64_t i = 0; i < n; i++) {
    const double cx = v[3 * i] - u[0], cy = v[3 * i + 1] - u[1], cz = v[3 * i + 2] - u[2];
    const double c = std::sqrt(cx * cx + cy * cy + cz * cz) / scale;
    if (c >= cmax) {
      beyond++;
      continue;
    }
    int64_t k = (int64_t)(c * inv_dc);
    if (k >= nbins) k = nbins - 1; /* c just below cmax rounded up */
    hist[k] += 1.0;
  }
  const double norm = inv_dc / (double)n;
  for (int64_t k = 0; k < nbins; k++) hist[k] *= norm;
  if (nbeyond) *nbeyond = beyond;
  return GRAN_SUCCESS;
}
