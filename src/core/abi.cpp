/* abi.cpp - the ABI described by name, so bindings can check their mirrors against the compiled
 * library: sizeof of every struct of granary.h, offsetof of every field and the
 * value of every integer constant. The list is src/core/abi_table.inc, generated from the header
 * by bindings/gen_raw.py (make checks that it is current). */
#include "granary_impl.h"

#include <cstddef>

namespace {

struct AbiEntry {
  const char *name;
  int64_t value;
};

#define GRAN_ABI_CONST(name) {#name, (int64_t)(name)},
#define GRAN_ABI_SIZE(type) {"sizeof(" #type ")", (int64_t)sizeof(type)},
#define GRAN_ABI_OFFSET(type, field) {"offsetof(" #type ", " #field ")", (int64_t)offsetof(type, field)},

const AbiEntry kAbi[] = {
#include "core/abi_table.inc"
};

#undef GRAN_ABI_CONST
#undef GRAN_ABI_SIZE
#undef GRAN_ABI_OFFSET

}  // namespace

/** @brief Look up a struct size ("sizeof(gran_rng)"), a field offset ("offsetof(gran_rng, s)") or an
 *  integer constant ("GRAN_ERR_ARG") by name.
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
