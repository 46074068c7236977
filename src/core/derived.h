/* derived.h - the one rule for values derived from inputs.
 *
 * Finite inputs can still overflow (or underflow) what an engine derives from them: T0 = 1e308
 * gives v^2 = inf, a = 1e-300 gives the density n0 / a^3 = inf, sigma = 1e300 gives sigma^2 = inf.
 * Rule: a derived value must be finite and lie within [lo, hi]; otherwise the input it comes from
 * is refused, naming its scene key or C option. The caller states the range and the key; this
 * header decides and words the reason. Users: the GSRD limits (src/srd/srd_limits.h: gran_srd_create
 * and the GSRD scene parser), the DSMC scene parser (src/dsmc/scene_dsmc.cpp: speeds and energies of the
 * initial temperatures) and gran_dsmc_create (src/dsmc/engine.cpp: the initial state). */
#ifndef GRAN_CORE_DERIVED_H
#define GRAN_CORE_DERIVED_H

#include <cmath>
#include <cstdio>
#include <string>

/* true when v is finite and lo <= v <= hi */
inline bool gran_derived_ok(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }
/* the rule with the widest range: v is finite */
inline bool gran_derived_finite(double v) { return gran_derived_ok(v, -HUGE_VAL, HUGE_VAL); }

/* "" when gran_derived_ok(v, lo, hi); else the reason, starting with `what` (a phrase naming the
 * derived value and how it is formed): "WHAT overflows (inf)", "WHAT is not finite (nan)",
 * "WHAT = 3.2e+14 exceeds 1e+06", "WHAT = 1e-45 is below 1e-15". */
inline std::string gran_derived_why(double v, double lo, double hi, const char *what) {
  if (gran_derived_ok(v, lo, hi)) return std::string();
  char b[512];
  if (std::isinf(v)) std::snprintf(b, sizeof b, "%s overflows (%g)", what, v);
  else if (std::isnan(v)) std::snprintf(b, sizeof b, "%s is not finite (nan)", what);
  else if (v > hi) std::snprintf(b, sizeof b, "%s = %.3g exceeds %.3g", what, v, hi);
  else std::snprintf(b, sizeof b, "%s = %.3g is below %.3g", what, v, lo);
  return b;
}

#endif
