/* device_cuda_ops.h - the per-particle and per-cell bodies of the GSRD device algorithm, written once
 * (GRAN_HD: `__host__ __device__` under nvcc, plain C99 / C++ otherwise) on top of the shared
 * functions of src/srd/srd_kernels.h. The CUDA kernels (cuda/srd.cu) and the host reference backend
 * (src/srd/device_cuda.cpp, device = GRAN_SRD_DEVICE_REFERENCE) call exactly these, so the CPU tests
 * (t890) cover the arithmetic the GPU runs. Each body reproduces the arithmetic of one phase of the
 * CPU engine's step (src/srd/engine.cpp): t890 checks the engine and the reference to rounding. */
#ifndef GRAN_SRD_DEVICE_CUDA_OPS_H
#define GRAN_SRD_DEVICE_CUDA_OPS_H

#include "srd/srd_kernels.h"

/* effect flags of a run (bit mask; an effect that is off skips its arithmetic) */
enum {
  SRD_FX_ACCEL = 1,  /* constant acceleration g */
  SRD_FX_WALL = 2,   /* walls on gm->wall_axis (reflection, virtual particles) */
  SRD_FX_LE = 4,     /* Lees-Edwards */
  SRD_FX_EPS = 8,    /* eps < 1: eps_eff scaling (Eq. 2.1) */
  SRD_FX_THERMO = 16 /* cell-level Maxwell-Boltzmann thermostat */
};

/* run constants the bodies need (POD, by value into kernels) */
typedef struct srd_dev_const {
  int32_t fx;       /* SRD_FX_* */
  int32_t dim;
  double dt;
  double g[3];      /* acceleration (SRD_FX_ACCEL) */
  double coef;      /* (1 - eps^2) sigma^2 dt (SRD_FX_EPS) */
  double inv_vol;   /* 1 / a^dim */
  double n0;        /* virtual particles fill cut cells up to n0 (SRD_FX_WALL) */
  double wall_T;    /* their temperature */
  double T0;        /* thermostat temperature (SRD_FX_THERMO) */
  double ca, sa;    /* cos, sin of the rotation angle */
} srd_dev_const;

/* accumulators of the streaming pass (energy ledger and Lees-Edwards stress); SRD_ACC_BAD counts the
 * particles whose position or velocity was not finite after a move (the per-step check of the
 * device algorithm: the host reads it with the ledger and names the particle, device_cuda.cpp) */
enum { SRD_ACC_FLUX = 0, SRD_ACC_EXT = 1, SRD_ACC_IMP = 2, SRD_ACC_DE = 3, SRD_ACC_VIR = 4, SRD_ACC_LEW = 5,
       SRD_ACC_BAD = 6, SRD_ACC_N = 7 };

/* Float storage of coordinate k: the rounding may not put a particle onto a wall (on the wall axis
 * a stored position stays in [0, box); periodic axes wrap any value at the next step). */
GRAN_HD static inline float srd_dev_float_pos(const srd_geom *gm, int k, double x) {
  float f = (float)x;
  while (k == gm->wall_axis && (double)f >= gm->box[k]) f = nextafterf(f, 0.0f);
  return f;
}

/* Lees-Edwards kinetic flux: interior planes y = j a (j = 1 .. Ly - 1) crossed upwards minus
 * downwards between y0 and y1 (before the wrap). */
GRAN_HD static inline double srd_dev_planes(double y0, double y1, double a, int64_t Ly) {
  const int64_t k0 = (int64_t)floor(y0 / a), k1 = (int64_t)floor(y1 / a);
  int64_t up = (k1 < Ly - 1 ? k1 : Ly - 1) - (k0 + 1 > 1 ? k0 + 1 : 1) + 1;
  int64_t dn = (k0 < Ly - 1 ? k0 : Ly - 1) - (k1 + 1 > 1 ? k1 + 1 : 1) + 1;
  up = up > 0 ? up : 0;
  dn = dn > 0 ? dn : 0;
  return (double)(up - dn);
}

/* Pass 1 body: stream (with g), Lees-Edwards kinetic flux, wall reflection, periodic / Lees-Edwards
 * wrap of one particle; acc[FLUX], acc[EXT], acc[IMP] accumulate (engine.cpp step phase 1). */
GRAN_HD static inline void srd_dev_move(const srd_dev_const *k, const srd_geom *gm, double p[3], double v[3],
                                        double acc[SRD_ACC_N]) {
  const int fx = k->fx;
  const int ledger = fx & (SRD_FX_ACCEL | SRD_FX_WALL | SRD_FX_LE);
  const double e0 = ledger ? 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) : 0.0;
  const double y0 = p[1];
  srd_stream(p, v, k->dt, k->g, k->dim, fx & SRD_FX_ACCEL);
  if (fx & SRD_FX_LE) { /* kinetic flux averaged over every plane y = const (engine.cpp phase 1) */
    const double dy = p[1] - y0, rate = gm->le_dv / gm->box[1];
    const double vxm = (fx & SRD_FX_ACCEL) ? v[0] - 0.5 * k->g[0] * k->dt : v[0];
    acc[SRD_ACC_FLUX] += (vxm - rate * (y0 + 0.5 * dy - 0.5 * gm->box[1])) * dy;
  }
  if (fx & SRD_FX_WALL) {
    double dpw[3];
    if (srd_wall_reflect(gm, p, v, dpw)) acc[SRD_ACC_IMP] += dpw[gm->wall_axis];
  }
  srd_wrap(gm, p, v);
  if (ledger) acc[SRD_ACC_EXT] += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - e0;
  if (srd_nonfinite(p, v) != 0.0) acc[SRD_ACC_BAD] += 1.0; /* non-finite stays non-finite: see srd_wrap1 */
}

/* Per-cell body (engine.cpp step phase 5): moments from the sums, new reference velocity, virtual
 * particles of a cut cell, random axis (n >= 2), eps_eff and thermostat factors. Returns 1 when the
 * cell collides (n >= 2). *clamped = 1 when eps_eff was clamped; *dt_max then is the largest dt
 * that avoids it (else INFINITY). */
GRAN_HD static inline int srd_dev_cell(const srd_dev_const *k, const srd_geom *gm, const double s[3], int64_t c,
                                       const srd_cell_sum *cs, double vref[3], gran_rng *rng, srd_cell_rot *cr,
                                       int *clamped, double *dt_max) {
  const int dim = k->dim;
  double V[3], th;
  *clamped = 0;
  *dt_max = INFINITY;
  srd_cell_moments(cs, vref, dim, V, &th);
  const int64_t nc = cs->n;
  cr->f = 1.0;
  cr->g = 1.0;
  if (nc > 0)
    for (int q = 0; q < 3; ++q) vref[q] = V[q];
  if (k->fx & SRD_FX_WALL) {
    int lo;
    if (srd_cell_cut(gm, s, c, &lo) && (double)nc < k->n0) {
      /* virtual particles (Sec. 1.3.5.5): n0 - n of them, Maxwellian about the wall velocity */
      const double m = floor(k->n0 - (double)nc + 0.5);
      if (m > 0) {
        const double *ut = lo ? gm->wall_t_lo : gm->wall_t_hi;
        const double uw = lo ? gm->wall_u_lo : gm->wall_u_hi;
        const double sd = sqrt(m * k->wall_T);
        for (int q = 0; q < dim; ++q) {
          const double u = (q == gm->wall_axis) ? uw : ut[q];
          V[q] = ((double)nc * V[q] + m * u + sd * srd_rng_normal(rng)) / ((double)nc + m);
        }
      }
    }
  }
  for (int q = 0; q < 3; ++q) cr->V[q] = V[q];
  if (nc < 2) {
    cr->r[0] = cr->r[1] = 0.0;
    cr->r[2] = 1.0;
    if (!(k->fx & SRD_FX_WALL)) cr->V[0] = cr->V[1] = cr->V[2] = 0.0;
    return 0;
  }
  srd_draw_axis(rng, dim, cr->r);
  if (k->fx & (SRD_FX_EPS | SRD_FX_THERMO)) {
    double f = 1.0;
    if (k->fx & SRD_FX_EPS) {
      const double rho = (double)nc * k->inv_vol;
      f = srd_eps_eff(k->coef, rho, th, clamped);
      if (*clamped) *dt_max = srd_dt_max(k->coef / k->dt, rho, th);
    }
    double sc = 1.0;
    if ((k->fx & SRD_FX_THERMO) && th > 0.0) {
      /* cell-level MB thermostat: kinetic energy of the d (n - 1) thermal dof redrawn */
      const double kk = 0.5 * dim * (double)(nc - 1);
      const double enew = srd_rng_gamma(rng, kk) * k->T0;
      const double eold = 0.5 * dim * (double)nc * th;
      sc = sqrt(enew / eold);
    }
    cr->f = f * sc;
    cr->g = sc;
  }
  return 1;
}

/* Pass 2 body (engine.cpp step phase 6): rotate-and-scale v of a particle at height py whose cell
 * (seen with the Lees-Edwards correction dvx) has record cr; acc[DE], acc[VIR], acc[LEW]. */
GRAN_HD static inline void srd_dev_collide(const srd_dev_const *k, const srd_geom *gm, const srd_cell_rot *cr,
                                           double dvx, double py, double v[3], double acc[SRD_ACC_N]) {
  const int fx = k->fx, dissip = (fx & (SRD_FX_EPS | SRD_FX_THERMO)) != 0;
  const int ledger = dissip || (fx & SRD_FX_WALL);
  v[0] += dvx;
  const double e0 = ledger ? v[0] * v[0] + v[1] * v[1] + v[2] * v[2] : 0.0;
  const double vx0 = v[0];
  srd_rotate(v, cr, k->ca, k->sa, k->dim, dissip);
  if (ledger) acc[SRD_ACC_DE] += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - e0);
  if (fx & SRD_FX_LE) {
    const double yy = (dvx != 0.0) ? py - gm->box[1] : py;
    acc[SRD_ACC_VIR] += (v[0] - vx0) * yy;
    acc[SRD_ACC_LEW] -= dvx * (v[0] - vx0);
  }
  v[0] -= dvx;
}

#endif
