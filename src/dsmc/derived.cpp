/* derived.cpp - the values a DSMC engine derives from its inputs, checked once at creation.
 *
 * Finite inputs can give non-finite or vanishing derived values: masses whose sum overflows
 * (m_i + m_j = inf: the collision factors 2 m_j / (m_i + m_j) are 0 or NaN), whose reduced mass
 * m_i m_j / (m_i + m_j) underflows, or so small that the speeds they imply square to inf; and
 * bounds whose squares, which the acceptance tests of the selectors compare, overflow (every
 * trial is then rejected: an advance that never ends), or, in Bird's test, underflow (the same). These rules refuse such inputs at creation
 * with GRAN_ERR_DOMAIN naming the input (the mixture field 'mass' or 'sigma' of a species). */
#include "dsmc_impl.h"
#include <cfloat>
#include <cmath>

namespace gran {

namespace {
/* headroom above the values at creation: bound raises, the (1 + eps) <= 2 of a collision, sums */
constexpr double kHeadroom = 64.0;
bool positive_normal(double x) { return std::isfinite(x) && x >= DBL_MIN; }
}  // namespace

/* Masses m_lo <= m_hi (species k_lo, k_hi; the extremes of the masses that can meet: those of the
 * species present, or with aggregation the monomer and the whole gas) and the kinetic energy E.
 * Every pair (m_i, m_j) of masses in [m_lo, m_hi] must give: m_i + m_j finite; 1/(m_i + m_j),
 * the factors (1 + eps) m_j/(m_i + m_j) and the reduced mass m_i m_j/(m_i + m_j) finite and normal
 * (> DBL_MIN); the relative speed^2 a pair can reach with the energy E, 4 E (1/m_i + 1/m_j),
 * finite with kHeadroom. Each of these is monotone in m_i and m_j, so the pairs of the two
 * extremes cover all. The reduced mass in the form its users compute it, m_i m_j / (m_i + m_j) (the
 * aggregation rules and the dissipated energy of every selector), whose product can under- or
 * overflow. */
int dsmc_check_masses(double m_lo, int64_t k_lo, double m_hi, int64_t k_hi, double E) {
  const double m[2] = {m_lo, m_hi};
  const int64_t k[2] = {k_lo, k_hi};
  for (int a = 0; a < 2; a++)
    for (int b = a; b < 2; b++) {
      const double mi = m[a], mj = m[b], sum = mi + mj, inv = 1.0 / sum;
      const double fi = 2.0 * inv * mj, fj = 2.0 * inv * mi, mu = mi * mj * inv;
      const double g2 = kHeadroom * 4.0 * E * (1.0 / mi + 1.0 / mj);
      const char *what = !std::isfinite(sum)                              ? "m_i + m_j"
                         : !positive_normal(inv)                          ? "1/(m_i + m_j)"
                         : !positive_normal(fi) || !positive_normal(fj)   ? "the momentum factor 2 m_j/(m_i + m_j)"
                         : !positive_normal(mu)                           ? "the reduced mass m_i m_j/(m_i + m_j)"
                         : !std::isfinite(g2)                             ? "the relative speed^2 4 E (1/m_i + 1/m_j)"
                                                                          : nullptr;
      if (what)
        return GRAN_ERROR(GRAN_ERR_DOMAIN,
                          "mixture 'mass' of species " GRAN_I64_FMT " = %g (beside 'mass' of species " GRAN_I64_FMT
                          " = %g, kinetic energy %g): the derived value %s is not finite and > 0 in double precision "
                          "(choose units with masses nearer 1)",
                          k[a], m[a], k[b], m[b], E, what);
    }
  return GRAN_SUCCESS;
}

/* The acceptance tests compare squares: Bird (u C_max)^2 < (sigma_ik^2)^2 g^2 with
 * C_max = 2 sigma^2 b (b: the speed bound), low-rank (u (b_i + b_k))^2 < g^2. With b2 the largest
 * squared speed bound and sigma the largest diameter that can collide (species k), the squares
 * (2 sigma^2 b)^2 and (sigma^2)^2 4 b2 (Bird) or 4 b2 (low-rank) must be finite with kHeadroom. */
int dsmc_check_acceptance(int bird, double sigma, int64_t k, double b2, double sigma_min, int64_t k_min) {
  const double w = sigma * sigma, B = bird ? 2.0 * w * std::sqrt(b2) : 2.0 * std::sqrt(b2);
  const double sq = kHeadroom * B * B, wg = bird ? kHeadroom * (w * w) * 4.0 * b2 : kHeadroom * 4.0 * b2;
  GRAN_CHECK(std::isfinite(sq) && std::isfinite(wg), GRAN_ERR_DOMAIN,
             "mixture 'sigma' of species " GRAN_I64_FMT " = %g with speed bound %g (from the masses and 'T0'): the "
             "selector's acceptance bound %g squares to %g, beyond double precision, so no candidate pair would ever "
             "be accepted (expected trials per collision unbounded; choose units with sigma and speeds nearer 1)",
             k, sigma, std::sqrt(b2), B, sq);
  /* Bird's right side (sigma_ik^2)^2 g^2 of the smallest diameter (sigma_min, species k_min) at the
   * speed bound: normal with kHeadroom, or every trial compares 0 < 0 (an advance that never ends);
   * a gas at rest (bound 0) has no trials to fail */
  const double wm = sigma_min * sigma_min, wgm = (wm * wm) * 4.0 * b2 / kHeadroom;
  GRAN_CHECK(!bird || !(b2 > 0) || wgm >= DBL_MIN, GRAN_ERR_DOMAIN,
             "mixture 'sigma' of species " GRAN_I64_FMT " = %g with speed bound %g (from the masses and 'T0'): Bird's "
             "acceptance test compares (sigma^2)^2 g^2 = %g, below the smallest normal double, so no candidate pair "
             "would ever be accepted (expected trials per collision unbounded; choose units with sigma and speeds "
             "nearer 1)",
             k_min, sigma_min, std::sqrt(b2), wgm);
  return GRAN_SUCCESS;
}

/* Both rules for a new engine (after its velocities and bounds): the masses of the species present
 * (with aggregation, agg: from the lightest to the whole gas in one cluster), and, with speeds (once
 * the energy and the bounds are known finite), the speeds they imply and the selector's acceptance
 * squares (event selectors; with aggregation the diameter of that one cluster). */
int dsmc_check_derived(const gran_dsmc *s, bool agg, bool speeds) {
  double m_lo = INFINITY, m_hi = 0, mtot = 0, smax = 0, smin = INFINITY, b2 = 0;
  int64_t k_lo = 0, k_hi = 0, k_s = 0, k_m = 0;
  for (int64_t k = 0; k < s->M; k++) {
    if (s->count[(size_t)k] <= 0) continue;
    const double mk = s->mix.m[(size_t)k];
    if (mk < m_lo) m_lo = mk, k_lo = k;
    if (mk > m_hi) m_hi = mk, k_hi = k;
    if (s->mix.sigma[(size_t)k] > smax) smax = s->mix.sigma[(size_t)k], k_s = k;
    if (s->mix.sigma[(size_t)k] < smin) smin = s->mix.sigma[(size_t)k], k_m = k;
    mtot += mk * (double)s->count[(size_t)k];
    b2 = std::fmax(b2, s->bound2[(size_t)k]);
  }
  if (!(m_hi > 0)) return GRAN_SUCCESS; /* no particles */
  GRAN_CHECK(std::isfinite(mtot), GRAN_ERR_DOMAIN,
             "mixture 'mass' of species " GRAN_I64_FMT " = %g: the total mass of the gas overflows (%g)", k_hi, m_hi,
             mtot);
  const double E = speeds ? s->e_initial : 0.0;
  GRAN_CALL(dsmc_check_masses(m_lo, k_lo, agg ? mtot : m_hi, k_hi, E));
  if (!speeds || s->selector == GRAN_SELECTOR_CELL) return GRAN_SUCCESS; /* its bound is checked with 'dt' (cell.cpp) */
  const double sigma = agg ? smax * std::cbrt(mtot / m_lo) : smax;
  return dsmc_check_acceptance(s->selector == GRAN_SELECTOR_BIRD, sigma, k_s, b2, smin, k_m);
}

}  // namespace gran
