/* fields.cpp - cell fields of the GSRD state (density, mean velocity, temperature on the unshifted
 * lattice) for snapshots and velocity profiles, and read-only accessors for the run driver.
 * Reads the engine's state (srd_impl.h) and never changes it. */
#include <cmath>
#include <cstring>
#include <vector>

#include "srd/fields.h"
#include "srd/srd_impl.h"

int64_t gran_srd_steps_(const gran_srd *srd) { return srd->step; }

/** @brief Cell fields of the unshifted lattice of cells[0] x cells[1] (x cells[2]) cells, cell
 *  (i, j, k) at index i + cells[0] (j + cells[1] k), x fastest. count: particles per cell;
 *  velocity: mean velocity [cell][3] (the third component 0 in 2-D); temperature: thermal
 *  temperature sum |v - V|^2 / (d n) (Eq. 1.36 with 1/(d n), as the engine uses). Empty cells give
 *  0 for all three. Any output may be NULL. Serial, in particle order: the same numbers for any
 *  thread count (the decomposable engine, creation by cells: each cell's particles in key order,
 *  the same numbers as its gas split over processes). A particle on the upper wall (x = L a)
 *  counts in the last layer. */
GRAN_EXTERN int gran_srd_fields(gran_srd *srd, double *count, double *velocity, double *temperature) {
  GRAN_CHECK_PTR(srd);
  if (srd->dev.p) GRAN_CALL(gran_srd_dev_sync(srd, 0)); /* a run on a device: bring the host copy up to date */
  /* the decomposable engine: as a split gas computes them (each cell's particles in key order) */
  if (srd->opt.creation == GRAN_SRD_CREATE_CELLS && !srd->dev.p) return srd_fields_cells_(srd, count, velocity, temperature);
  GRAN_TRY {
    const gran_srd *s = srd;
    const int d = s->opt.dim;
    const int64_t L0 = s->gm.L[0], L1 = s->gm.L[1], L2 = d == 3 ? s->gm.L[2] : 1;
    const int64_t nc = L0 * L1 * L2, n = s->n;
    const double inv_a = 1.0 / s->opt.a;
    std::vector<int64_t> cnt((size_t)nc, 0);
    std::vector<double> V((size_t)nc * 3, 0.0), Q((size_t)nc, 0.0);
    std::vector<uint32_t> ci((size_t)n);
    const double *px[3] = {s->x.data(), s->y.data(), d == 3 ? s->z.data() : nullptr};
    const double *pv[3] = {s->vx.data(), s->vy.data(), d == 3 ? s->vz.data() : nullptr};
    const int64_t L[3] = {L0, L1, L2};
    for (int64_t i = 0; i < n; ++i) {
      int64_t c = 0, stride = 1;
      for (int k = 0; k < d; ++k) {
        const int64_t ck = srd_clamp_bin(px[k][i] * inv_a, L[k]); /* also a NaN position: a cell of the grid */
        c += ck * stride;
        stride *= L[k];
      }
      ci[(size_t)i] = (uint32_t)c;
      cnt[(size_t)c]++;
      for (int k = 0; k < d; ++k) V[3 * (size_t)c + k] += pv[k][i];
    }
    for (int64_t c = 0; c < nc; ++c)
      if (cnt[(size_t)c] > 0)
        for (int k = 0; k < 3; ++k) V[3 * (size_t)c + k] /= (double)cnt[(size_t)c];
    for (int64_t i = 0; i < n; ++i) {
      const size_t c = ci[(size_t)i];
      double q = 0;
      for (int k = 0; k < d; ++k) {
        const double u = pv[k][i] - V[3 * c + k];
        q += u * u;
      }
      Q[c] += q;
    }
    for (int64_t c = 0; c < nc; ++c) {
      const double m = (double)cnt[(size_t)c];
      if (count) count[c] = m;
      if (velocity)
        for (int k = 0; k < 3; ++k) velocity[3 * c + k] = V[3 * (size_t)c + k];
      if (temperature) temperature[c] = m > 0 ? Q[(size_t)c] / ((double)d * m) : 0.0;
    }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
