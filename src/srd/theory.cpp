/* theory.cpp - the GSRD theory of srd_theory.h: Haff's law with the mean-field rate and its
 * Poisson-occupancy factor, and the SRD shear viscosity (kinetic + collisional). */
#include "srd/srd_theory.h"

#include <algorithm>
#include <cmath>

#include "granary_impl.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

extern "C" int gran_srd_haff_applies_(const gran_srd_options *o) {
  return o->eps < 1.0 && o->sigma > 0 && !o->thermostat && o->shear_rate == 0 && o->wall_axis < 0 &&
         o->accel[0] == 0 && o->accel[1] == 0 && o->accel[2] == 0;
}

extern "C" double gran_srd_haff_rate_(const gran_srd_options *o) {
  const double vol = o->dim == 3 ? o->a * o->a * o->a : o->a * o->a;
  return (o->dim == 3 ? 2.0 / 3.0 : 1.0) * (1.0 - o->eps * o->eps) * o->sigma * o->sigma * (o->n0 / vol) *
         std::sqrt(o->T0);
}

extern "C" double gran_srd_haff_T_(const gran_srd_options *o, double f, double t) {
  if (!(t > 0)) return o->T0;
  const double r = f * gran_srd_haff_rate_(o);
  if (std::isfinite(r * t)) { /* the usual case, directly */
    const double x = 1.0 + r * t;
    return o->T0 / (x * x);
  }
  const double d = o->dim == 3 ? 3.0 : 2.0;
  const double lx = std::log(t) + std::log(f) + std::log(o->dim == 3 ? 2.0 / 3.0 : 1.0) + std::log1p(-o->eps * o->eps) +
                    2.0 * std::log(o->sigma) + std::log(o->n0) - d * std::log(o->a) + 0.5 * std::log(o->T0);
  if (lx > 700.0) { /* T0 / x^2 with x = e^lx: from the logarithm, 0 where it underflows */
    const double lT = std::log(o->T0) - 2.0 * lx;
    return lT < -745.0 ? 0.0 : std::exp(lT);
  }
  const double x = 1.0 + std::exp(lx);
  return o->T0 / (x * x);
}

extern "C" double gran_srd_haff_poisson_factor_(int dim, double n0) {
  if ((dim != 2 && dim != 3) || !(n0 > 0) || !std::isfinite(n0)) return 0.0;
  const double d = dim, ln0 = std::log(n0);
  /* the Poisson weights beyond n0 +- (12 sqrt(n0) + 40) are below 1e-30 */
  const double w = 12.0 * std::sqrt(n0) + 40.0;
  const long lo = std::max(2L, (long)std::floor(n0 - w)), hi = (long)std::ceil(n0 + w);
  double sum = 0.0;
  for (long n = lo; n <= hi; ++n) {
    const double x = (double)n, k = d * (x - 1.0);
    const double lg = -n0 + x * ln0 - std::lgamma(x + 1.0) + std::lgamma(0.5 * k + 1.5) - std::lgamma(0.5 * k);
    sum += 2.0 * std::sqrt(2.0 * x / d) * std::exp(lg);
  }
  return sum / (d * n0 * n0);
}

extern "C" int gran_srd_viscosity_theory_(const gran_srd_options *o, double theta, double *nu_kin, double *nu_coll) {
  GRAN_CHECK_PTR(o);
  GRAN_CHECK_PTR(nu_kin);
  GRAN_CHECK_PTR(nu_coll);
  GRAN_CHECK(o->dim == 2 || o->dim == 3, GRAN_ERR_ARG, "option 'dim' must be 2 or 3 (got %d)", (int)o->dim);
  GRAN_CHECK(std::isfinite(o->n0) && o->n0 > 0, GRAN_ERR_ARG, "option 'n0' must be finite and > 0 (got %g)", o->n0);
  GRAN_CHECK(std::isfinite(o->a) && o->a > 0, GRAN_ERR_ARG, "option 'a' must be finite and > 0 (got %g)", o->a);
  GRAN_CHECK(std::isfinite(o->dt) && o->dt > 0, GRAN_ERR_ARG, "option 'dt' must be finite and > 0 (got %g)", o->dt);
  GRAN_CHECK(o->alpha_deg > 0 && o->alpha_deg <= 180, GRAN_ERR_ARG, "option 'alpha_deg' must lie in (0, 180] (got %g)",
             o->alpha_deg);
  GRAN_CHECK(std::isfinite(theta) && theta >= 0, GRAN_ERR_ARG, "argument 'theta' must be finite and >= 0 (got %g)",
             theta);
  const double M = o->n0, q = M - 1.0 + std::exp(-M), al = o->alpha_deg * M_PI / 180.0, d = o->dim;
  const double den = o->dim == 2 ? q * (1.0 - std::cos(2.0 * al)) : q * (4.0 - 2.0 * std::cos(al) - 2.0 * std::cos(2.0 * al));
  GRAN_CHECK(den > 1e-12 * q, GRAN_ERR_DOMAIN,
             "the kinetic viscosity of Eq. 1.48 diverges at alpha = %g degrees in 2-D (1 - cos 2 alpha = 0)",
             o->alpha_deg);
  *nu_kin = theta * o->dt * ((o->dim == 2 ? M : 5.0 * M) / den - 0.5);
  *nu_coll = o->a * o->a / (6.0 * d * o->dt) * (q / M) * (1.0 - std::cos(al));
  return GRAN_SUCCESS;
}
