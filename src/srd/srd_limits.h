/* srd_limits.h - the bounds on what a GSRD run derives from its inputs,
 * written once: gran_srd_create and gran_srd_checkpoint_read check them (check_options, engine.cpp),
 * the scene parser checks them with the scene's run length and names the scene key
 * (src/srd/scene_srd.cpp). Each bound is the rule of src/core/derived.h: a derived value
 * must be finite and within its range, else the input is refused by name. README, "GSRD: bounds".
 *
 * Velocity scales u of a run (each only when its effect is on):
 *   T0           thermal speed sqrt(T0)                       wall_T      sqrt(wall_T) of the walls
 *   shear_rate   Lees-Edwards velocity jump |rate| Ly         vib_amp     wall speed amplitude x omega
 *   accel        |g| dt gained per step; sqrt(2 |g_w| L_w) of a fall across the box along the wall
 *                axis; |g| t_end over the run along periodic axes (scene: the run length is known)
 * Bounds (N particles, smallest box length L_min):
 *   displacement per step u dt <= SRD_MAX_BOXES_PER_STEP x L_min (1e6 box lengths: positions
 *     after a step stay below ~1e7 box lengths even for a 10-sigma particle, far inside the 2^53
 *     box lengths where the periodic wrap stops resolving a cell; the wrap is exact beyond that too,
 *     srd_wrap1, but a step that crosses a million boxes is no SRD run);
 *   energy 100 N u^2 <= 1e300 (sums of squares over every particle and its tails stay finite);
 *   T0, wall_T >= 1e-280 (squared thermal speeds are normal doubles: no subnormal arithmetic);
 *   cell volume a^d within [1e-290, 1e290], box lengths cells x a <= 1e290 (densities n0 / a^d,
 *     N / a^d finite and non-zero);
 *   eps < 1: the collision parameter (1 - eps^2) sigma^2 dt (N / a^d) 10 u_max of Eq. 2.1 (every
 *     particle in one cell at ten times the largest speed) <= 1e300, so eps_eff = 1 - kappa is
 *     never inf - inf or inf x 0;
 *   Lees-Edwards: the collisional stress scale (n0 / a^d) 10 u_max Ly / dt <= 1e300 (the stress
 *     is a momentum change per step over dt: a tiny dt with a strong shear overflows it);
 *   precision = float (device storage): every u <= 1e15 and the thermal speeds >= 1e-15 (their
 *     squares, the temperatures, within 1e-30 .. 1e30), a and the box lengths within 1e-30 .. 1e30:
 *     the stored values stay far inside the normal range of float (1.2e-38 .. 3.4e38);
 *   threads <= SRD_MAX_THREADS (4096, the bound of gran_set_threads and [engine] threads); more
 *     than 4 per processor are reduced to that with a warning (engine.cpp, srd_threads_used). */
#ifndef GRAN_SRD_LIMITS_H
#define GRAN_SRD_LIMITS_H

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "granary.h"
#include "core/derived.h"

#define SRD_MAX_BOXES_PER_STEP 1e6
#define SRD_MAX_ENERGY 1e300
#define SRD_MIN_TEMPERATURE 1e-280
#define SRD_FLOAT_LO 1e-30 /* float storage: temperatures and lengths at least this, at most SRD_FLOAT_HI */
#define SRD_FLOAT_HI 1e30
#define SRD_MAX_THREADS 4096

/* the first bound a run breaks: the option it names (gran_srd_options field: "a", "T0", "dt",
 * "wall_T", "shear_rate", "vib_amp", "vib_omega", "accel", "sigma") and the reason */
struct srd_limit_fail {
  const char *key = nullptr;
  std::string why;
};

/* true when the options (already checked one by one: check_options) keep every derived value in
 * its bounds; else false with *f. t_end: the run's length when known (a scene), < 0 otherwise. */
inline bool srd_check_limits(const gran_srd_options &o, double t_end, srd_limit_fail *f) {
  const int d = o.dim;
  double ncb = 1, bmin = HUGE_VAL, bmax = 0, box[3] = {o.a, o.a, o.a};
  for (int k = 0; k < d; ++k) {
    box[k] = (double)o.cells[k] * o.a;
    ncb *= (double)o.cells[k];
    bmin = std::min(bmin, box[k]);
    bmax = std::max(bmax, box[k]);
  }
  const double N = std::floor(o.n0 * ncb + 0.5);
  if (!(N >= 1 && N < 4e9)) return true; /* refused by the particle count check (alloc_state) */
  auto fail = [&](const char *key, const std::string &why, const char *tail = "") {
    if (why.empty()) return false;
    f->key = key;
    f->why = why + tail;
    return true;
  };
  char w[400];
  /* ---- the cell and the box ---- */
  const double vol = d == 3 ? o.a * o.a * o.a : o.a * o.a;
  std::snprintf(w, sizeof w, "the cell volume a^%d (a = %g)", d, o.a);
  if (fail("a", gran_derived_why(vol, 1e-290, 1e290, w), ": the densities n0 / a^d would under- or overflow")) return false;
  std::snprintf(w, sizeof w, "the box length cells x a (a = %g)", o.a);
  if (fail("a", gran_derived_why(bmax, 0, 1e290, w))) return false;
  /* ---- velocity scales ---- */
  struct Scale {
    const char *key;
    double u;
    char what[160];
    bool thermal;
  } us[8]; /* at most 7: T0, wall_T, shear_rate, the wall speed and three of accel */
  int nu = 0;
  auto add = [&](const char *key, double u, bool thermal, const char *fmt, double x) {
    Scale &s = us[nu++];
    s.key = key;
    s.u = u;
    s.thermal = thermal;
    std::snprintf(s.what, sizeof s.what, fmt, x);
  };
  add("T0", std::sqrt(o.T0), true, "the thermal speed sqrt(T0) (T0 = %g)", o.T0);
  if (o.wall_axis >= 0 && o.wall_T > 0) add("wall_T", std::sqrt(o.wall_T), true, "the walls' thermal speed sqrt(wall_T) (wall_T = %g)", o.wall_T);
  if (o.shear_rate != 0) add("shear_rate", std::fabs(o.shear_rate) * box[1], false, "the Lees-Edwards velocity jump |shear_rate| Ly (shear_rate = %g)", o.shear_rate);
  if (o.vib_amp != 0 && o.vib_omega != 0) {
    /* name the factor farther from 1 */
    const bool amp = std::fabs(std::log(std::fabs(o.vib_amp))) >= std::fabs(std::log(std::fabs(o.vib_omega)));
    add(amp ? "vib_amp" : "vib_omega", std::fabs(o.vib_amp * o.vib_omega), false, "the wall speed vib_amp x vib_omega (%g)",
        o.vib_amp * o.vib_omega);
  }
  double g2 = 0, gp2 = 0;
  for (int k = 0; k < d; ++k) {
    g2 += o.accel[k] * o.accel[k];
    if (k != o.wall_axis) gp2 += o.accel[k] * o.accel[k];
  }
  if (g2 > 0 || !std::isfinite(g2)) {
    const double g = std::sqrt(g2);
    add("accel", g * o.dt, false, "the speed |g| dt gained per step (|g| = %g: gravity + body force, option accel)", g);
    if (o.wall_axis >= 0 && o.accel[o.wall_axis] != 0)
      add("accel", std::sqrt(2.0 * std::fabs(o.accel[o.wall_axis]) * box[o.wall_axis]), false,
          "the speed sqrt(2 |g| L) of a fall across the box (g = %g along the walls' axis)", o.accel[o.wall_axis]);
    if (t_end > 0 && gp2 > 0)
      add("accel", std::sqrt(gp2) * t_end, false, "the speed |g| t_end gained over the run along periodic axes (t_end = %g)",
          t_end);
  }
  /* float storage first: its message says why double would do */
  if (o.precision == 1) {
    const char *tail = ": with precision = \"float\" (device storage) speeds must stay within 1e-15 .. 1e15 and their "
                       "squares within 1e-30 .. 1e30; use precision = \"double\"";
    for (int i = 0; i < nu; ++i)
      if (fail(us[i].key, gran_derived_why(us[i].u, us[i].thermal ? 1e-15 : 0.0, 1e15, us[i].what), tail)) return false;
    const char *ltail = ": with precision = \"float\" (device storage) lengths must stay within 1e-30 .. 1e30; use "
                        "precision = \"double\"";
    if (fail("a", gran_derived_why(o.a, SRD_FLOAT_LO, SRD_FLOAT_HI, "the cell size a"), ltail)) return false;
    if (fail("a", gran_derived_why(bmax, SRD_FLOAT_LO, SRD_FLOAT_HI, "the box length cells x a"), ltail)) return false;
  }
  if (fail("T0", gran_derived_why(o.T0, SRD_MIN_TEMPERATURE, HUGE_VAL, "the temperature T0"),
           ": squared thermal speeds would be subnormal doubles (slow and inexact)"))
    return false;
  if (o.wall_axis >= 0 && o.wall_T > 0 &&
      fail("wall_T", gran_derived_why(o.wall_T, SRD_MIN_TEMPERATURE, HUGE_VAL, "the wall temperature wall_T"),
           ": squared thermal speeds would be subnormal doubles (slow and inexact)"))
    return false;
  double umax = 0;
  for (int i = 0; i < nu; ++i) {
    const Scale &s = us[i];
    char e[400];
    std::snprintf(e, sizeof e, "the energy 100 N u^2 of %s, N = %.0f particles", s.what, N);
    if (fail(s.key, gran_derived_why(100.0 * N * s.u * s.u, 0, SRD_MAX_ENERGY, e), ": speeds and energies would overflow"))
      return false;
    /* the displacement u dt in box lengths: name dt when it is the factor farther from 1 */
    const double x = s.u / bmin, disp = x * o.dt;
    const bool blame_dt = std::fabs(std::log(o.dt)) > std::fabs(std::log(x));
    std::snprintf(e, sizeof e, "the displacement per step u dt of %s with dt = %g, in box lengths (smallest box length %g)", s.what,
                  o.dt, bmin);
    if (fail(blame_dt ? "dt" : s.key, gran_derived_why(disp, 0, SRD_MAX_BOXES_PER_STEP, e),
             ": a step may move at most 1e6 box lengths"))
      return false;
    umax = std::max(umax, s.u);
  }
  /* ---- dissipation: kappa of Eq. 2.1 at its largest ---- */
  if (o.eps < 1.0 && o.sigma > 0) {
    const double kap = (1.0 - o.eps * o.eps) * o.sigma * o.sigma * o.dt * (N / vol) * 10.0 * umax;
    if (fail("sigma",
             gran_derived_why(kap, 0, SRD_MAX_ENERGY,
                              "the collision parameter (1 - eps^2) sigma^2 dt (N / a^d) 10 u_max of Eq. 2.1 (every particle in "
                              "one cell, ten times the largest speed)"),
             ": eps_eff = 1 - kappa would not be finite"))
      return false;
  }
  /* ---- Lees-Edwards: the collisional stress, a momentum change per step over dt ---- */
  if (o.shear_rate != 0) {
    const double st = o.n0 / vol * 10.0 * umax * box[1] / o.dt;
    if (fail("dt",
             gran_derived_why(st, 0, SRD_MAX_ENERGY,
                              "the collisional stress scale (n0 / a^d) 10 u_max Ly / dt of the Lees-Edwards shear (every "
                              "collision at ten times the largest speed)"),
             ": the stress would overflow"))
      return false;
  }
  return true;
}

#endif
