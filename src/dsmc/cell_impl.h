/* cell_impl.h - private state of the time-step/cell selector (GRAN_SELECTOR_CELL, the DSMC outline):
 * positions in a cubic periodic box, cells, the fractional candidate numbers carried between
 * steps, and (agg.cpp) the cluster-size bookkeeping of aggregation and fragmentation. Only an
 * engine of this selector allocates any of it (gran_dsmc::cell is NULL otherwise). */
#ifndef GRANARY_DSMC_CELL_IMPL_H
#define GRANARY_DSMC_CELL_IMPL_H

#include "agg_impl.h"

#include <cstdlib>
#include <vector>

namespace gran {

struct DsmcCell : DsmcAgg { /* DsmcAgg: the cluster sizes (agg.cpp) */
  gran_dsmc_cell_options o{};
  int64_t nc = 1, C = 1;   /* cells per side, cells */
  double L = 1;            /* box side */
  double inv_a = 1;        /* cells per unit length (nc / L) */
  double pfac = 0;         /* F_N dt / V_c (= dt C / V, V the volume per simulated particle) */
  int64_t step = 0;        /* steps done; the state's positions belong to time step * dt */
  double vmax2 = 0;        /* upper bound of |v|^2 over all particles (exact after each streaming) */
  double pmax_last = 0;    /* largest F_N (sigma g)_max dt / V_c of the last step */
  std::vector<double> rem; /* C: fractional candidates carried to the next step */
  /* derived every step (not part of the checkpoint) */
  std::vector<int64_t> start;  /* C+1: cell c holds list[start[c] .. start[c+1]) */
  std::vector<int32_t> list;   /* N: particle indices sorted by cell (stable; N < 2^31 in this selector) */
  std::vector<int32_t> cellof; /* N */
  std::vector<double> cvm2;    /* C: max |v|^2 in the cell */
  std::vector<double> csg;     /* C: max diameter in the cell */
  std::vector<int64_t> fillpos; /* C: scratch of the counting sort */
  /* Cell order (cell.cpp, cell_reorder): every kSortEvery steps the particles of each species are
   * moved into cell order (species ranges kept), so that streaming, binning and the candidates read
   * memory in sequence. Only without aggregation and trajectories and from kReorderMin (3e5) particles;
   * the spare arrays swap with the particles' (malloc, like gran_particles). */
  int reorder = 0;
  double *spare[4] = {nullptr, nullptr, nullptr, nullptr}; /* x, v, r, t_last */
  std::vector<int64_t> cursor;  /* M: scratch of the reorder */
  DsmcCell() = default;
  DsmcCell(const DsmcCell &) = delete;
  DsmcCell &operator=(const DsmcCell &) = delete;
  ~DsmcCell() {
    for (double *a : spare) std::free(a);
  }
  /* GRAN_CELL_STREAMS_CELLS (cell.cpp, "Streams by cell"): order holds the particles in the order of
   * their keys, cell << 32 | the particle's place in its cell's list at the end of the last step (at
   * creation: among its cell's particles, species by species), which is the last step's lists one after
   * the other; the next step's stable sort by cell runs through it, so that each cell's list comes out
   * in key order. Part of the state (checkpoints store the keys). */
  int by_cells = 0;
  std::vector<int32_t> order;  /* N (by_cells) */
  std::vector<int32_t> tcount; /* threads x C: the threaded sort's counts, then places (derived) */
  /* aggregation / fragmentation (agg.cpp; the sizes in DsmcAgg) */
  std::vector<int64_t> where;  /* agg: position of a particle in the cell list (derived) */
  int64_t ndead = 0;           /* agg: merged-away particles waiting for the end of the step */
  double e_heat = 0, e_heat_c = 0;   /* added by the thermostat */
};

/* agg.cpp */
/* end of a step: drop merged-away particles, counts per species, bounds */
void dsmc_agg_end_step(gran_dsmc *s);

/* cell.cpp */
int dsmc_cell_check_options(const gran_dsmc_cell_options *o);
/* geometry and arrays (positions allocated, not drawn): creation and checkpoint reading */
int dsmc_cell_setup(gran_dsmc *s, const gran_dsmc_cell_options *o);
/* GRAN_CELL_STREAMS_CELLS: after dsmc_cell_setup, the initial positions, velocities (species k at
 * temperature T[k], the gas's mean velocity subtracted) and keys, cell by cell; *e_initial their
 * kinetic energy (an exact sum). */
int dsmc_cell_create_by_cells(gran_dsmc *s, const double *T, double *e_initial);
/* GRAN_CELL_STREAMS_CELLS: the particles' keys (N; checkpoints), and the order back from them (a
 * checkpoint read: GRAN_ERR_IO naming 'path' unless they are the keys of the positions, each cell's
 * ranks 0 .. n_c - 1). */
void dsmc_cell_keys(const gran_dsmc *s, int64_t *key);
int dsmc_cell_order_from_keys(gran_dsmc *s, const int64_t *key, const char *path);
/* The bath's expected collisions per particle and step within kBathMaxPerStep (at creation and
 * on a checkpoint read; the speeds as they stand). */
int dsmc_cell_check_bath(const gran_dsmc *s);

}  // namespace gran

#endif
