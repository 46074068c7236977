/* run_bounds.h - the one bound on the length of a run that every time-stepped engine (GSRD, the
 * DSMC cell selector) applies where a run is set up: the scene parser for [engine] t_end / steps
 * and dt, the C API at each advance. A run of more than kRunMaxSteps steps, or of more than
 * kRunMaxUpdates particle (and cell) updates, is refused with its estimate: such a run does not
 * end in any useful time (1e14 updates are about 12 days at 1e8 updates per second). */
#ifndef GRANARY_RUN_BOUNDS_H
#define GRANARY_RUN_BOUNDS_H

#include <cstddef>

namespace gran {
constexpr double kRunMaxSteps = 1e12;
constexpr double kRunMaxUpdates = 1e14;
constexpr double kRunUpdatesPerSecond = 1e8; /* for the estimate in the message only */
/* true when `steps` steps of `per_step` updates each (particles, plus cells where a step visits
 * them) are within the bounds (NaN or inf steps are not); otherwise false with the estimate in
 * why (steps, updates, estimated days), for the caller's message naming its key. */
bool gran_run_steps_ok(double steps, double per_step, char *why, size_t len);

/* The kinetic theory a DSMC scene computes beside its run (the HCS start, tau0, the T_theory,
 * msd_theory and collision-count trajectories) costs O(M^2) pair evaluations per pass over an
 * M-species mixture (measured about 7e8 pair evaluations per second on one core). A scene whose
 * theory needs more than kTheoryMaxPairs (about 4 hours) is refused with the estimate; above
 * kTheoryWarnPairs (about 15 s) it is accepted with a warning that gives the estimate. */
constexpr double kTheoryMaxPairs = 1e13;
constexpr double kTheoryWarnPairs = 1e10;
constexpr double kTheoryPairsPerSecond = 7e8; /* for the estimate in the message only */
/* 0: within kTheoryWarnPairs; 1: warn; 2: refuse. why (always written when not 0): the passes,
 * species, pair evaluations and the estimated time, for the caller's message naming its key. */
int gran_theory_work_check(double passes, double nspecies, char *why, size_t len);
}  // namespace gran

#endif
