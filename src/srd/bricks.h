/* bricks.h - the brick layer of the GSRD domain decomposition (src/srd/bricks.cpp; design:
 * docs/developers/domain-decomposition.md, "Step 2"). The decomposable engine (gran_srd_options
 * .creation = GRAN_SRD_CREATE_CELLS) steps one GSRD box as P bricks of the binning grid, each
 * with its own particles and cells, exchanging particles and exact-sum accumulators through a
 * transport; the single-process engine in that mode is the same code with one brick. Plain C
 * declarations, so that the C tests call them. */
#ifndef GRAN_SRD_BRICKS_H
#define GRAN_SRD_BRICKS_H

#include "granary.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A gathered brick run (or a plain engine's state in the same layout), malloc'd arrays:
 * particles in key order (the order of the single-process arrays), the cells of the binning grid
 * (ncell) each from its owner: reference velocity V[3 c .. 3 c + 2] and RNG state rng[4 c .. 4 c + 3];
 * the ledger; the transport's count of the bytes sent between bricks. */
typedef struct srd_bricks_out {
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz; /* z, vz NULL in 2-D */
  int64_t ncell;
  double *V;
  uint64_t *rng;
  double time, e_initial, e_coll, e_ext, flux_kin, flux_coll, wall_impulse[3], dt_max;
  int64_t step, clamped;
  int64_t bytes_sent;    /* particle messages (payload bytes), all bricks, all steps */
  int64_t particles_sent;/* particles that changed brick */
  double seconds;        /* wall time of the steps (the set-up and the gather left out) */
  int64_t faces;         /* brick faces of the split (a periodic axis of P_a > 1 bricks has P_a faces
                            per brick row, a wall axis P_a - 1), for bytes per face */
} srd_bricks_out;

/* The run of the options (creation must be GRAN_SRD_CREATE_CELLS) for nsteps steps as
 * pgrid[0] x pgrid[1] x pgrid[2] virtual bricks in this process (1 on the axes beyond dim; at
 * most the grid's cells per axis), gathered into *out (srd_bricks_out_free_ releases it). The
 * initial state: create_in_bricks = 0 gran_srd_create's, each particle given to the brick of its
 * cell; 1 each brick draws the particles of its own cells, sets up its cells' streams, and the
 * mean momentum and the initial energy are all-reduced (the same state). GRAN_ERR_ARG naming a
 * bad option or pgrid entry. */
int srd_bricks_run_(const gran_srd_options *opt, const int pgrid[3], int64_t nsteps, int create_in_bricks,
                    srd_bricks_out *out);
/* A plain engine's state s (CPU) in the same layout. */
int srd_bricks_gather_plain_(const gran_srd *s, srd_bricks_out *out);
void srd_bricks_out_free_(srd_bricks_out *out);

#ifdef __cplusplus
}
/* gran_srd_advance of the decomposable engine: steps s as one brick (engine.cpp calls it) */
int srd_bricks_advance_(gran_srd *s, int64_t steps);
/* adds 0.5 |v|^2 of particles [0, n) to *acc exactly (vz NULL in 2-D): the decomposable engine's
 * initial energy, one compiled instance for the plain engine and the bricks */
void srd_kinetic_exact_(const double *vx, const double *vy, const double *vz, int64_t n, struct gran_exactsum *acc);
#endif

#endif
