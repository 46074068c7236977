/* bird.cpp - Bird's selector's instantiations of the hot loop (Bodrova & Osinsky Eqs. 46-52, event form). */
#include "dsmc_loop.h"

namespace gran {

/** @brief Hot loop of Bird's selector for the given effects. */
DsmcLoopFn dsmc_bird_loop(int paper, int disp, int counts, int rest, int tracers) {
  return paper ? dsmc_pick<SelBird, true>(disp, counts, rest, tracers) : dsmc_pick<SelBird, false>(disp, counts, rest, tracers);
}

}  // namespace gran
