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

/* What one process of a decomposed run reports (srd_bricks_report_). The whole gas's values are
 * the same on every process and for any split: the state digests (sums mod 2^64 of a 64-bit hash
 * per particle, of its position and velocity bits, and per cell, of its global index, V and RNG
 * state: order-independent, so equal digests mean the same set of particle states and the same
 * cells bit for bit), the momentum and kinetic energy (exact sums, rounded once) and the ledger. */
typedef struct srd_bricks_rank_out {
  int64_t n;                          /* particles of the gas */
  uint64_t digest_particles, digest_cells;
  double momentum[3], energy;         /* sum v, sum |v|^2 / 2 of the gas at the end */
  double temperature;                 /* sum |v - P/N|^2 / (d N) */
  double time, e_initial, e_coll, e_ext, flux_kin, flux_coll, wall_impulse[3], dt_max;
  int64_t step, clamped;
  int bricks[3];                      /* the split */
  /* this process (its bricks) */
  int64_t n_local;                    /* its particles at the end */
  int64_t particle_steps;             /* sum over the steps of its particles (its rate: / seconds) */
  double seconds;                     /* wall time of its steps */
  int64_t bytes_sent, particles_sent; /* particle messages it sent (payload) and the particles in them */
  /* all processes */
  double seconds_max;                 /* the slowest process's steps */
  int64_t bytes_sent_all, particles_sent_all;
  int64_t n_local_min, n_local_max;   /* the balance of the split at the end: particles per brick */
  int64_t far_messages_all;           /* messages to bricks beyond the 3^d - 1 around the sender */
} srd_bricks_rank_out;

/* The peak bytes of one process of a split run of these options into nbricks bricks (its brick's
 * share of the particles, with 10 % for the fluctuation of a brick's count, and of the cells, with
 * the step's work arrays); all_in_one = 1: all bricks in one process. */
double srd_bricks_memory_(const gran_srd_options *opt, int nbricks, int all_in_one);

/* Order-independent digests (as in srd_bricks_rank_out) of a gathered run or a plain state. */
void srd_bricks_digest_(const srd_bricks_out *o, int dim, uint64_t *particles, uint64_t *cells);

/* The split of the binning grid (cells nc[0..2] per axis; 1 beyond dim) into P bricks that has the
 * fewest brick faces (ties: the most cells along x per brick), each axis at most its cells: pgrid.
 * GRAN_ERR_ARG when P exceeds the cells. */
int srd_bricks_auto_(const gran_srd_options *opt, int P, int pgrid[3]);

/* A split gas held by this process: with comm (the process group below, C++ only; NULL from C) of
 * size P > 1 its one brick (comm->rank of the pgrid split, whose product must be P); with comm NULL
 * or of size 1 every brick of the split, stepped one after the other in this process. Open draws the bricks' particles (the creation by
 * cells); step advances every brick nsteps (collective); report fills *out (collective: the gas's
 * values the same on every process; also the temperature, sum |v - P/N|^2 / (d N)); close
 * releases it. GRAN_ERR_ARG naming a bad option or pgrid entry (creation must be
 * GRAN_SRD_CREATE_CELLS, the device the CPU); an error of the transport is GRAN_ERR_IO. */
struct srd_bricks_comm;
typedef struct srd_bricks_state srd_bricks_state;
int srd_bricks_open_(const gran_srd_options *opt, const int pgrid[3], const struct srd_bricks_comm *comm,
                     srd_bricks_state **out);
int srd_bricks_step_(srd_bricks_state *st, int64_t nsteps);
int srd_bricks_report_(srd_bricks_state *st, srd_bricks_rank_out *out);
/* S(k) of the split gas (collective; the same on every process): gran_srd_structure_factor's shells
 * of the unshifted cell counts. The counts go to the process holding their slab of the transform
 * (rows of the last axis, in blocks of ceil(L / P)); over a process group of P > 1 the group's
 * fft_r2c transforms them, else FFTW in this process; each shell's sums are exact, as the serial
 * engine's (srd_sk_bin). So in one process the result is gran_srd_structure_factor's bit for bit,
 * for every split; over processes it differs only where the distributed transform rounds unlike
 * the serial one. A periodic box only; 1 <= nbins <= SRD_BRICKS_SK_MAX_BINS. GRAN_ERR_ARG naming
 * what was wrong. */
#define SRD_BRICKS_SK_MAX_BINS 4096
int srd_bricks_structure_factor_(srd_bricks_state *st, int64_t nbins, double *k, double *sk, int64_t *count);
/* gran_srd_observe of the split gas (collective; the same on every process and, bit for bit, for
 * any split, the decomposable engine's gran_srd_observe in one process included): the particles of
 * each unshifted cell are gathered on the process holding that cell (one message round), every
 * cell's sums taken over its particles in key order, every global sum exact. The clamps are those
 * since the last observation (then reset); the stress is averaged since srd_bricks_stress_reset_
 * (or the start), which resets the Lees-Edwards fluxes of every brick. */
int srd_bricks_observe_(srd_bricks_state *st, gran_srd_obs *ob);
/* the same, with (profile not NULL) the velocity profile: the mean velocity of the particles of each
 * layer of y, profile[3 j + q] for layer j < cells[1] and component q (NaN for a layer without
 * particles), each layer's momentum an exact sum of its cells'; over processes at most
 * SRD_BRICKS_PROFILE_MAX_LAYERS layers (the all-reduce holds 1.8 kB per layer) */
#define SRD_BRICKS_PROFILE_MAX_LAYERS 16384
int srd_bricks_observe_profile_(srd_bricks_state *st, gran_srd_obs *ob, double *profile);
/* gran_srd_observe of the decomposable engine (creation = GRAN_SRD_CREATE_CELLS, CPU: GRAN_ERR_ARG
 * otherwise) with its velocity profile as a split gas computes it (profile as above, any number of
 * layers): the same bits as srd_bricks_observe_profile_ of any split */
int srd_cells_observe_(gran_srd *s, gran_srd_obs *ob, double *profile);
/* Checkpoint sets (docs/developers/domain-decomposition.md, "Checkpoints of a split gas"): each
 * brick's state is a part file of its own (srd_part, src/srd/srd_impl.h). srd_bricks_held_ is the
 * number of bricks st holds (one over a process group), srd_bricks_brick_ the rank of its i-th in
 * the split. srd_bricks_save_ writes brick i's part to paths[i] (not collective: each process its
 * own), marked with the set's generation (>= 1). */
int srd_bricks_held_(const srd_bricks_state *st);
int srd_bricks_brick_(const srd_bricks_state *st, int i);
int srd_bricks_save_(srd_bricks_state *st, const char *const *paths, int64_t generation);
/* A split gas (as srd_bricks_open_: options opt with the replica's seed, split pgrid, process group
 * comm) from the parts paths[0 .. nparts) of the set of generation `generation` at step `step`
 * (collective): own = 1 the one part of this process's brick, written by the same split (its
 * particles kept as they are); own = 0 every part of the set, of any split, each brick keeping the
 * cells of its window and the particles of its window's unshifted cells, in key order (every
 * process reads every part: for a change of the split). Every part is checked as a checkpoint is
 * (srd_part_read_), then across the parts and processes: the same generation, step and scalar
 * state bit for bit, every brick of the set once, every cell covered, the gas's particle count.
 * GRAN_ERR_IO naming the part and the field, on every process (one whose own parts passed says
 * which process failed, and sets *peer_failed when peer_failed is not NULL). The state steps on bit
 * for bit as the gas that wrote the set. */
int srd_bricks_load_(const gran_srd_options *opt, const int pgrid[3], const struct srd_bricks_comm *comm,
                     const char *const *paths, int nparts, int own, int64_t generation, int64_t step,
                     srd_bricks_state **out, int *peer_failed);
/* A split gas from a whole state s of the decomposable engine (a checkpoint of one process): each
 * brick keeps the cells of its window and the particles of its unshifted cells */
int srd_bricks_from_state_(const gran_srd *s, const int pgrid[3], const struct srd_bricks_comm *comm,
                           srd_bricks_state **out);
/* The decomposable engine's whole state (one process, options opt with the replica's seed) from
 * every part of a set (srd_bricks_load_'s checks, then a checkpoint's on the whole) */
int srd_state_from_parts_(const gran_srd_options *opt, const char *const *paths, int nparts, int64_t generation,
                          int64_t step, gran_srd **out);
/* gran_srd_fields of the split gas (collective): each box cell's count, mean velocity and
 * temperature, every cell's sums over its particles in key order (the same bits for any split,
 * the decomposable engine's gran_srd_fields in one process included), gathered on the group's
 * first process (comm->rank 0, or this process without a group), whose outputs (cells, 3 x cells,
 * cells doubles; any NULL) receive them; the others' outputs are not touched. */
int srd_bricks_fields_(srd_bricks_state *st, double *count, double *velocity, double *temperature);
int srd_bricks_stress_reset_(srd_bricks_state *st);
void srd_bricks_close_(srd_bricks_state **st);

#ifdef __cplusplus
}
#include <string>
#include <vector>

/* The process group of a decomposed run, one brick per process: build/granary-mpi fills it over
 * MPI_COMM_WORLD (src/cli/mpi.cpp); libgranary calls no MPI. Every function is called by every
 * process in the same order, from the main thread; each returns 0 on success. */
struct srd_bricks_comm {
  int rank = 0, size = 1;
  void *ctx = nullptr;
  /* a message round: out[p] (size entries; out[rank] unused, others possibly empty) goes to
   * process p, in[p] is what p sent this process (empty when p sent nothing or an empty message;
   * in[rank] left empty). Usually only the bricks around a brick have messages for it, but any
   * process may send to any. */
  int (*round)(void *ctx, std::vector<std::vector<double>> &out, std::vector<std::vector<double>> &in) = nullptr;
  /* all-reduce in place of the count records of elem_bytes each at buf, element by element, with
   * merge(inout, in), commutative and associative (an exact sum: any order gives the same bytes) */
  int (*allreduce)(void *ctx, void *buf, size_t elem_bytes, size_t count,
                   void (*merge)(void *inout, const void *in)) = nullptr;
  /* the forward real-to-complex DFT (FFTW's sign, not normalised) of a real field of rank dim
   * (2 or 3), n[0] x .. x n[dim - 1] row-major (the last index fastest), distributed along n[0] in
   * blocks of `block` rows (process p holds rows [p block, (p + 1) block) clipped to n[0]): in holds
   * this process's rows unpadded, out receives the same rows of the half spectrum (the last axis
   * n[dim - 1] / 2 + 1 long), re and im interleaved. NULL: the group has none (S(k) of a gas split
   * over processes is then refused). */
  int (*fft_r2c)(void *ctx, int dim, const int64_t n[3], int64_t block, const double *in, double *out) = nullptr;
  /* stop every process of the group after an error of this one (`msg` names it; the group prints
   * it with this process's rank): the others would wait for it in the next exchange. NULL: the
   * group has none (the caller returns the error). Does not return. */
  void (*abort)(void *ctx, const char *msg) = nullptr;
};

/* The process group a run's split gas spans (GSRD `[engine] decomposition` under
 * build/granary-mpi: src/io/engine_srd.cpp opens its bricks over it): installed by the program
 * before it runs a scene, copied; NULL or size 1: one process (not thread-safe: call before
 * running). srd_bricks_run_comm_ returns it (size 1 when none is installed). */
void srd_bricks_set_run_comm_(const srd_bricks_comm *comm);
const srd_bricks_comm *srd_bricks_run_comm_();
/* steps done by the split gas */
int64_t srd_bricks_steps_(const srd_bricks_state *st);

/* gran_srd_advance of the decomposable engine: steps s as one brick (engine.cpp calls it) */
int srd_bricks_advance_(gran_srd *s, int64_t steps);
/* adds 0.5 |v|^2 of particles [0, n) to *acc exactly (vz NULL in 2-D): the decomposable engine's
 * initial energy, one compiled instance for the plain engine and the bricks */
void srd_kinetic_exact_(const double *vx, const double *vy, const double *vz, int64_t n, struct gran_exactsum *acc);
#endif

#endif
