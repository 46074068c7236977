/* keyed.cpp - GSL's view of a keyed gran_rng (core/keyed.h). */
#include "core/keyed.h"

namespace {
unsigned long xo_get(void *st) { return (unsigned long)(gran_xo_next((gran_rng *)st) >> 32); }
double xo_get_double(void *st) { return gran_xo_uniform((gran_rng *)st); }
void xo_set(void *, unsigned long) {}
}  // namespace

namespace gran {
const gsl_rng_type kKeyedGslType = {"granary-xoshiro256**", 0xffffffffUL, 0, sizeof(gran_rng), xo_set, xo_get,
                                    xo_get_double};
}  // namespace gran
