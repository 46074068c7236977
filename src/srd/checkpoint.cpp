/* checkpoint.cpp - the GSRD engine state as a versioned HDF5 group ("granary-srd-state 1"), written
 * and read through the state interface of the I/O layer (src/io/state.h): a restart continues bit
 * for bit on any device and with any thread count.
 *
 * Group layout (every field a named 1-D dataset):
 *   options/<name>  every field of gran_srd_options under its own name (kOptions below: dim,
 *                   wall_axis, wall_rule, thermostat, cells[3], a, n0, dt, alpha, eps, sigma, T0,
 *                   shear_rate, accel[3], vib_amp, vib_omega, wall_T, seed, sort_every, threads,
 *                   device, precision, creation)
 *   counters        step, clamped, n (int64 each, one dataset per name)
 *   energies        e_initial, e_collisions, e_external; time, dt_max, flux_kin, flux_coll,
 *                   stress_t0, wall_impulse[3] (double)
 *   arrays          x, y, (z), vx, vy, (vz): n each; cell_velocity: 3 per cell of the binning
 *                   grid; rng: 4 uint64 per cell; shift_rng: 4 uint64 (the grid shift's stream)
 * Read: the options are read and pass gran_srd_create's check (a refusal names the option), the
 * array sizes they imply are compared with the file's before anything is allocated, then every
 * value is validated (srd_state_validate), each refusal naming the field. The run driver passes
 * the scene's options and the replica's seed: each stored option is then compared with those,
 * field by field (threads and device excepted). */
#include "srd/srd_impl.h"
#include "io/state.h"

#include <cfloat>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace {

const char *kSrdFormat = "granary-srd-state 1";

/* ---- the options, one entry per field of gran_srd_options ---- */
enum OptType { kI32, kI64, kF64, kU64 };
struct OptField {
  const char *name; /* dataset under options/, the name gran_srd_create's messages use */
  OptType type;
  size_t off;
  int count;
  bool compared; /* compared with the run's on resume (the seed with the replica's own); not:
                    threads and device, how and not what is computed */
};
#define SRD_OPT(field, name, type, count, compared) {name, type, offsetof(gran_srd_options, field), count, compared}
constexpr OptField kOptions[] = {
    SRD_OPT(dim, "dim", kI32, 1, true),
    SRD_OPT(wall_axis, "wall_axis", kI32, 1, true),
    SRD_OPT(wall_rule, "wall_rule", kI32, 1, true),
    SRD_OPT(thermostat, "thermostat", kI32, 1, true),
    SRD_OPT(cells, "cells", kI64, 3, true),
    SRD_OPT(a, "a", kF64, 1, true),
    SRD_OPT(n0, "n0", kF64, 1, true),
    SRD_OPT(dt, "dt", kF64, 1, true),
    SRD_OPT(alpha_deg, "alpha", kF64, 1, true),
    SRD_OPT(eps, "eps", kF64, 1, true),
    SRD_OPT(sigma, "sigma", kF64, 1, true),
    SRD_OPT(T0, "T0", kF64, 1, true),
    SRD_OPT(shear_rate, "shear_rate", kF64, 1, true),
    SRD_OPT(accel, "accel", kF64, 3, true),
    SRD_OPT(vib_amp, "vib_amp", kF64, 1, true),
    SRD_OPT(vib_omega, "vib_omega", kF64, 1, true),
    SRD_OPT(wall_T, "wall_T", kF64, 1, true),
    SRD_OPT(seed, "seed", kU64, 1, true),
    SRD_OPT(sort_every, "sort_every", kI32, 1, true),
    SRD_OPT(threads, "threads", kI32, 1, false),
    SRD_OPT(device, "device", kI32, 1, false),
    SRD_OPT(precision, "precision", kI32, 1, true),
    SRD_OPT(creation, "creation", kI32, 1, true),
};
#undef SRD_OPT
constexpr size_t opt_size(OptType t) { return t == kI32 ? 4 : 8; }
constexpr size_t options_bytes() {
  size_t b = 0;
  for (const OptField &f : kOptions) b += opt_size(f.type) * (size_t)f.count;
  return b;
}
/* every field but pad_ is stored */
static_assert(options_bytes() + sizeof(int32_t) == sizeof(gran_srd_options),
              "gran_srd_options changed: add the new field to kOptions (src/srd/checkpoint.cpp)");

const char *kScalarName[11] = {"time",      "e_initial", "e_collisions", "e_external",      "dt_max",         "flux_kin",
                               "flux_coll", "stress_t0", "wall_impulse[0]", "wall_impulse[1]", "wall_impulse[2]"};

int options_write(const gran_state::Group &g, const gran_srd_options &o) {
  const unsigned char *b = (const unsigned char *)&o;
  for (const OptField &f : kOptions) {
    const void *p = b + f.off;
    switch (f.type) {
      case kI32: GRAN_CALL(g.put(f.name, f.count, (const int32_t *)p)); break;
      case kI64: GRAN_CALL(g.put(f.name, f.count, (const int64_t *)p)); break;
      case kF64: GRAN_CALL(g.put(f.name, f.count, (const double *)p)); break;
      case kU64: GRAN_CALL(g.put(f.name, f.count, (const uint64_t *)p)); break;
    }
  }
  return GRAN_SUCCESS;
}

int options_read(const gran_state::Group &g, gran_srd_options *o) {
  std::memset(o, 0, sizeof *o);
  unsigned char *b = (unsigned char *)o;
  for (const OptField &f : kOptions) {
    void *p = b + f.off;
    /* a state written before the option existed: creation was serial (the only one then); it
     * matters only at creation, so the state is the same */
    if (p == (void *)&o->creation && !g.has(f.name)) {
      o->creation = GRAN_SRD_CREATE_SERIAL;
      continue;
    }
    switch (f.type) {
      case kI32: GRAN_CALL(g.get(f.name, f.count, (int32_t *)p)); break;
      case kI64: GRAN_CALL(g.get(f.name, f.count, (int64_t *)p)); break;
      case kF64: GRAN_CALL(g.get(f.name, f.count, (double *)p)); break;
      case kU64: GRAN_CALL(g.get(f.name, f.count, (uint64_t *)p)); break;
    }
  }
  return GRAN_SUCCESS;
}

/* the value of element k of an option, for messages */
std::string opt_value(const gran_srd_options &o, const OptField &f, int k) {
  const unsigned char *p = (const unsigned char *)&o + f.off + opt_size(f.type) * (size_t)k;
  char buf[64];
  switch (f.type) {
    case kI32: std::snprintf(buf, sizeof buf, "%d", (int)*(const int32_t *)p); break;
    case kI64: std::snprintf(buf, sizeof buf, "%" PRId64, *(const int64_t *)p); break;
    case kF64: std::snprintf(buf, sizeof buf, "%.17g", *(const double *)p); break;
    case kU64: std::snprintf(buf, sizeof buf, "%" PRIu64, *(const uint64_t *)p); break;
  }
  return buf;
}

/* the shared plausibility of a generator state (src/io/state.h) */
int rng_bits(const gran_rng &r) { return gran_state::rng_bits(r.s[0], r.s[1], r.s[2], r.s[3]); }
bool rng_plausible(const gran_rng &r) { return gran_state::rng_plausible(r.s[0], r.s[1], r.s[2], r.s[3]); }
bool finite_all(const double *p, size_t n) {
  for (size_t i = 0; i < n; ++i)
    if (!std::isfinite(p[i])) return false;
  return true;
}

/* Every stored value of a checkpoint (s: options checked, arrays read; sc, ic: the scalars and
 * integers as stored), each refusal naming the field:
 * - counters: particle count = the options'; step >= 0; clamp count in [0, step x cells] (at most
 *   one clamp per cell and step);
 * - time = step dt (the step loop adds dt per step: within the rounding of step additions);
 *   stress_t0 (start of the stress window) in [0, time];
 * - energies: finite; e_initial >= 0 and > 0 unless N = 1 (the only state whose velocities are all
 *   zero once the mean is removed, without shear); the ledger e_initial + e_collisions +
 *   e_external is the kinetic energy now (>= 0 to rounding);
 * - velocities: finite, finite squares, and no particle with more kinetic energy than
 *   kVelocityFactor x the ledger's (or e_initial's) total: velocities changed through
 *   gran_srd_particles by more than that factor in energy make the file unreadable;
 * - positions: every coordinate in [0, L) of its axis (the step loop keeps them there);
 * - cell reference velocities: finite and within the speeds the state allows (below);
 * - dt_max > 0 (inf: no clamp); stress sums and wall impulses finite;
 * - RNG states: the grid shift's and every cell's non-zero with 32..224 of 256 bits set. */
constexpr double kVelocityFactor = 1e3;
/* the scalars and counters (ic: step, clamped; n: the particle count the options give) */
int srd_scalars_check(const char *path, const gran_srd_options &o, int64_t ncell, int64_t n, const double sc[11],
                      const int64_t ic[2]) {
  GRAN_CHECK(ic[0] >= 0, GRAN_ERR_IO, "checkpoint '%s': field 'step' = %lld is negative", path, (long long)ic[0]);
  GRAN_CHECK(ic[1] >= 0 && (double)ic[1] <= (double)ic[0] * (double)ncell, GRAN_ERR_IO,
             "checkpoint '%s': field 'clamped' = %lld outside [0, step x cells] = [0, %g]", path, (long long)ic[1],
             (double)ic[0] * (double)ncell);
  for (int k = 0; k < 11; ++k)
    GRAN_CHECK(k == 4 || std::isfinite(sc[k]), GRAN_ERR_IO, "checkpoint '%s': field '%s' is not finite (%g)", path,
               kScalarName[k], sc[k]);
  GRAN_CHECK(sc[4] > 0, GRAN_ERR_IO, "checkpoint '%s': field 'dt_max' = %g (must be > 0 or inf)", path, sc[4]);
  /* each step's addition rounds by at most eps t / 2: k steps by k eps t / 2 (4x margin, and at most
   * 1e-3 of t: a step count whose time no longer changes by dt is not a run's) */
  const double tstep = (double)ic[0] * o.dt, ttol = std::min(((double)ic[0] + 1.0) * 2.0 * DBL_EPSILON, 1e-3) * tstep;
  GRAN_CHECK(std::fabs(sc[0] - tstep) <= ttol, GRAN_ERR_IO,
             "checkpoint '%s': field 'time' = %.17g is not step x dt = %lld x %g = %.17g", path, sc[0],
             (long long)ic[0], o.dt, tstep);
  GRAN_CHECK(sc[7] >= 0 && sc[7] <= sc[0], GRAN_ERR_IO, "checkpoint '%s': field 'stress_t0' = %g outside [0, time = %g]",
             path, sc[7], sc[0]);
  GRAN_CHECK(sc[1] >= 0 && (sc[1] > 0 || n == 1), GRAN_ERR_IO,
             "checkpoint '%s': field 'e_initial' = %g (the energy at creation is > 0 for N = %lld particles)", path, sc[1],
             (long long)n);
  const double ledger = sc[1] + sc[2] + sc[3], lscale = std::fabs(sc[1]) + std::fabs(sc[2]) + std::fabs(sc[3]);
  GRAN_CHECK(std::isfinite(ledger) && ledger >= -1e-9 * lscale, GRAN_ERR_IO,
             "checkpoint '%s': fields 'e_initial' + 'e_collisions' + 'e_external' = %g: a negative kinetic energy", path,
             ledger);
  return GRAN_SUCCESS;
}

/* the largest kinetic energy one particle may have (kVelocityFactor x the stored total) */
double srd_energy_cap(const double sc[11]) {
  const double ledger = sc[1] + sc[2] + sc[3], lscale = std::fabs(sc[1]) + std::fabs(sc[2]) + std::fabs(sc[3]);
  return kVelocityFactor * std::max(std::max(ledger, sc[1]), 1e-9 * lscale);
}

/* the values of n particles (px, pv: x, y, z and vx, vy, vz, the third NULL in 2-D) and of ncell
 * cells (V: 3 doubles, rng: one state each) and the shift's stream, against the cap emax */
int srd_values_check(const char *path, const gran_srd_options &o, const srd_geom &gm, double emax, size_t n,
                     const double *const px[3], const double *const pv[3], size_t ncell, const double *V,
                     const gran_rng *rng, const gran_rng &shift_rng) {
  const char *ax = "xyz";
  for (size_t i = 0; i < n; ++i) {
    double e = 0;
    for (int k = 0; k < o.dim; ++k) {
      const double v = pv[k][i];
      GRAN_CHECK(std::isfinite(v) && std::isfinite(v * v), GRAN_ERR_IO,
                 "checkpoint '%s': field 'v%c' of particle %zu = %g (its square is not finite)", path, ax[k], i, v);
      e += 0.5 * v * v;
    }
    GRAN_CHECK(e <= emax, GRAN_ERR_IO,
               "checkpoint '%s': field 'v' of particle %zu: kinetic energy %g exceeds %g x the stored total kinetic "
               "energy %g", path, i, e, kVelocityFactor, emax / kVelocityFactor);
  }
  for (int k = 0; k < o.dim; ++k) {
    const double hi = gm.box[k];
    for (size_t i = 0; i < n; ++i)
      GRAN_CHECK(px[k][i] >= 0.0 && px[k][i] < hi, GRAN_ERR_IO,
                 "checkpoint '%s': field '%c' of particle %zu = %.17g outside the box [0, %.17g)", path, ax[k], i,
                 px[k][i], hi);
  }
  /* a cell's reference velocity is the mean of its particles' and virtual particles' velocities
   * (wall velocity + Maxwellian at wall_T) of an earlier step: within the fastest particle, the
   * walls' and the Lees-Edwards speeds and 40 thermal speeds of the virtual particles */
  const double wT = o.wall_axis >= 0 ? (o.wall_T > 0 ? o.wall_T : o.T0) : 0.0;
  const double vcap = std::sqrt(2.0 * emax) + std::fabs(o.vib_amp * o.vib_omega) + std::fabs(o.shear_rate) * gm.box[1] +
                      40.0 * std::sqrt(wT);
  for (size_t c = 0; c < ncell; ++c) {
    const double *v = V + 3 * c;
    const double q = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    GRAN_CHECK(finite_all(v, 3) && q <= vcap, GRAN_ERR_IO,
               "checkpoint '%s': field 'cell_velocity' (reference velocity) of cell %zu: |V| = %g exceeds the speeds the "
               "state allows (%g)", path, c, q, vcap);
  }
  GRAN_CHECK(rng_plausible(shift_rng), GRAN_ERR_IO,
             "checkpoint '%s': field 'shift_rng' (grid-shift RNG state) has %d of 256 bits set (a generated state: "
             "32..224; 0 is xoshiro's forbidden state)", path, rng_bits(shift_rng));
  for (size_t c = 0; c < ncell; ++c)
    GRAN_CHECK(rng_plausible(rng[c]), GRAN_ERR_IO,
               "checkpoint '%s': field 'rng' of cell %zu has %d of 256 bits set (a generated state: 32..224; 0 is "
               "xoshiro's forbidden state)", path, c, rng_bits(rng[c]));
  return GRAN_SUCCESS;
}

int srd_state_validate(const char *path, const gran_srd *s, const double sc[11], const int64_t ic[3]) {
  GRAN_CHECK(ic[2] == s->n, GRAN_ERR_IO, "checkpoint '%s': field 'n' (particle count) %lld, the options give %lld", path,
             (long long)ic[2], (long long)s->n);
  GRAN_CALL(srd_scalars_check(path, s->opt, s->ncell, s->n, sc, ic));
  const bool d3 = s->opt.dim == 3;
  const double *pv[3] = {s->vx.data(), s->vy.data(), d3 ? s->vz.data() : nullptr};
  const double *px[3] = {s->x.data(), s->y.data(), d3 ? s->z.data() : nullptr};
  static_assert(sizeof(srd_cpu_cell) == 3 * sizeof(double), "a cell record is its reference velocity");
  return srd_values_check(path, s->opt, s->gm, srd_energy_cap(sc), (size_t)s->n, px, pv, s->cell.size(),
                          s->cell.empty() ? nullptr : s->cell[0].V, s->rng.data(), s->shift_rng);
}

/* the scalars of a state in kScalarName's order, and its counters (step, clamped, n) */
void scalars_of(const gran_srd *s, double sc[11], int64_t ic[3]) {
  const double v[11] = {s->time,     s->e_initial, s->e_coll,  s->e_ext,          s->dt_max,         s->flux_kin,
                        s->flux_coll, s->stress_t0, s->wall_impulse[0], s->wall_impulse[1], s->wall_impulse[2]};
  for (int k = 0; k < 11; ++k) sc[k] = v[k];
  ic[0] = s->step;
  ic[1] = s->clamped;
  ic[2] = s->n;
}

/* the first 8 bytes of PATH start with the magic of the binary format before HDF5 */
bool old_binary_format(const char *path, char *version) {
  FILE *f = std::fopen(path, "rb");
  if (!f) return false;
  char m[8] = {0};
  const bool got = std::fread(m, 1, 8, f) == 8;
  std::fclose(f);
  *version = m[7];
  return got && std::memcmp(m, "GSRDCKP", 7) == 0;
}

}  // namespace

/* The first compared option in which stored (c) and expected (o) differ, or NULL; *k is the element
 * of an array option. */
static const OptField *options_differ(const gran_srd_options &c, const gran_srd_options &o, int *k) {
  const unsigned char *pc = (const unsigned char *)&c, *po = (const unsigned char *)&o;
  for (const OptField &f : kOptions) {
    if (!f.compared) continue;
    if (std::strcmp(f.name, "wall_rule") == 0 && o.wall_axis < 0 && c.wall_axis < 0) continue; /* no walls */
    const int n = std::strcmp(f.name, "cells") == 0 ? std::min(o.dim, 3) : f.count; /* cells[2] unused in 2-D */
    for (int j = 0; j < n; ++j) {
      const size_t at = f.off + opt_size(f.type) * (size_t)j;
      bool same;
      if (f.type == kF64) { /* as numbers (-0 = 0), bits for NaN (never stored: refused by the check) */
        double a, b;
        std::memcpy(&a, pc + at, 8);
        std::memcpy(&b, po + at, 8);
        same = a == b;
      } else {
        same = std::memcmp(pc + at, po + at, opt_size(f.type)) == 0;
      }
      if (!same) {
        *k = f.count > 1 ? j : -1;
        return &f;
      }
    }
  }
  return nullptr;
}

/* The engine state into group `group` of the open HDF5 file `file` (`path` names it in messages). */
int gran_srd_checkpoint_write_h5_(const gran_srd *s, int64_t file, const char *group, const char *path) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    GRAN_CALL(gran_srd_dev_sync(s, 1)); /* device hook (owner: CUDA backend): copy back, cells too */
    gran_state::Group g, og;
    GRAN_CALL(g.create(file, group, kSrdFormat, path));
    GRAN_CALL(og.create(g.id(), "options", "gran_srd_options", path));
    GRAN_CALL(options_write(og, s->opt));
    GRAN_CALL(g.put1("step", s->step));
    GRAN_CALL(g.put1("clamped", s->clamped));
    GRAN_CALL(g.put1("n", s->n));
    GRAN_CALL(g.put1("time", s->time));
    GRAN_CALL(g.put1("e_initial", s->e_initial));
    GRAN_CALL(g.put1("e_collisions", s->e_coll));
    GRAN_CALL(g.put1("e_external", s->e_ext));
    GRAN_CALL(g.put1("dt_max", s->dt_max));
    GRAN_CALL(g.put1("flux_kin", s->flux_kin));
    GRAN_CALL(g.put1("flux_coll", s->flux_coll));
    GRAN_CALL(g.put1("stress_t0", s->stress_t0));
    GRAN_CALL(g.put("wall_impulse", 3, s->wall_impulse));
    const int64_t n = s->n;
    GRAN_CALL(g.put("x", n, s->x.data()));
    GRAN_CALL(g.put("y", n, s->y.data()));
    if (s->opt.dim == 3) GRAN_CALL(g.put("z", n, s->z.data()));
    GRAN_CALL(g.put("vx", n, s->vx.data()));
    GRAN_CALL(g.put("vy", n, s->vy.data()));
    if (s->opt.dim == 3) GRAN_CALL(g.put("vz", n, s->vz.data()));
    std::vector<double> refs;
    srd_refs_get(s, refs);
    GRAN_CALL(g.put("cell_velocity", 3 * s->ncell, refs.data()));
    static_assert(sizeof(gran_rng) == 4 * sizeof(uint64_t), "an RNG state is 4 uint64");
    GRAN_CALL(g.put("rng", 4 * s->ncell, &s->rng.data()->s[0]));
    GRAN_CALL(g.put("shift_rng", 4, s->shift_rng.s));
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/* A new engine from group `group` of the open HDF5 file `file`. With `expect` (the run driver: the
 * options its scene gives, with the replica's seed), every stored option must equal the expected
 * one (threads and device excepted: the resuming run's threads are used), checked before anything
 * is allocated. */
int gran_srd_checkpoint_read_h5_(int64_t file, const char *group, const char *path, const gran_srd_options *expect,
                                 gran_srd **out) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(out, srd);
    *out = nullptr;
    gran_state::Group g, og;
    GRAN_CALL(g.open(file, group, path));
    std::string fmt;
    GRAN_CALL(g.format(&fmt));
    GRAN_CHECK(fmt == kSrdFormat, GRAN_ERR_IO,
               "checkpoint '%s': group '%s' is not a GSRD engine state (format '%s'; this granary reads '%s'%s)", path,
               group, fmt.c_str(), kSrdFormat,
               fmt == "granary-srd-checkpoint 1" ? ": a checkpoint of the binary state format, rerun the scene to make "
                                                   "a new one"
                                                 : "");
    GRAN_CALL(og.open(g.id(), "options", path));
    gran_srd_options o;
    GRAN_CALL(options_read(og, &o));
    /* the stored options pass the check of gran_srd_create; a refusal is the file's (GRAN_ERR_IO) */
    if (srd_check_options_(&o) != GRAN_SUCCESS) {
      const std::string why = gran_last_error_message();
      return GRAN_ERROR(GRAN_ERR_IO, "checkpoint '%s' holds invalid options: %s", path, why.c_str());
    }
    if (expect) {
      int k = -1;
      const OptField *f = options_differ(o, *expect, &k);
      if (f) {
        char name[40];
        if (k >= 0) std::snprintf(name, sizeof name, "%s[%d]", f->name, k);
        else std::snprintf(name, sizeof name, "%s", f->name);
        return GRAN_ERROR(GRAN_ERR_IO,
                          "checkpoint '%s': the GSRD state in '%s' does not match the scene: option '%s' differs "
                          "(stored %s, scene %s; a checkpoint resumes the run of its own scene)", path, group, name,
                          opt_value(o, *f, k < 0 ? 0 : k).c_str(), opt_value(*expect, *f, k < 0 ? 0 : k).c_str());
      }
    }
    if (expect) o.threads = expect->threads; /* the resuming run's choice: results do not depend on it */
    std::unique_ptr<gran_srd> s(new gran_srd);
    s->opt = o;
    {
      /* the sizes the options imply against the file's, before anything is allocated: geometry only */
      int64_t nc = 1, ncb = 1;
      for (int k = 0; k < 3; ++k) {
        const int64_t L = k < o.dim ? o.cells[k] : 1;
        ncb *= L;
        nc *= L + (k == o.wall_axis ? 1 : 0);
      }
      const double nn = std::floor(o.n0 * (double)ncb + 0.5);
      const int64_t n = nn >= 1 && nn < 4e9 ? (int64_t)nn : -1;
      const char *arr[6] = {"x", "y", "z", "vx", "vy", "vz"};
      for (int a = 0; a < 6; ++a) {
        if (o.dim == 2 && (a == 2 || a == 5)) continue;
        const int64_t m = g.npoints(arr[a]);
        GRAN_CHECK(m == n, GRAN_ERR_IO, "checkpoint '%s': field '%s' has %lld values, its options give %lld particles",
                   path, arr[a], (long long)m, (long long)n);
      }
      GRAN_CHECK(g.npoints("cell_velocity") == 3 * nc, GRAN_ERR_IO,
                 "checkpoint '%s': field 'cell_velocity' has %lld values, its options give %lld cells", path,
                 (long long)g.npoints("cell_velocity"), (long long)nc);
      GRAN_CHECK(g.npoints("rng") == 4 * nc, GRAN_ERR_IO,
                 "checkpoint '%s': field 'rng' has %lld values, its options give %lld cells", path,
                 (long long)g.npoints("rng"), (long long)nc);
    }
    GRAN_CALL(srd_alloc_state_(s.get()));
    double sc[11];
    int64_t ic[3];
    GRAN_CALL(g.get1("step", &ic[0]));
    GRAN_CALL(g.get1("clamped", &ic[1]));
    GRAN_CALL(g.get1("n", &ic[2]));
    for (int k = 0; k < 8; ++k) GRAN_CALL(g.get1(kScalarName[k], &sc[k]));
    GRAN_CALL(g.get("wall_impulse", 3, sc + 8));
    const int64_t n = s->n;
    GRAN_CALL(g.get("x", n, s->x.data()));
    GRAN_CALL(g.get("y", n, s->y.data()));
    if (o.dim == 3) GRAN_CALL(g.get("z", n, s->z.data()));
    GRAN_CALL(g.get("vx", n, s->vx.data()));
    GRAN_CALL(g.get("vy", n, s->vy.data()));
    if (o.dim == 3) GRAN_CALL(g.get("vz", n, s->vz.data()));
    {
      std::vector<double> refs((size_t)(3 * s->ncell));
      GRAN_CALL(g.get("cell_velocity", 3 * s->ncell, refs.data()));
      srd_refs_set(s.get(), refs.data());
    }
    GRAN_CALL(g.get("rng", 4 * s->ncell, &s->rng.data()->s[0]));
    GRAN_CALL(g.get("shift_rng", 4, s->shift_rng.s));
    /* values: a checksum-consistent file may still have been written by a foreign or edited program */
    GRAN_CALL(srd_state_validate(path, s.get(), sc, ic));
    s->time = sc[0];
    s->e_initial = sc[1];
    s->e_coll = sc[2];
    s->e_ext = sc[3];
    s->dt_max = sc[4];
    s->flux_kin = sc[5];
    s->flux_coll = sc[6];
    s->stress_t0 = sc[7];
    for (int k = 0; k < 3; ++k) s->wall_impulse[k] = sc[8 + k];
    s->step = ic[0];
    s->clamped = ic[1];
    /* ---- device hook (owner: CUDA backend): resume on the device the options name ---- */
    const int e = gran_srd_dev_attach(s.get(), 1);
    if (e != GRAN_SUCCESS) return e;
    /* ---- end device hook ---- */
    *out = s.release();
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

static int check_group_arg(const char *group) {
  GRAN_CHECK_PTR(group);
  GRAN_CHECK(group[0] != '\0' && std::strcmp(group, "/") != 0, GRAN_ERR_ARG,
             "argument 'group' = '%s' must name a group below the root", group);
  return GRAN_SUCCESS;
}

/** @brief Write the complete engine state into group `group` of the HDF5 file `path` (created if
 *  missing; an existing group of that name is replaced). */
GRAN_EXTERN int gran_srd_checkpoint_write(const gran_srd *s, const char *path, const char *group) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    GRAN_CHECK_PTR(path);
    GRAN_CHECK(path[0] != '\0', GRAN_ERR_ARG, "argument 'path' is empty");
    GRAN_CALL(check_group_arg(group));
    char v = 0;
    GRAN_CHECK(!old_binary_format(path, &v), GRAN_ERR_IO,
               "checkpoint file '%s' holds a GSRD checkpoint of the binary format GSRDCKP%c; remove it or write to "
               "another path", path, v);
    gran_state::File f;
    GRAN_CALL(f.open_update(path));
    GRAN_CALL(gran_srd_checkpoint_write_h5_(s, f.id(), group, path));
    return f.commit("checkpoint");
  }
  GRAN_CATCH
}

/** @brief New engine from the state in group `group` of `path`; it resumes on the device its
 *  options name. */
GRAN_EXTERN int gran_srd_checkpoint_read(const char *path, const char *group, gran_srd **out) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(out, srd);
    *out = nullptr;
    GRAN_CHECK_PTR(path);
    GRAN_CALL(check_group_arg(group));
    char v = 0;
    GRAN_CHECK(!old_binary_format(path, &v), GRAN_ERR_IO,
               "checkpoint '%s' is a GSRD checkpoint of the binary format GSRDCKP%c, which this granary no longer "
               "reads (GSRD states are HDF5 groups now, format '%s'): rerun the scene, or resume it with the granary "
               "release that wrote it to its end", path, v, kSrdFormat);
    gran_state::File f;
    GRAN_CALL(f.open_read(path, "checkpoint", true));
    return gran_srd_checkpoint_read_h5_(f.id(), group, path, nullptr, out);
  }
  GRAN_CATCH
}

/* ---- a part of a checkpoint set (srd_impl.h, srd_part) ---- */
namespace {
const char *kPartFormat = "granary-srd-part 1";
const char *kPartGroup = "/srd_part";
}  // namespace

int srd_state_check_(const char *path, const gran_srd *s) {
  double sc[11];
  int64_t ic[3];
  scalars_of(s, sc, ic);
  return srd_state_validate(path, s, sc, ic);
}

int srd_part_write_(const gran_srd_options *opt, const srd_part &p, const char *path) {
  GRAN_TRY {
    GRAN_CHECK_PTR(opt);
    GRAN_CHECK_PTR(path);
    std::remove(path); /* a part of this name from a run that did not commit it */
    gran_state::File f;
    GRAN_CALL(f.open_update(path));
    gran_state::Group g, og;
    GRAN_CALL(g.create(f.id(), kPartGroup, kPartFormat, path));
    GRAN_CALL(og.create(g.id(), "options", "gran_srd_options", path));
    GRAN_CALL(options_write(og, *opt));
    GRAN_CALL(g.put1("generation", p.generation));
    GRAN_CALL(g.put("pgrid", 3, p.pgrid));
    GRAN_CALL(g.put1("brick", (int64_t)p.brick));
    GRAN_CALL(g.put1("step", p.step));
    GRAN_CALL(g.put1("clamped", p.clamped));
    GRAN_CALL(g.put1("clamped_obs", p.clamped_obs));
    const double sc[11] = {p.time,      p.e_initial, p.e_coll,          p.e_ext,           p.dt_max,          p.flux_kin,
                           p.flux_coll, p.stress_t0, p.wall_impulse[0], p.wall_impulse[1], p.wall_impulse[2]};
    for (int k = 0; k < 8; ++k) GRAN_CALL(g.put1(kScalarName[k], sc[k]));
    GRAN_CALL(g.put("wall_impulse", 3, p.wall_impulse));
    GRAN_CALL(g.put1("dt_max_obs", p.dt_max_obs));
    const int64_t n = (int64_t)p.x.size();
    const bool d3 = opt->dim == 3;
    GRAN_CALL(g.put("x", n, p.x.data()));
    GRAN_CALL(g.put("y", n, p.y.data()));
    if (d3) GRAN_CALL(g.put("z", n, p.z.data()));
    GRAN_CALL(g.put("vx", n, p.vx.data()));
    GRAN_CALL(g.put("vy", n, p.vy.data()));
    if (d3) GRAN_CALL(g.put("vz", n, p.vz.data()));
    GRAN_CALL(g.put("key", n, p.key.data()));
    GRAN_CALL(g.put("cell_velocity", (int64_t)p.V.size(), p.V.data()));
    GRAN_CALL(g.put("rng", (int64_t)p.rng.size(), p.rng.data()));
    GRAN_CALL(g.put("shift_rng", 4, p.shift_rng.s));
    return f.commit("checkpoint part");
  }
  GRAN_CATCH
}

int srd_part_read_(const char *path, const gran_srd *shell, srd_part *p) {
  GRAN_TRY {
    GRAN_CHECK_PTR(path);
    GRAN_CHECK_PTR(shell);
    GRAN_CHECK_PTR(p);
    *p = srd_part();
    gran_state::File f;
    GRAN_CALL(f.open_read(path, "checkpoint part", true));
    gran_state::Group g, og;
    GRAN_CALL(g.open(f.id(), kPartGroup, path));
    std::string fmt;
    GRAN_CALL(g.format(&fmt));
    GRAN_CHECK(fmt == kPartFormat, GRAN_ERR_IO,
               "checkpoint part '%s': group '%s' is not a part of a split GSRD gas (format '%s'; this granary reads '%s')",
               path, kPartGroup, fmt.c_str(), kPartFormat);
    GRAN_CALL(og.open(g.id(), "options", path));
    gran_srd_options o;
    GRAN_CALL(options_read(og, &o));
    if (srd_check_options_(&o) != GRAN_SUCCESS) {
      const std::string why = gran_last_error_message();
      return GRAN_ERROR(GRAN_ERR_IO, "checkpoint part '%s' holds invalid options: %s", path, why.c_str());
    }
    int k = -1;
    const OptField *fd = options_differ(o, shell->opt, &k);
    if (fd) {
      char name[40];
      if (k >= 0) std::snprintf(name, sizeof name, "%s[%d]", fd->name, k);
      else std::snprintf(name, sizeof name, "%s", fd->name);
      return GRAN_ERROR(GRAN_ERR_IO,
                        "checkpoint part '%s': option '%s' differs from the run's (stored %s, the run's %s: a part "
                        "resumes the run of its own scene and replica)", path, name,
                        opt_value(o, *fd, k < 0 ? 0 : k).c_str(), opt_value(shell->opt, *fd, k < 0 ? 0 : k).c_str());
    }
    /* the split and the brick: within the grid, before anything is allocated */
    GRAN_CALL(g.get1("generation", &p->generation));
    GRAN_CHECK(p->generation >= 1, GRAN_ERR_IO, "checkpoint part '%s': field 'generation' = %lld (a generation is >= 1)",
               path, (long long)p->generation);
    GRAN_CALL(g.get("pgrid", 3, p->pgrid));
    int64_t nb = 1, ncl = 1, lo[3], w[3];
    for (int a = 0; a < 3; ++a) {
      const int64_t nc = shell->gm.nc[a];
      GRAN_CHECK(p->pgrid[a] >= 1 && p->pgrid[a] <= nc, GRAN_ERR_IO,
                 "checkpoint part '%s': field 'pgrid[%d]' = %d outside [1, %lld] (the cells along axis %d)", path, a,
                 p->pgrid[a], (long long)nc, a);
      nb *= p->pgrid[a];
    }
    int64_t brick = -1;
    GRAN_CALL(g.get1("brick", &brick));
    GRAN_CHECK(brick >= 0 && brick < nb, GRAN_ERR_IO, "checkpoint part '%s': field 'brick' = %lld outside [0, %lld)", path,
               (long long)brick, (long long)nb);
    p->brick = (int)brick;
    {
      const int64_t b[3] = {brick % p->pgrid[0], (brick / p->pgrid[0]) % p->pgrid[1], brick / (p->pgrid[0] * p->pgrid[1])};
      for (int a = 0; a < 3; ++a) {
        lo[a] = srd_brick_cut(b[a], shell->gm.nc[a], p->pgrid[a]);
        w[a] = srd_brick_cut(b[a] + 1, shell->gm.nc[a], p->pgrid[a]) - lo[a];
        ncl *= w[a];
      }
    }
    const bool d3 = o.dim == 3;
    const char *arr[7] = {"x", "y", "z", "vx", "vy", "vz", "key"};
    const int64_t m = g.npoints("x");
    GRAN_CHECK(m >= 0 && m <= shell->n, GRAN_ERR_IO,
               "checkpoint part '%s': field 'x' has %lld values, and the gas has %lld particles", path, (long long)m,
               (long long)shell->n);
    for (int a = 1; a < 7; ++a) {
      if (!d3 && (a == 2 || a == 5)) continue;
      GRAN_CHECK(g.npoints(arr[a]) == m, GRAN_ERR_IO, "checkpoint part '%s': field '%s' has %lld values, field 'x' %lld",
                 path, arr[a], (long long)g.npoints(arr[a]), (long long)m);
    }
    GRAN_CHECK(g.npoints("cell_velocity") == 3 * ncl && g.npoints("rng") == 4 * ncl, GRAN_ERR_IO,
               "checkpoint part '%s': fields 'cell_velocity' and 'rng' have %lld and %lld values, brick %lld of the split "
               "%d x %d x %d has %lld cells (3 and 4 each)", path, (long long)g.npoints("cell_velocity"),
               (long long)g.npoints("rng"), (long long)brick, p->pgrid[0], p->pgrid[1], p->pgrid[2], (long long)ncl);
    double sc[11];
    int64_t ic[2];
    GRAN_CALL(g.get1("step", &ic[0]));
    GRAN_CALL(g.get1("clamped", &ic[1]));
    GRAN_CALL(g.get1("clamped_obs", &p->clamped_obs));
    for (int q = 0; q < 8; ++q) GRAN_CALL(g.get1(kScalarName[q], &sc[q]));
    GRAN_CALL(g.get("wall_impulse", 3, sc + 8));
    GRAN_CALL(g.get1("dt_max_obs", &p->dt_max_obs));
    GRAN_CALL(srd_scalars_check(path, o, shell->ncell, shell->n, sc, ic));
    GRAN_CHECK(p->clamped_obs >= 0 && p->clamped_obs <= ic[1], GRAN_ERR_IO,
               "checkpoint part '%s': field 'clamped_obs' = %lld outside [0, clamped = %lld]", path,
               (long long)p->clamped_obs, (long long)ic[1]);
    GRAN_CHECK(p->dt_max_obs > 0, GRAN_ERR_IO, "checkpoint part '%s': field 'dt_max_obs' = %g (must be > 0 or inf)", path,
               p->dt_max_obs);
    std::vector<double> *pa[6] = {&p->x, &p->y, &p->z, &p->vx, &p->vy, &p->vz};
    for (int a = 0; a < 6; ++a) {
      if (!d3 && (a == 2 || a == 5)) continue;
      pa[a]->resize((size_t)m);
      GRAN_CALL(g.get(arr[a], m, pa[a]->data()));
    }
    p->key.resize((size_t)m);
    GRAN_CALL(g.get("key", m, p->key.data()));
    for (size_t i = 1; i < (size_t)m; ++i)
      GRAN_CHECK(p->key[i - 1] < p->key[i], GRAN_ERR_IO,
                 "checkpoint part '%s': field 'key' is not strictly increasing at particle %zu (a part holds its "
                 "particles in key order)", path, i);
    p->V.resize((size_t)(3 * ncl));
    p->rng.resize((size_t)(4 * ncl));
    GRAN_CALL(g.get("cell_velocity", 3 * ncl, p->V.data()));
    GRAN_CALL(g.get("rng", 4 * ncl, p->rng.data()));
    GRAN_CALL(g.get("shift_rng", 4, p->shift_rng.s));
    const double *px[3] = {p->x.data(), p->y.data(), d3 ? p->z.data() : nullptr};
    const double *pv[3] = {p->vx.data(), p->vy.data(), d3 ? p->vz.data() : nullptr};
    static_assert(sizeof(gran_rng) == 4 * sizeof(uint64_t), "an RNG state is 4 uint64");
    GRAN_CALL(srd_values_check(path, o, shell->gm, srd_energy_cap(sc), (size_t)m, px, pv, (size_t)ncl, p->V.data(),
                               (const gran_rng *)p->rng.data(), p->shift_rng));
    p->step = ic[0];
    p->clamped = ic[1];
    p->time = sc[0];
    p->e_initial = sc[1];
    p->e_coll = sc[2];
    p->e_ext = sc[3];
    p->dt_max = sc[4];
    p->flux_kin = sc[5];
    p->flux_coll = sc[6];
    p->stress_t0 = sc[7];
    for (int q = 0; q < 3; ++q) p->wall_impulse[q] = sc[8 + q];
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}
