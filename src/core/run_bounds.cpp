/* run_bounds.cpp - the bounds on the number of steps of a run and on the work of the theory beside
 * it (see run_bounds.h). */
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

int gran_theory_work_check(double passes, double nspecies, char *why, size_t len) {
  const double pairs = passes * nspecies * nspecies;
  const int level = pairs > kTheoryMaxPairs ? 2 : pairs > kTheoryWarnPairs ? 1 : 0;
  if (level && why && len > 0) {
    const double sec = pairs / kTheoryPairsPerSecond;
    std::snprintf(why, len,
                  "%.3g passes over %.3g^2 species pairs = %.3g pair evaluations (about %.3g %s at %.0e per second on "
                  "one core; the theory refuses more than %.0e)",
                  passes, nspecies, pairs, sec >= 7200 ? sec / 3600 : sec >= 120 ? sec / 60 : sec,
                  sec >= 7200 ? "hours" : sec >= 120 ? "minutes" : "seconds", kTheoryPairsPerSecond, kTheoryMaxPairs);
  }
  return level;
}
}  // namespace gran
