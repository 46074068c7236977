/* create.h - the initial state of a GSRD run (src/srd/create.cpp): the serial creation (one stream
 * draws every particle) and the creation by cells, whose particles of a cell range do not depend
 * on how the cells are split (the domain decomposition's creation, docs/developers/
 * domain-decomposition.md). Plain C declarations, so that the C tests call them too. */
#ifndef GRAN_SRD_CREATE_H
#define GRAN_SRD_CREATE_H

#include "granary.h"
#include "core/exactsum.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Particles in each box cell [lo, hi) of a creation by cells (0 <= lo <= hi <= the box cells,
 * index i + L0 (j + L1 k) of the unshifted lattice), count[0 .. hi - lo): N = round(n0 x cells)
 * split multinomially down the binary tree over [0, box cells): node [nlo, nhi) (heap number id,
 * the root 1 and the children 2 id, 2 id + 1) of count c gives its left half [nlo, mid),
 * mid = nlo + (nhi - nlo) / 2, Binomial(c, (mid - nlo) / (nhi - nlo)) (gsl_ran_binomial) drawn
 * from the node's own generator (seed, id). GRAN_ERR_ARG for options gran_srd_create refuses or a
 * bad range. */
int gran_srd_cell_counts_(const gran_srd_options *o, int64_t lo, int64_t hi, int64_t *count);

/* The particles of box cells [lo, hi), count[] as gran_srd_cell_counts_ gives for that range, in
 * cell order into x, y, (z), vx, vy, (vz) (sum of count entries each; z and vz unused in 2-D):
 * each cell draws from its own generator (seed, cell) its particles' positions (uniform inside the
 * cell; a draw that the engine would bin into another cell, by rounding, is drawn again) and then
 * their velocities (normal, standard deviation sqrt(T0)), per particle x y (z) vx vy (vz). The
 * velocities are raw (mean momentum not removed); mom[0 .. 2] (NULL: none) get each cell's
 * momentum, summed over its particles in order, added. */
int gran_srd_create_cells_(const gran_srd_options *o, int64_t lo, int64_t hi, const int64_t *count, double *x,
                           double *y, double *z, double *vx, double *vy, double *vz, gran_exactsum *mom);

/* The initial particles of the engine s (allocated, streams set up) by its options' creation: the
 * serial one or the one by cells (then in cell order; threads split the cells, the result does not
 * depend on them), the mean momentum removed and the Lees-Edwards shear profile added. */
int gran_srd_initial_state_(gran_srd *s);

#ifdef __cplusplus
}
#endif

#endif
