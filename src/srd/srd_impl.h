/* srd_impl.h - private state of the GSRD engine (src/srd/). */
#ifndef GRAN_SRD_IMPL_H
#define GRAN_SRD_IMPL_H

#include "granary_impl.h"
#include "srd/srd_kernels.h"

#include <vector>

struct gran_srd {
  gran_srd_options opt;
  srd_geom gm;
  int64_t n = 0;          /* particles */
  int64_t ncell = 0;      /* cells of the binning grid */
  int64_t ncell_box = 0;  /* cells of the box (unshifted lattice) */
  /* particles, SoA (48 B) + cell index (4 B) */
  std::vector<double> x, y, z, vx, vy, vz;
  std::vector<uint32_t> ci;
  /* cells */
  std::vector<srd_cell_sum> sum;
  std::vector<srd_cell_rot> rot;
  std::vector<double> vref; /* 3 per cell: reference velocity (last cell mean) */
  std::vector<gran_rng> rng; /* one stream per cell: stream c + 1 */
  gran_rng shift_rng;        /* stream 0 */
  double shift[3] = {0, 0, 0};
  /* state */
  int64_t step = 0;
  double time = 0.0;
  double ca = 1.0, sa = 0.0;
  /* energy ledger (per mass; E = sum v^2 / 2 (+ potential)) */
  double e_initial = 0.0;
  double e_coll = 0.0;    /* energy change in collisions (< 0: dissipated; thermostat adds) */
  double e_ext = 0.0;     /* work of walls, Lees-Edwards crossings, forces */
  int64_t clamped = 0;    /* eps_eff clamps since the last observe */
  double dt_max = INFINITY; /* smallest dt_max over clamped cells */
  /* stress (Lees-Edwards) */
  double flux_kin = 0.0;  /* sum over streaming moves of (vx - u(y)) dy (all planes y = const) */
  double flux_coll = 0.0; /* sum dvx * y in collisions */
  double stress_t0 = 0.0; /* time at the last stress reset */
  double wall_impulse[3] = {0, 0, 0};
  /* block partial sums (deterministic reductions independent of thread count) */
  std::vector<double> part;
};

#define SRD_BLOCK 4096

#endif
