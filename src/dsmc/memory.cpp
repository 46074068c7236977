/* memory.cpp - the memory model of a DSMC run (io_impl.h: gran_dsmc_memory_), used by the scene
 * check at load time and by the engine adapter's gran_engine::memory (src/io/engine_dsmc.cpp). */
#include <cmath>

#include "io/engine.h"
#include "io/io_impl.h"

double gran_dsmc_memory_(const gran_scene &s, std::vector<gran_mem_part> &parts) {
  const double M = (double)s.nspecies, nt = (double)s.times.size();
  double N = 0;
  for (int64_t k = 0; k < s.nspecies; k++)
    N += s.counts_kind == 0 ? (double)s.counts[(size_t)k] : std::nearbyint(s.density[(size_t)k] * s.volume);
  double pow2 = 1;
  while (pow2 < M) pow2 *= 2;
  const bool disp = s.obs_msd || s.obs_tamsd, cell = s.selector == GRAN_SELECTOR_CELL;
  const double nc = cell ? (double)s.cell.cells : 0.0;
  /* streams by cell: the key order (4 B per particle), the threads' counts per cell (4 B per cell and
   * thread: bounded here by 4 B per particle and thread, 2 threads counted), a checkpoint's keys (8 B) */
  const double keys = cell && s.cell.streams == GRAN_CELL_STREAMS_CELLS ? 20.0 : 0.0;
  const double particles = N * (28.0 + 24.0 + (disp ? 32.0 : 0.0) + (cell ? 36.0 : 0.0) + keys) + 48.0 * nc * nc * nc;
  const double species = 8.0 * M * 40.0 + 6.0 * 2.0 * pow2 * 8.0;
  const double pairs = (s.model == GRAN_RESTITUTION_MATRIX || s.g2_is_matrix || s.visco_kind == 1 ? 40.0 * M * M : 0.0) +
                       (s.obs_collision_counts ? 8.0 * M * M * 2.0 : 0.0);
  const double trajectories = s.obs_tamsd ? 24.0 * (double)s.tamsd_tracers * M * (double)s.tamsd_samples : 0.0;
  /* the engine and its adapter: structs, about 40 allocations (malloc header and rounding), the
   * adapter's mixture (species tables and theory work space) */
  const double fixed = 4096.0 + 40.0 * gran_alloc_bytes + 64.0 * M;
  /* rows: the buffers gran_engine::declare makes (DSMC adapter: stats 2, T, msd + msd_total,
   * energy 3, momentum, M x M counts, a2, the cluster rows, the speed histograms) */
  const bool agg = s.agg.e_agg > 0 || std::isfinite(s.agg.e_frag);
  double elems = 2, nbuf = 2;
  auto add = [&](bool on, double bufs, double per_row) {
    if (on) nbuf += bufs, elems += per_row;
  };
  add(s.obs_temperatures, 1, M);
  add(s.obs_msd, 2, M + 1);
  add(s.obs_energy, 3, 3);
  add(s.obs_momentum, 1, 3);
  add(s.obs_collision_counts, 1, M * M);
  add(s.obs_sonine_a2, 1, M);
  add(agg, 3, 10 + M);
  add(s.obs_veldist, 1, M * (double)s.vd_bins);
  const double rows = gran_row_bytes_(nbuf, elems, nt);
  /* at the peak: the particle state once more while a checkpoint image is assembled, the
   * trajectories twice while the TAMSD is computed; once per run the dense theory Jacobian */
  const double ck = s.checkpoint_path.empty() ? 0.0 : 1.0;
  const double theory = s.obs_theory ? (M <= 2048 ? 32.0 * M * M : 0.0) + 3.0 * nt * M * 8.0 : 0.0;
  parts.clear();
  parts.push_back({"particles", "engine", s.counts_kind == 0 ? "counts" : s.counts_kind == 1 ? "N1" : "volume", particles,
                   particles * (1.0 + ck), 0.0});
  parts.push_back({"species arrays and trees", "mixture", "nspecies", species, species, 0.0});
  parts.push_back({"M x M tables", "observables", "collision_counts", pairs, pairs, 0.0});
  parts.push_back({"trajectories", "observables", "tamsd", trajectories, 2.0 * trajectories, 0.0});
  parts.push_back({"engine structs", "engine", "replicas", fixed, fixed, 0.0});
  parts.push_back({"recorded rows", "observables", "times", rows, rows, 0.0});
  parts.push_back({"theory", "observables", "theory", 0.0, 0.0, theory});
  return particles + species + pairs + trajectories + fixed + rows;
}
