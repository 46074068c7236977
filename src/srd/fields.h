/* fields.h - read-only accessors of the GSRD state for the run driver's adapter
 * (src/io/engine_srd.cpp); src/srd/fields.cpp. */
#ifndef GRAN_SRD_FIELDS_H
#define GRAN_SRD_FIELDS_H

#include "granary_impl.h"

/* Steps done so far (what gran_srd_observe reports, without its side effects on the clamp
 * counters). */
int64_t gran_srd_steps_(const gran_srd *srd);

#endif
