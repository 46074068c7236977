/* lowrank.cpp - the low-rank selector's instantiations of the hot loop (Bodrova & Osinsky Eqs. 36-44). */
#include "dsmc_loop.h"

namespace gran {

/** @brief Hot loop of the low-rank selector for the given effects. */
DsmcLoopFn dsmc_lowrank_loop(int paper, int disp, int counts, int rest, int tracers) {
  return paper ? dsmc_pick<SelLowRank, true>(disp, counts, rest, tracers) : dsmc_pick<SelLowRank, false>(disp, counts, rest, tracers);
}

}  // namespace gran
