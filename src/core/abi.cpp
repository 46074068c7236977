/* abi.cpp - the ABI described by name, so bindings can check their hand-written mirrors against
 * the compiled library (STYLE rule 10): sizeof of every struct of granary.h and the value of every
 * enum constant. A constant or struct added to the header belongs in this table too. */
#include "granary_impl.h"

namespace {

struct AbiEntry {
  const char *name;
  int64_t value;
};

#define GRAN_ABI_CONST(name) {#name, (int64_t)(name)},
#define GRAN_ABI_SIZE(type) {"sizeof(" #type ")", (int64_t)sizeof(type)},
#define GRAN_ABI_ERROR_(name, value, msg) {#name, (int64_t)(value)},

const AbiEntry kAbi[] = {
    /* structs */
    GRAN_ABI_SIZE(gran_rng)
    GRAN_ABI_SIZE(gran_segtree)
    GRAN_ABI_SIZE(gran_particles)
    GRAN_ABI_SIZE(gran_dsmc_options)
    GRAN_ABI_SIZE(gran_dsmc_stats)
    GRAN_ABI_SIZE(gran_run_progress)
    GRAN_ABI_SIZE(gran_run_control)
    GRAN_ABI_SIZE(gran_run_result)
    GRAN_ABI_SIZE(gran_srd_options) /* GSRD */
    GRAN_ABI_SIZE(gran_srd_obs)     /* GSRD */
    GRAN_ABI_SIZE(gran_dsmc_cell_options) /* cell selector */
    GRAN_ABI_SIZE(gran_dsmc_cluster_stats) /* cell selector: aggregation */
    GRAN_ABI_SIZE(gran_dsmc_agg_options) /* aggregation in the event selectors */
    /* version */
    GRAN_ABI_CONST(GRAN_VERSION_MAJOR)
    GRAN_ABI_CONST(GRAN_VERSION_MINOR)
    GRAN_ABI_CONST(GRAN_VERSION_PATCH)
    /* error codes: from the one X-macro list */
    GRAN_ERROR_LIST(GRAN_ABI_ERROR_)
    /* particle flags */
    GRAN_ABI_CONST(GRAN_PARTICLES_DISPLACEMENT)
    GRAN_ABI_CONST(GRAN_PARTICLES_POSITION)
    GRAN_ABI_CONST(GRAN_PARTICLES_MASS)
    /* theory */
    GRAN_ABI_CONST(GRAN_RESTITUTION_CONSTANT)
    GRAN_ABI_CONST(GRAN_RESTITUTION_MATRIX)
    GRAN_ABI_CONST(GRAN_RESTITUTION_VISCOELASTIC)
    GRAN_ABI_CONST(GRAN_HCS_NORM_MEAN)
    GRAN_ABI_CONST(GRAN_HCS_NORM_T1)
    /* dsmc */
    GRAN_ABI_CONST(GRAN_SELECTOR_LOWRANK)
    GRAN_ABI_CONST(GRAN_SELECTOR_BIRD)
    GRAN_ABI_CONST(GRAN_SELECTOR_LOWRANK_PAPER)
    GRAN_ABI_CONST(GRAN_SELECTOR_BIRD_PAPER)
    GRAN_ABI_CONST(GRAN_OBSERVE_DISPLACEMENT)
    GRAN_ABI_CONST(GRAN_OBSERVE_COLLISION_COUNTS)
    GRAN_ABI_CONST(GRAN_OBSERVE_TRAJECTORIES)
    /* GSRD devices (CUDA backend) */
    GRAN_ABI_CONST(GRAN_SRD_DEVICE_CPU)
    GRAN_ABI_CONST(GRAN_SRD_DEVICE_CUDA)
    GRAN_ABI_CONST(GRAN_SRD_DEVICE_AUTO)
    GRAN_ABI_CONST(GRAN_SRD_DEVICE_REFERENCE)
    /* cell selector */
    GRAN_ABI_CONST(GRAN_SELECTOR_CELL)
    GRAN_ABI_CONST(GRAN_PLACE_RANDOM)
    GRAN_ABI_CONST(GRAN_PLACE_COLLISION)
    /* aggregation: fragment laws */
    GRAN_ABI_CONST(GRAN_FRAG_MONOMERS)
    GRAN_ABI_CONST(GRAN_FRAG_BINARY)
    /* speed classes of the low-rank selector (issue 11) */
    GRAN_ABI_CONST(GRAN_SPEED_CLASSES_OFF)
    GRAN_ABI_CONST(GRAN_SPEED_CLASSES_ON)
    GRAN_ABI_CONST(GRAN_SPEED_CLASSES_AUTO)
};

#undef GRAN_ABI_CONST
#undef GRAN_ABI_SIZE
#undef GRAN_ABI_ERROR_

}  // namespace

/** @brief Look up a struct size ("sizeof(gran_rng)") or an enum constant ("GRAN_ERR_ARG") by name.
 *  @param[in] name exact spelling  @param[out] value its value
 *  @return GRAN_ERR_ARG (naming it) for an unknown name. */
GRAN_EXTERN int gran_abi_query(const char *name, int64_t *value) {
  GRAN_CHECK_PTR(name);
  GRAN_CHECK_PTR(value);
  for (const AbiEntry &e : kAbi)
    if (std::strcmp(e.name, name) == 0) {
      *value = e.value;
      return GRAN_SUCCESS;
    }
  return GRAN_ERROR(GRAN_ERR_ARG, "unknown ABI name '%s' in argument 'name'", name);
}
