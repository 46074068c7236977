/* run_bounds.cpp - the bound on the number of steps of a run (see run_bounds.h). */
#include "core/run_bounds.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace gran {
bool gran_run_steps_ok(double steps, double per_step, char *why, size_t len) {
  const double upd = steps * std::max(per_step, 1.0);
  if (steps >= 0 && steps <= kRunMaxSteps && upd <= kRunMaxUpdates) return true;
  if (why && len > 0)
    std::snprintf(why, len,
                  "%.3g steps of %.3g particle/cell updates each = %.3g updates (about %.3g days at %.0e updates per "
                  "second); a run may have at most %.0e steps and %.0e updates",
                  steps, std::max(per_step, 1.0), upd, upd / kRunUpdatesPerSecond / 86400.0, kRunUpdatesPerSecond,
                  kRunMaxSteps, kRunMaxUpdates);
  return false;
}
}  // namespace gran
