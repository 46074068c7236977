/* rules.h - the GSRD step rules, written once for the CPU engine and the devices.
 *
 * One step of GSRD is, per particle, a move (srd_rule_move), per cell of the shifted grid a
 * collision rule (srd_rule_cell; with the global thermostat, after a sum over the cells of
 * srd_rule_thermal and srd_rule_gscale), and per particle the collision (srd_rule_collide). These
 * functions are the whole physics of a step; the callers only iterate and store:
 *  - the CPU engine (src/srd/engine.cpp): OpenMP loops over blocks of particles and slabs of cells
 *    (its collision loop writes srd_rule_collide out with its template flags, for the bits: see
 *    there and docs/developers/gsrd-rules.md);
 *  - the GPU (cuda/srd.cu): one kernel per phase, a thread per particle or cell;
 *  - the host reference of the device algorithm (src/srd/device_cuda.cpp): plain serial loops.
 * They are built on the primitives of src/srd/srd_kernels.h and are C99 / C++ / CUDA alike
 * (SRD_RULE: `__host__ __device__` and forced inline under nvcc, forced inline under GCC).
 *
 * Effects: every rule takes the effect mask fx (SRD_FX_*) and the dimension as arguments. The
 * devices pass the run's values (srd_rule_const.fx, .dim); the CPU engine passes values in which
 * the template flags of its step loop are compile-time constants (srd_rule_fx_fold), so that an
 * effect that is off is compiled out of its loops (the rules are always inlined).
 *
 * Accumulators: the ledger and stress terms of a particle are added to acc[SRD_ACC_*], a
 * caller-owned array (a block's or a slab's partial on the CPU, a thread's on the GPU, the run's
 * on the reference); the caller adds the partials up in its own fixed order. */
#ifndef GRAN_SRD_RULES_H
#define GRAN_SRD_RULES_H

#include "srd/srd_kernels.h"

#if defined(__CUDACC__)
#define SRD_RULE static __host__ __device__ __forceinline__
#elif defined(__GNUC__)
#define SRD_RULE static inline __attribute__((always_inline))
#else
#define SRD_RULE static inline
#endif

/* effects of a run (bit mask; an effect that is off skips its arithmetic) */
enum {
  SRD_FX_ACCEL = 1,    /* constant acceleration g */
  SRD_FX_WALL = 2,     /* walls on gm->wall_axis (reflection, virtual particles) */
  SRD_FX_LE = 4,       /* Lees-Edwards shear across y */
  SRD_FX_EPS = 8,      /* eps < 1: eps_eff scaling (Eq. 2.1) */
  SRD_FX_THERMO = 16,  /* cell-level Maxwell-Boltzmann thermostat (option thermostat = 1) */
  SRD_FX_GTHERMO = 32, /* global profile-unbiased thermostat (thermostat = 2): one factor per step */
  SRD_FX_DISSIP = 64,  /* collisions scale the thermal velocities: set with EPS, THERMO or GTHERMO */
  SRD_FX_ALL = 127
};

/* the accumulators of the rules (energy ledger, Lees-Edwards stress, wall impulse); SRD_ACC_BAD is
 * the devices' count of moves that left a non-finite position or velocity (the per-step check; the
 * CPU engine checks its blocks' positions instead and names the particle) */
enum { SRD_ACC_FLUX = 0, SRD_ACC_EXT = 1, SRD_ACC_IMP = 2, SRD_ACC_DE = 3, SRD_ACC_VIR = 4, SRD_ACC_LEW = 5,
       SRD_ACC_BAD = 6, SRD_ACC_N = 7 };

/* Run constants of the rules (POD, by value into kernels); made from the launcher parameters by
 * srd_rule_const_of (cuda/srd_cuda.h), for the CPU engine and the devices alike. */
typedef struct srd_rule_const {
  int32_t fx;     /* SRD_FX_* (DISSIP set whenever EPS, THERMO or GTHERMO is) */
  int32_t dim;
  double dt;
  double g[3];    /* acceleration (SRD_FX_ACCEL) */
  double rate;    /* shear rate d u_x / d y (SRD_FX_LE) */
  double coef;    /* (1 - eps^2) sigma^2 dt (SRD_FX_EPS) */
  double inv_vol; /* 1 / a^dim */
  double n0;      /* virtual particles fill cut cells up to n0 (SRD_FX_WALL) */
  double wall_T;  /* their temperature */
  double T0;      /* thermostat temperature (SRD_FX_THERMO, SRD_FX_GTHERMO) */
  double ca, sa;  /* cos, sin of the rotation angle */
} srd_rule_const;

/* fx with DISSIP derived from the dissipative effects */
SRD_RULE int32_t srd_rule_fx_norm(int32_t fx) {
  fx &= ~SRD_FX_DISSIP;
  return fx | ((fx & (SRD_FX_EPS | SRD_FX_THERMO | SRD_FX_GTHERMO)) ? SRD_FX_DISSIP : 0);
}
/* The effects of a run's options (the one place that maps options to SRD_FX_*). */
static inline int32_t srd_fx_of(const gran_srd_options *o) {
  const int32_t fx = (o->accel[0] != 0 || o->accel[1] != 0 || o->accel[2] != 0 ? SRD_FX_ACCEL : 0) |
                     (o->wall_axis >= 0 ? SRD_FX_WALL : 0) | (o->shear_rate != 0 ? SRD_FX_LE : 0) |
                     (o->eps < 1.0 ? SRD_FX_EPS : 0) | (o->thermostat == 1 ? SRD_FX_THERMO : 0) |
                     (o->thermostat == 2 ? SRD_FX_GTHERMO : 0);
  return srd_rule_fx_norm(fx);
}
/* The effect mask of a CPU step loop: `fixed` holds the effects of its template flags (ACCEL, WALL,
 * LE, DISSIP), known at compile time; the dissipative kinds come from the run's fx when DISSIP is
 * among them. Every bit but EPS / THERMO / GTHERMO is then a constant the compiler folds. */
SRD_RULE int32_t srd_rule_fx_fold(int32_t fixed, int32_t run_fx) {
  return fixed | ((fixed & SRD_FX_DISSIP) ? (run_fx & (SRD_FX_EPS | SRD_FX_THERMO | SRD_FX_GTHERMO)) : 0);
}

/* ---- per particle: the move ------------------------------------------------------------------ */
/* Stream (with g), Lees-Edwards kinetic flux, wall reflection, periodic / Lees-Edwards wrap of one
 * particle. acc[FLUX]: the kinetic momentum flux averaged over every plane y = const (Eq. 1.43
 * integrated over the plane position): each plane y_p between y0 and y1 sees the particle cross
 * with vx relative to the imposed flow there, u(y_p) = rate (y_p - Ly/2); the integral over y_p is
 * (vx_mid - u((y0 + y1)/2)) (y1 - y0), y unwrapped during the step (the same mean as counting
 * crossings of discrete planes, far less noise). acc[EXT]: the kinetic energy the move changed
 * (gravity, walls, Lees-Edwards crossings); acc[IMP]: the momentum the walls gave (wall axis). */
SRD_RULE void srd_rule_move(int fx, int dim, const srd_rule_const *k, const srd_geom *gm, double p[3], double v[3],
                            double acc[SRD_ACC_N]) {
  const int ledger = fx & (SRD_FX_ACCEL | SRD_FX_WALL | SRD_FX_LE);
  const double e0 = ledger ? 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) : 0.0;
  const double y0 = p[1];
  srd_stream(p, v, k->dt, k->g, dim, fx & SRD_FX_ACCEL);
  if (fx & SRD_FX_LE) {
    const double dy = p[1] - y0;
    const double vxm = (fx & SRD_FX_ACCEL) ? v[0] - 0.5 * k->g[0] * k->dt : v[0];
    acc[SRD_ACC_FLUX] += (vxm - k->rate * (y0 + 0.5 * dy - 0.5 * gm->box[1])) * dy;
  }
  if (fx & SRD_FX_WALL) {
    double dpw[3];
    if (srd_wall_reflect(gm, p, v, dpw)) acc[SRD_ACC_IMP] += dpw[gm->wall_axis];
  }
  srd_wrap_fx(gm, dim, fx & SRD_FX_LE, fx & SRD_FX_WALL, p, v);
  if (ledger) acc[SRD_ACC_EXT] += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) - e0;
}

/* ---- per cell: the global thermostat's sums -------------------------------------------------- */
/* One cell's part of the global profile-unbiased thermostat (SRD_FX_GTHERMO): *e = d n theta (twice
 * the thermal kinetic energy relative to the cell mean), *dof = d (n - 1); returns 0 (and sets
 * nothing) for a cell with n < 2. The callers add every cell's part (in their fixed order) before
 * any cell collides. */
SRD_RULE int srd_rule_thermal(int dim, const srd_cell_sum *cs, const double vref[3], double *e, double *dof) {
  if (cs->n < 2) return 0;
  double V[3], th;
  srd_cell_moments(cs, vref, dim, V, &th);
  *e = (double)(dim * cs->n) * th;
  *dof = (double)(dim * (cs->n - 1));
  return 1;
}
/* The global thermostat's factor on the thermal velocities: thermal energy d T0 sum (n_c - 1) / 2
 * after the collision (1 when the gas has no thermal energy). */
SRD_RULE double srd_rule_gscale(double e, double dof, double T0) { return e > 0.0 ? sqrt(dof * T0 / e) : 1.0; }

/* ---- per cell: the collision rule ------------------------------------------------------------ */
/* Cell c of the shifted grid (shift s) with sums cs relative to vref: the moments; the new mean
 * (the old reference in an empty cell), mixed with the virtual particles of a cut cell (SRD_FX_WALL:
 * n0 - n of them, Maxwellian at wall_T about the wall velocity, Sec. 1.3.5.5), becomes the cell's
 * reference vref and the record's V; a cell with n >= 2 draws its axis and the factors of its
 * thermal velocities: eps_eff (SRD_FX_EPS, Eq. 2.1) times the thermostat's scale (SRD_FX_GTHERMO:
 * gscale, srd_rule_gscale of the step; SRD_FX_THERMO: the kinetic energy of the d (n - 1) thermal
 * degrees of freedom redrawn from its Gamma distribution at T0). Draws from the cell's own stream
 * rng only. Returns 1 when the cell collides (n >= 2; the record's axis is then non-zero, else
 * r = 0). *clamped = 1 when eps_eff was clamped, *dt_max then the largest dt that avoids it (else
 * INFINITY). cs must not share memory with cr. */
SRD_RULE int srd_rule_cell(int fx, int dim, const srd_rule_const *k, const srd_geom *gm, const double s[3], int64_t c,
                           const srd_cell_sum *cs, double gscale, double vref[3], gran_rng *rng, srd_cell_rot *cr,
                           int *clamped, double *dt_max) {
  double V[3], th;
  *clamped = 0;
  *dt_max = INFINITY;
  srd_cell_moments(cs, vref, dim, V, &th);
  const int64_t nc = cs->n;
  if (nc == 0)
    for (int q = 0; q < 3; ++q) V[q] = vref[q];
  cr->f = 1.0;
  cr->g = 1.0;
  if (fx & SRD_FX_WALL) {
    int lo;
    if (srd_cell_cut(gm, s, c, &lo) && (double)nc < k->n0) {
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
  for (int q = 0; q < 3; ++q) cr->V[q] = vref[q] = V[q];
  if (nc < 2) {
    cr->r[0] = cr->r[1] = cr->r[2] = 0.0; /* no collision in this cell */
    return 0;
  }
  srd_draw_axis(rng, dim, cr->r);
  if (fx & SRD_FX_DISSIP) {
    double f = 1.0;
    if (fx & SRD_FX_EPS) {
      const double rho = (double)nc * k->inv_vol;
      f = srd_eps_eff(k->coef, rho, th, clamped);
      if (*clamped) *dt_max = srd_dt_max(k->coef / k->dt, rho, th);
    }
    double sc = 1.0;
    if (fx & SRD_FX_GTHERMO) {
      sc = gscale;
    } else if ((fx & SRD_FX_THERMO) && th > 0.0) {
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

/* ---- per particle: the collision ------------------------------------------------------------- */
/* Rotate-and-scale the velocity v of a particle at height py in a cell with record cr, seen with
 * the Lees-Edwards correction dvx (srd_bin: -le_dv when the shifted cell straddles y = Ly, else 0).
 * A cell that does not collide (r = 0) leaves v as it is (up to the rounding of v_x + dvx - dvx
 * under Lees-Edwards). acc[DE]: the energy change; acc[VIR]: the collisional stress (dvx y);
 * acc[LEW]: the Lees-Edwards work (the lab-frame energy change minus the cell-frame one). */
SRD_RULE void srd_rule_collide(int fx, int dim, const srd_rule_const *k, const srd_geom *gm, const srd_cell_rot *cr,
                               double dvx, double py, double v[3], double acc[SRD_ACC_N]) {
  const int dissip = fx & SRD_FX_DISSIP;
  const int ledger = dissip || (fx & SRD_FX_WALL);
  if (fx & SRD_FX_LE) v[0] += dvx;
  const double e0 = ledger ? v[0] * v[0] + v[1] * v[1] + v[2] * v[2] : 0.0;
  const double vx0 = v[0];
  if (cr->r[0] != 0.0 || cr->r[1] != 0.0 || cr->r[2] != 0.0) srd_rotate(v, cr, k->ca, k->sa, dim, dissip);
  if (ledger) acc[SRD_ACC_DE] += 0.5 * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2] - e0);
  if (fx & SRD_FX_LE) {
    const double yy = (dvx != 0.0) ? py - gm->box[1] : py;
    acc[SRD_ACC_VIR] += (v[0] - vx0) * yy;
    acc[SRD_ACC_LEW] -= dvx * (v[0] - vx0);
    v[0] -= dvx;
  }
}

#endif /* GRAN_SRD_RULES_H */
