/* srd_kernels.h - GSRD per-particle and per-cell operations, written once for CPU and GPU.
 *
 * Every function is `static inline` and marked GRAN_HD (`__host__ __device__` under nvcc). No STL,
 * no exceptions, no allocation: the CPU engine (src/srd/engine.cpp) calls them in OpenMP loops,
 * cuda/ calls the same functions from kernels. Plain C structs only (PODs that a kernel can take by
 * value).
 *
 * Model (Zantop): streaming x += v dt (Eq. 2.2, plus a constant acceleration g: x += v dt + g
 * dt^2/2, v += g dt); collision on a grid shifted by a random vector; per cell the number n, mean
 * velocity V and temperature theta (Eqs. 1.34-1.36, theta with 1/(d n)); thermal velocities are
 * rotated by +-alpha (2-D) or by alpha about a random axis (3-D) and their perpendicular part is
 * scaled by eps_eff of Eq. 2.1 (Eqs. 2.3-2.5). eps = 1 compiles the scaling out (SRD_DISSIP = 0).
 *
 * Conventions:
 *  - Positions lie in [0, box) on periodic axes; cell (i, j, k) -> index i + nc0 (j + nc1 k). Every
 *    bin index is clamped into the grid (srd_clamp_bin), whatever the coordinate (also NaN or
 *    huge): no particle is ever binned outside the arrays.
 *  - Grid shift: a vector s with components uniform in [0, a) (the same distribution as
 *    [-a/2, a/2) modulo a); a particle at x is binned in cell floor((x + s) / a) (periodic wrap).
 *    On a wall axis the binning grid has L + 1 layers (layers 0 and L are cut by the walls).
 *  - Lees-Edwards: flow along x, gradient along y. The image above (y + Ly) is displaced by
 *    le_dx in x and moves with +le_dv in vx. Crossing y = Ly downward-wrap: x -= le_dx,
 *    vx -= le_dv (and the reverse at y = 0), both in streaming and when a shifted cell straddles
 *    y = Ly (then vx seen by the cell is corrected by dvx, returned by srd_bin).
 *  - Cell sums relative to a reference velocity Vref (the cell's mean of the previous collision):
 *    S = sum (v - Vref), Q = sum |v - Vref|^2, so that theta = (Q - |S|^2/n) / (d n) keeps its
 *    digits when theta << |V|^2 (after the gas has cooled by 1e8 it is still accurate).
 *  - Per-cell random numbers: cell c of the binning grid owns stream c + 1 of the run's seed
 *    (xoshiro256**, stream = jumps by 2^128, see src/core/rng.cpp); stream 0 draws the grid
 *    shift. The draws of one cell in one step depend on nothing but its stream, so the numbers
 *    are the same for any thread count or launch shape.
 */
#ifndef GRAN_SRD_KERNELS_H
#define GRAN_SRD_KERNELS_H

#include <math.h>
#include <stdint.h>

#include "granary.h"      /* gran_rng (POD of four uint64_t) */
#include "core/xoshiro.h" /* the RNG draws, shared with the core */

#ifndef GRAN_HD
#if defined(__CUDACC__)
#define GRAN_HD __host__ __device__
#else
#define GRAN_HD
#endif
#endif

/* wall rules on the wall axis */
enum { SRD_WALL_NONE = 0, SRD_WALL_NOSLIP = 1, SRD_WALL_SLIP = 2 };

/* Geometry and boundary state of one step (a POD passed by value to kernels). */
typedef struct srd_geom {
  int32_t dim;        /* 2 or 3 */
  int32_t wall_axis;  /* -1: all axes periodic; else the axis with walls at 0 and box[wall_axis] */
  int32_t wall_rule;  /* SRD_WALL_* */
  int32_t le_on;      /* 1: Lees-Edwards across y (flow x) */
  int64_t L[3];       /* cells per axis of the box (1 on unused axes) */
  int64_t nc[3];      /* binning grid per axis: L, or L + 1 on the wall axis */
  double a, inv_a;    /* cell size and its inverse */
  double box[3];      /* L * a */
  double le_dx;       /* Lees-Edwards offset of the upper image, in [0, box[0]) */
  double le_dv;       /* Lees-Edwards velocity jump = shear rate * box[1] */
  double wall_u_lo;   /* wall-axis velocity of the lower wall (vibrating bottom) */
  double wall_u_hi;   /* wall-axis velocity of the upper wall */
  double wall_t_lo[3];/* tangential velocity of the lower wall (velocity of virtual particles) */
  double wall_t_hi[3];/* same for the upper wall */
} srd_geom;

/* Per-cell sums of one step (relative to ref). */
typedef struct srd_cell_sum {
  double S[3]; /* sum (v - Vref) */
  double Q;    /* sum |v - Vref|^2 */
  int64_t n;   /* particles */
} srd_cell_sum;

/* Per-cell collision parameters (what every particle of the cell needs). */
typedef struct srd_cell_rot {
  double V[3]; /* cell mean velocity (incl. virtual particles) */
  double r[3]; /* rotation axis (3-D); r[2] = +-1 for the 2-D sign */
  double f;    /* factor on the perpendicular thermal part: eps_eff (times the thermostat scale) */
  double g;    /* factor on the parallel thermal part (thermostat scale; 1 otherwise) */
} srd_cell_rot;

/* ---- RNG: the core's xoshiro256** draws (src/core/xoshiro.h), so CPU and GPU draw the same bits */
GRAN_HD static inline uint64_t srd_rng_next(gran_rng *r) { return gran_xo_next(r); }
GRAN_HD static inline double srd_rng_uniform(gran_rng *r) { return gran_xo_uniform(r); }
GRAN_HD static inline double srd_rng_normal(gran_rng *r) { return gran_xo_normal(r); }
GRAN_HD static inline void srd_rng_unit3(gran_rng *r, double e[3]) { gran_xo_unit3(r, e); }
/* Gamma(k, 1) for k >= 1 (Marsaglia-Tsang), used by the cell-level MB thermostat. */
GRAN_HD static inline double srd_rng_gamma(gran_rng *r, double k) {
  const double d = k - 1.0 / 3.0, c = 1.0 / sqrt(9.0 * d);
  for (;;) {
    double x, v;
    do {
      x = srd_rng_normal(r);
      v = 1.0 + c * x;
    } while (v <= 0.0);
    v = v * v * v;
    const double u = srd_rng_uniform(r);
    if (u < 1.0 - 0.0331 * x * x * x * x) return d * v;
    if (log(u) < 0.5 * x * x + d * (1.0 - v + log(v))) return d * v;
  }
}

/* ---- streaming ------------------------------------------------------------------------------ */
/* x += v dt + g dt^2 / 2, v += g dt (g = gravity + body force per mass; zero: pure Eq. 2.2). */
GRAN_HD static inline void srd_stream(double p[3], double v[3], double dt, const double g[3], int dim, int accel) {
  for (int k = 0; k < dim; ++k) {
    if (accel) {
      p[k] += (v[k] + 0.5 * g[k] * dt) * dt;
      v[k] += g[k] * dt;
    } else {
      p[k] += v[k] * dt;
    }
  }
}

/* Reflection at the walls of the wall axis (call after srd_stream, before srd_wrap). A particle
 * found beyond a wall is traced back to its crossing point (time t_r ago, in the wall frame) and
 * sent on for t_r with the reflected velocity: no-slip reverses every component relative to the
 * wall (v' = 2u - v), slip only the normal one. Returns the number of reflections (0 or 1; a
 * second crossing in the same step is folded back inside). dp_out: momentum change per mass. */
GRAN_HD static inline int srd_wall_reflect(const srd_geom *gm, double p[3], double v[3], double dp_out[3]) {
  const int w = gm->wall_axis;
  dp_out[0] = dp_out[1] = dp_out[2] = 0.0;
  if (w < 0) return 0;
  double yw, u;
  if (p[w] < 0.0) {
    yw = 0.0;
    u = gm->wall_u_lo;
  } else if (p[w] >= gm->box[w]) {
    yw = gm->box[w];
    u = gm->wall_u_hi;
  } else {
    return 0;
  }
  const double vrel = v[w] - u;
  double tr = vrel != 0.0 ? (p[w] - yw) / vrel : 0.0; /* time since crossing, >= 0 */
  if (!(tr >= 0.0)) tr = 0.0;
  const double *ut = (yw == 0.0) ? gm->wall_t_lo : gm->wall_t_hi;
  for (int k = 0; k < gm->dim; ++k) {
    double uk = (k == w) ? u : ut[k];
    if (k == w || gm->wall_rule == SRD_WALL_NOSLIP) {
      const double pc = p[k] - v[k] * tr; /* crossing point */
      const double vn = 2.0 * uk - v[k];
      dp_out[k] = vn - v[k];
      v[k] = vn;
      p[k] = pc + vn * tr;
    }
  }
  /* the wall moved by at most u dt: keep the particle inside */
  if (p[w] < 0.0) p[w] = 0.0;
  if (p[w] >= gm->box[w]) p[w] = nextafter(gm->box[w], 0.0);
  return 1;
}

/* The periodic wrap's repair (srd_wrap, rare): r = x - b floor(x / b) fell outside [0, b). r = b is
 * -tiny + b rounded (0); a non-finite x stays non-finite (the engine's per-step check names it); far
 * outside the box (|x| >> 2^53 b the product b floor(x / b) is off by more than b) the exact fmod
 * gives x mod b. */
GRAN_HD static inline double srd_wrap_repair(double x, double r, double b) {
  if (r == b) return 0.0;
  if (!(x - x == 0.0)) return x;
  r = fmod(x, b); /* exact, |r| < b, the sign of x */
  if (r < 0.0) r += b;
  return r < b ? r : 0.0;
}
/* x mod b in [0, b) for any finite x (b > 0): x - b floor(x / b), exact for the |x| < 2 b of ordinary
 * steps, repaired when rounding or a huge x puts it outside. */
GRAN_HD static inline double srd_wrap1(double x, double b) {
  const double r = x - b * floor(x / b);
  return r >= 0.0 && r < b ? r : srd_wrap_repair(x, r, b);
}

/* Bin index of the scaled coordinate q = x / a: floor(q) clamped into [0, n - 1], decided in double
 * before any conversion (a NaN, an infinity or a value beyond int64 is never converted). Branch-free:
 * q < 1 or NaN selects 0 (truncation gives 0 for q in [0, 1)), then the minimum with n - 1 (exact for
 * n < 2^53; truncating any q in [n - 1, n) gives n - 1 too), then the truncation. */
GRAN_HD static inline int64_t srd_clamp_bin(double q, int64_t n) {
  const double top = (double)(n - 1);
  double r = q >= 1.0 ? q : 0.0;
  r = r < top ? r : top;
  return (int64_t)r;
}

/* 0 when the three components of p and of v are finite, else NaN (x - x is 0 for every finite x):
 * the per-step finiteness check, a few additions per particle folded into the streaming pass */
GRAN_HD static inline double srd_nonfinite(const double p[3], const double v[3]) {
  return ((p[0] - p[0]) + (p[1] - p[1]) + (p[2] - p[2])) + ((v[0] - v[0]) + (v[1] - v[1]) + (v[2] - v[2]));
}

/* Periodic wrap of the periodic axes, with the Lees-Edwards rule across y; dim, le (gm->le_on) and
 * walls (gm->wall_axis >= 0) as arguments, so that a caller with constants gets the loop unrolled
 * and p kept in registers (srd_wrap below takes them from gm). */
GRAN_HD static inline void srd_wrap_fx(const srd_geom *gm, int dim, int le, int walls, double p[3], double v[3]) {
  if (le && (p[1] >= gm->box[1] || p[1] < 0.0)) {
    /* m images crossed (m = +-1 in an ordinary step; any m when a step moves more than Ly): each
     * shifts x by le_dx and vx by le_dv */
    const double m = floor(p[1] / gm->box[1]);
    p[1] -= m * gm->box[1];
    p[0] -= m * gm->le_dx;
    v[0] -= m * gm->le_dv;
  }
  for (int k = 0; k < dim; ++k) {
    if (walls && k == gm->wall_axis) continue;
    const double b = gm->box[k];
    if (p[k] >= b || p[k] < 0.0) {
      const double r = p[k] - b * floor(p[k] / b);
      p[k] = r >= 0.0 && r < b ? r : srd_wrap_repair(p[k], r, b);
    }
  }
}
GRAN_HD static inline void srd_wrap(const srd_geom *gm, double p[3], double v[3]) {
  srd_wrap_fx(gm, gm->dim, gm->le_on, gm->wall_axis >= 0, p, v);
}

/* A shifted coordinate x taken into [0, b) for binning: x - b floor(x / b) outside [0, b), else x
 * (no repair: srd_clamp_bin takes what rounding leaves). A position in [0, b) shifted by less than
 * b lies in [0, 2 b), where floor(x / b) is 1 beyond b (x / b < 2 rounds below 2) and the result is
 * x - b (exact): that select is the fast path, the division only for what is still outside. */
GRAN_HD static inline double srd_wrap_shifted(double x, double b) {
  const double r = x >= b ? x - b : x;
  return r >= 0.0 && r < b ? r : x - b * floor(x / b);
}
/* Index along a periodic axis or the wall axis k of the shifted cell that holds coordinate x
 * (already shifted: x = p[k] + s[k], Lees-Edwards correction applied on x). */
GRAN_HD static inline int64_t srd_bin_index(const srd_geom *gm, int k, double x) {
  if (k == gm->wall_axis) return srd_clamp_bin(x * gm->inv_a, gm->L[k] + 1); /* layers 0 .. L */
  return srd_clamp_bin(srd_wrap_shifted(x, gm->box[k]) * gm->inv_a, gm->L[k]);
}

/* Index along y (k = 1) of the shifted cell that holds p; *wrapped = 1 when the shifted y lay
 * beyond box[1] on a periodic y axis (the cell straddles y = box[1]: Lees-Edwards image). */
GRAN_HD static inline int64_t srd_bin_y(const srd_geom *gm, const double s[3], const double p[3], int *wrapped) {
  double y = p[1] + s[1];
  int64_t cy;
  *wrapped = 0;
  if (gm->wall_axis == 1) {
    cy = srd_clamp_bin(y * gm->inv_a, gm->L[1] + 1); /* layers 0 .. L */
  } else {
    const int w = y >= gm->box[1];
    y = w ? y - gm->box[1] : y;
    *wrapped = w;
    cy = srd_clamp_bin(y * gm->inv_a, gm->L[1]);
  }
  return cy;
}

/* Index along the slowest axis of the binning grid (y in 2-D, z in 3-D) of the shifted cell that
 * holds p: the layer of srd_bin's cell (srd_bin(...) / (nc[0] nc[1]) in 3-D, / nc[0] in 2-D),
 * without the other axes. */
GRAN_HD static inline int64_t srd_bin_layer(const srd_geom *gm, const double s[3], const double p[3]) {
  if (gm->dim == 2) {
    int w;
    return srd_bin_y(gm, s, p, &w);
  }
  return srd_bin_index(gm, 2, p[2] + s[2]);
}

/* The cell of the shifted grid that holds p, as its three indices c (0 on the axes beyond dim). *dvx is
 * the x-velocity correction seen by that cell (Lees-Edwards: +-le_dv when the shifted cell straddles
 * y = box[1], else 0). */
GRAN_HD static inline void srd_bin3(const srd_geom *gm, const double s[3], const double p[3], int64_t c[3],
                                    double *dvx) {
  double px = p[0];
  *dvx = 0.0;
  c[0] = c[1] = c[2] = 0;
  if (gm->dim > 1) {
    int wrapped;
    c[1] = srd_bin_y(gm, s, p, &wrapped);
    if (wrapped && gm->le_on) {
      px -= gm->le_dx;
      *dvx = -gm->le_dv;
    }
  }
  c[0] = srd_bin_index(gm, 0, px + s[0]);
  if (gm->dim > 2) c[2] = srd_bin_index(gm, 2, p[2] + s[2]);
}
/* The same cell as its index in the grid. */
GRAN_HD static inline int64_t srd_bin(const srd_geom *gm, const double s[3], const double p[3], double *dvx) {
  int64_t c[3];
  srd_bin3(gm, s, p, c, dvx);
  return c[0] + gm->nc[0] * (c[1] + gm->nc[1] * c[2]);
}

/* Is cell c cut by a wall (it has virtual particles)? Layer 0 and layer L of the wall axis when the
 * shift along it is > 0. */
GRAN_HD static inline int srd_cell_cut(const srd_geom *gm, const double s[3], int64_t c, int *lo) {
  const int w = gm->wall_axis;
  if (w < 0 || s[w] == 0.0) return 0;
  int64_t cw = c;
  if (w >= 1) cw /= gm->nc[0];
  if (w >= 2) cw /= gm->nc[1];
  cw %= gm->nc[w];
  if (cw == 0) {
    *lo = 1;
    return 1;
  }
  if (cw == gm->L[w]) {
    *lo = 0;
    return 1;
  }
  return 0;
}

/* ---- cell sums ------------------------------------------------------------------------------ */
GRAN_HD static inline void srd_sum_clear(srd_cell_sum *cs) {
  cs->S[0] = cs->S[1] = cs->S[2] = 0.0;
  cs->Q = 0.0;
  cs->n = 0;
}
/* Add one particle with velocity v (already corrected by dvx) relative to ref. */
GRAN_HD static inline void srd_sum_add(srd_cell_sum *cs, const double v[3], const double ref[3], int dim) {
  double q = 0.0;
  for (int k = 0; k < dim; ++k) {
    const double d = v[k] - ref[k];
    cs->S[k] += d;
    q += d * d;
  }
  cs->Q += q;
  cs->n += 1;
}
/* Mean velocity and temperature (Eqs. 1.35, 1.36 with 1/(d n), m = 1) from the sums. */
GRAN_HD static inline void srd_cell_moments(const srd_cell_sum *cs, const double ref[3], int dim, double V[3], double *theta) {
  V[0] = V[1] = V[2] = 0.0;
  *theta = 0.0;
  if (cs->n <= 0) return;
  const double inv = 1.0 / (double)cs->n;
  double s2 = 0.0;
  for (int k = 0; k < dim; ++k) {
    V[k] = ref[k] + cs->S[k] * inv;
    s2 += cs->S[k] * cs->S[k];
  }
  double th = (cs->Q - s2 * inv) * inv / (double)dim;
  *theta = th > 0.0 ? th : 0.0;
}

/* ---- dissipation ---------------------------------------------------------------------------- */
/* Eq. 2.1: eps_eff = 1 - (1 - eps^2) sigma^2 rho sqrt(theta) dt, rho = n / a^d. Clamped to [0, 1];
 * *clamped is set to 1 when the raw value fell outside. */
GRAN_HD static inline double srd_eps_eff(double one_minus_eps2_sigma2_dt, double rho, double theta, int *clamped) {
  double e = 1.0 - one_minus_eps2_sigma2_dt * rho * sqrt(theta);
  *clamped = 0;
  if (!(e >= 0.0)) { /* below 0, or NaN (inf x 0: never with the limits of srd_limits.h) */
    e = 0.0;
    *clamped = 1;
  } else if (e > 1.0) {
    e = 1.0;
    *clamped = 1;
  }
  return e;
}
/* Largest dt for which eps_eff(cell) >= 0: 1 / ((1 - eps^2) sigma^2 rho sqrt(theta)). */
GRAN_HD static inline double srd_dt_max(double one_minus_eps2_sigma2, double rho, double theta) {
  const double d = one_minus_eps2_sigma2 * rho * sqrt(theta);
  return d > 0.0 ? 1.0 / d : INFINITY;
}

/* ---- rotation ------------------------------------------------------------------------------- */
/* Per-cell random part of one collision: 2-D a sign (r[2] = +-1), 3-D a uniform axis. */
GRAN_HD static inline void srd_draw_axis(gran_rng *rng, int dim, double r[3]) {
  if (dim == 2) {
    r[0] = r[1] = 0.0;
    r[2] = (srd_rng_next(rng) >> 63) ? 1.0 : -1.0;
  } else {
    srd_rng_unit3(rng, r);
  }
}

/* v <- V + g u_par + f R(alpha) u_perp, u = v - V (Eqs. 2.3-2.5). 2-D: rotation by r[2] * alpha
 * in the plane (u_par = 0). 3-D: rotation by alpha about r, f applied to the part perpendicular to
 * r only. ca, sa = cos alpha, sin alpha. DISSIP = 0 compiles f and g out (standard SRD, eps = 1). */
GRAN_HD static inline void srd_rotate(double v[3], const srd_cell_rot *cr, double ca, double sa, int dim, int dissip) {
  const double ux = v[0] - cr->V[0], uy = v[1] - cr->V[1];
  if (dim == 2) {
    const double s = sa * cr->r[2];
    double wx = ca * ux - s * uy, wy = s * ux + ca * uy;
    if (dissip) {
      wx *= cr->f;
      wy *= cr->f;
    }
    v[0] = cr->V[0] + wx;
    v[1] = cr->V[1] + wy;
    return;
  }
  const double uz = v[2] - cr->V[2];
  const double *r = cr->r;
  const double up = ux * r[0] + uy * r[1] + uz * r[2];
  const double px = ux - up * r[0], py = uy - up * r[1], pz = uz - up * r[2]; /* perpendicular */
  const double cx = r[1] * pz - r[2] * py, cy = r[2] * px - r[0] * pz, cz = r[0] * py - r[1] * px;
  double wx = ca * px + sa * cx, wy = ca * py + sa * cy, wz = ca * pz + sa * cz;
  double q = up;
  if (dissip) {
    wx *= cr->f;
    wy *= cr->f;
    wz *= cr->f;
    q *= cr->g;
  }
  v[0] = cr->V[0] + q * r[0] + wx;
  v[1] = cr->V[1] + q * r[1] + wy;
  v[2] = cr->V[2] + q * r[2] + wz;
}

#endif /* GRAN_SRD_KERNELS_H */
