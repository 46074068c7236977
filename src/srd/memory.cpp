/* memory.cpp - the memory model of a GSRD run (io_impl.h: gran_srd_memory_), used by the scene
 * check at load time and by the engine adapter's gran_engine::memory (src/io/engine_srd.cpp). */
#include <algorithm>
#include <cmath>

#include "io/engine.h"
#include "io/io_impl.h"
#include "srd/srd_impl.h" /* SRD_SLAB_CELLS, srd_threads_used, struct gran_srd */

double gran_srd_memory_(const gran_scene &s, std::vector<gran_mem_part> &parts) {
  const gran_srd_options &o = s.srd.opt;
  double box = 1, bin = 1;
  for (int k = 0; k < o.dim; k++) {
    box *= (double)o.cells[k];
    bin *= (double)(o.cells[k] + (k == o.wall_axis ? 1 : 0)); /* walls: one more layer to shift into */
  }
  const double N = std::floor(o.n0 * box + 0.5), slab = std::min(bin, (double)SRD_SLAB_CELLS);
  int threads = srd_threads_used(o.threads); /* the engine's count (at most 4 per processor) */
  if (threads <= 0) threads = 1;
  const double particles = N * (48.0 + 2.0 + 12.0);
  const double cells = bin * (56.0 + 8.0) + (double)threads * (64.0 * slab + 4.0 * N * slab / bin);
  const double snapshots = (double)s.srd.snap_index.size() * box * 5.0 * 8.0;
  /* struct gran_srd, its 16 allocations, the adapter (SrdEngine and its copy of the options) */
  const double fixed = (double)sizeof(gran_srd) + 16.0 * gran_alloc_bytes + 2.0 * (double)sizeof(gran_srd_options) + 256.0;
  /* rows: the buffers of the GSRD adapter's declare (engine_srd.cpp) */
  const auto &q = s.srd;
  double elems = 1, nbuf = 1;
  auto add = [&](bool on, double bufs, double per_row) {
    if (on) nbuf += bufs, elems += per_row;
  };
  add(q.obs_temperature, 2, 2);
  add(q.obs_energy, 5, 5);
  add(o.eps < 1.0, 2, 2);
  add(q.obs_momentum, 1, 3);
  add(q.obs_clustering, 3, 3);
  add(q.obs_a2, 1, 1);
  add(q.obs_sk, 1, (double)q.sk_bins);
  add(q.obs_stress, 3, 3);
  add(q.obs_profile, 1, 3.0 * (double)o.cells[1]);
  const double rows = gran_row_bytes_(nbuf, elems, (double)s.times.size());
  /* at the peak: the 48 B of particle state once more while a checkpoint image is assembled */
  const double ck = s.checkpoint_path.empty() ? 0.0 : 1.0;
  parts.clear();
  parts.push_back({"particles", "engine", "n0", particles, particles + ck * 48.0 * (particles / 62.0), 0.0});
  parts.push_back({"cells", "engine", "cells", cells, cells, 0.0});
  parts.push_back({"snapshots", "observables", "snapshots", snapshots, snapshots, 0.0});
  parts.push_back({"engine structs", "engine", "replicas", fixed, fixed, 0.0});
  parts.push_back({"recorded rows", "observables", "every", rows, rows, 0.0});
  return particles + cells + snapshots + fixed + rows;
}
