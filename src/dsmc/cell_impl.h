/* cell_impl.h - private state of the time-step/cell selector (GRAN_SELECTOR_CELL, seed 002):
 * positions in a cubic periodic box, cells, the fractional candidate numbers carried between
 * steps, and (agg.cpp) the cluster-size bookkeeping of aggregation and fragmentation. Only an
 * engine of this selector allocates any of it (gran_dsmc::cell is NULL otherwise). */
#ifndef GRANARY_DSMC_CELL_IMPL_H
#define GRANARY_DSMC_CELL_IMPL_H

#include "dsmc_impl.h"

#include <cstdlib>
#include <vector>

namespace gran {

struct DsmcCell {
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
  /* aggregation / fragmentation (agg.cpp) */
  int agg = 0;                 /* 1: species are cluster sizes (e_agg > 0 or e_frag finite) */
  double m1 = 1, sigma1 = 1;   /* monomer mass and diameter */
  int64_t kmax = 0;            /* largest cluster size present (agg) */
  std::vector<int64_t> nsize;  /* agg: clusters of size k at [k-1], grown on demand */
  std::vector<double> sigk;    /* agg: diameter of a k-mer at [k-1], grown with nsize */
  std::vector<int64_t> where;  /* agg: position of a particle in the cell list (derived) */
  int64_t ndead = 0;           /* agg: merged-away particles waiting for the end of the step */
  int64_t merges = 0, breakups = 0, bounces = 0;
  double e_merge = 0, e_merge_c = 0; /* energy lost in merges (Neumaier sum, compensation) */
  double e_break = 0, e_break_c = 0; /* lost in breakups */
  double e_heat = 0, e_heat_c = 0;   /* added by the thermostat */
  int64_t monomers = 0;              /* total mass in monomers (conserved) */
};

/* a k-mer (agg): mass k m1, diameter sigma1 k^(1/3) */
static inline double cell_mass(const DsmcCell *c, int64_t k) { return (double)k * c->m1; }
static inline double cell_sigma(const DsmcCell *c, int64_t k) { return c->sigma1 * std::cbrt((double)k); }

/* agg.cpp */
/* checks (mixture of k-mers, constant restitution, observables) and the size tables */
int dsmc_agg_setup(gran_dsmc *s);
/* room for a size k (1-based) in nsize / sigk */
void dsmc_agg_grow(DsmcCell *c, int64_t k);
/* end of a step: drop merged-away particles, counts per species, bounds */
void dsmc_agg_end_step(gran_dsmc *s);
/* per-particle observables of an aggregating gas (species = size - 1): the mixture's M sizes */
void dsmc_agg_mean_flow(const gran_dsmc *s, double u[3]);
void dsmc_agg_temperatures(const gran_dsmc *s, double *T, double *a2);
void dsmc_agg_energy_momentum(const gran_dsmc *s, double *e_kin, double p[3]);

/* cell.cpp */
int dsmc_cell_check_options(const gran_dsmc_cell_options *o);
/* geometry and arrays (positions allocated, not drawn): creation and checkpoint reading */
int dsmc_cell_setup(gran_dsmc *s, const gran_dsmc_cell_options *o);

}  // namespace gran

#endif
