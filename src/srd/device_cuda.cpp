/* device_cuda.cpp - devices of the GSRD engine.
 *
 * (1) Selection ([engine] device = "cpu" | "cuda" | "auto" | "reference"; options.device): "auto"
 *     takes the GPU when the CUDA backend is compiled and a device is visible, else the CPU with a
 *     warning; "cuda" without either is GRAN_ERR_UNSUPPORTED naming which.
 * (2) The host reference of the device algorithm (gran_ref_srd_*, same contracts as the GPU
 *     launchers of cuda/srd_cuda.h): the rules of src/srd/rules.h in plain serial loops, cell sums
 *     in particle order (so its particles follow the CPU engine's to rounding in double storage:
 *     t890; the CPU engine's loops compile the rules with constant effect bits, so the compiler
 *     fuses other multiply-adds), float storage emulated by rounding what it stores. The GPU tests
 *     compare the GPU against it.
 * (3) The engine hooks: a run whose options name a device keeps its particles and cells there; the
 *     engine (src/srd/engine.cpp) calls gran_srd_dev_* at its dispatch points. The host side does
 *     what the CPU engine does on the host: the per-step geometry (Lees-Edwards offset, wall
 *     velocity), the grid shift from stream 0, the step and time counters, the sort cadence and the
 *     ledger sums (read from the device once per advance). */
#include <algorithm>
#include <cmath>
#include <cstring>
#include <fftw3.h>
#include <new>
#include <vector>

#include "granary_impl.h"
#include "srd/device_cuda.h"
#include "srd/srd_impl.h"
#include "srd/srd_limits.h"
#include "../cuda/srd_cuda.h"

/* ---- (1) selection -------------------------------------------------------------------------- */

int gran_srd_device_parse(const char *name, int32_t *device) {
  GRAN_CHECK_PTR(name);
  GRAN_CHECK_PTR(device);
  static const char *const names[4] = {"cpu", "cuda", "auto", "reference"};
  for (int32_t d = 0; d < 4; ++d)
    if (!std::strcmp(name, names[d])) {
      *device = d;
      return GRAN_SUCCESS;
    }
  return GRAN_ERROR(GRAN_ERR_ARG, "device = \"%s\": must be \"cpu\", \"cuda\", \"auto\" or \"reference\"", name);
}

namespace {

/* GRAN_SRD_DEVICE_* -> where the run goes (CPU, CUDA or REFERENCE). soft: "cuda" without a GPU
 * falls back like "auto" (a checkpoint must stay readable). */
int resolve_id(int32_t device, bool soft, int32_t *out) {
  GRAN_CHECK(device >= 0 && device <= 3, GRAN_ERR_ARG,
             "option 'device' = %d: must be 0 (cpu), 1 (cuda), 2 (auto) or 3 (reference)", (int)device);
  *out = device;
  if (device == GRAN_SRD_DEVICE_CPU || device == GRAN_SRD_DEVICE_REFERENCE) return GRAN_SUCCESS;
  int compiled = 0, count = 0;
  GRAN_CALL(gran_cuda_compiled(&compiled));
  if (compiled) GRAN_CALL(gran_cuda_device_count(&count));
  if (compiled && count > 0) {
    *out = GRAN_SRD_DEVICE_CUDA;
    return GRAN_SUCCESS;
  }
  const char *why = !compiled ? "the CUDA backend was not compiled (no nvcc at build time)" : "no CUDA device is visible";
  GRAN_CHECK(device == GRAN_SRD_DEVICE_AUTO || soft, GRAN_ERR_UNSUPPORTED, "device = \"cuda\": %s", why);
  gran_warning_add("device = \"%s\": %s; running on the CPU", device == GRAN_SRD_DEVICE_AUTO ? "auto" : "cuda", why);
  *out = GRAN_SRD_DEVICE_CPU;
  return GRAN_SUCCESS;
}

}  // namespace

int gran_srd_device_resolve(const char *device, int *use_cuda) {
  GRAN_CHECK_PTR(device);
  GRAN_CHECK_PTR(use_cuda);
  *use_cuda = 0;
  int32_t d = 0, r = 0;
  GRAN_CALL(gran_srd_device_parse(device, &d));
  GRAN_CALL(resolve_id(d, false, &r));
  *use_cuda = r == GRAN_SRD_DEVICE_CUDA;
  return GRAN_SUCCESS;
}

/* ---- the launchers' parameters: one check for the GPU and the host reference ------------------ */

int gran_srd_dev_check_params(const gran_cuda_srd_params *p) {
  GRAN_CHECK_PTR(p);
  const srd_geom &g = p->geom;
  GRAN_CHECK(g.dim == 2 || g.dim == 3, GRAN_ERR_ARG, "geom.dim = %d: must be 2 or 3", (int)g.dim);
  GRAN_CHECK(p->n >= 0, GRAN_ERR_ARG, "n = " GRAN_I64_FMT " is negative", p->n);
  GRAN_CHECK(p->precision == 0 || p->precision == 1, GRAN_ERR_ARG, "precision = %d: must be 0 (double) or 1 (float)",
             (int)p->precision);
  GRAN_CHECK(p->dt > 0.0 && std::isfinite(p->dt), GRAN_ERR_ARG, "dt = %g must be positive", p->dt);
  GRAN_CHECK((p->fx & ~SRD_FX_ALL) == 0, GRAN_ERR_ARG, "fx = %d: bits outside SRD_FX_* (%d)", (int)p->fx, SRD_FX_ALL);
  GRAN_CHECK((p->fx & (SRD_FX_THERMO | SRD_FX_GTHERMO)) != (SRD_FX_THERMO | SRD_FX_GTHERMO), GRAN_ERR_ARG,
             "fx = %d: SRD_FX_THERMO (cell-level) and SRD_FX_GTHERMO (global) exclude each other", (int)p->fx);
  GRAN_CHECK(!(p->fx & (SRD_FX_THERMO | SRD_FX_GTHERMO)) || (p->T0 > 0.0 && std::isfinite(p->T0)), GRAN_ERR_ARG,
             "T0 = %g: a thermostat needs a positive temperature", p->T0);
  GRAN_CHECK(!(p->fx & SRD_FX_LE) || (std::isfinite(p->shear_rate) && p->shear_rate != 0.0 && g.le_on), GRAN_ERR_ARG,
             "fx has SRD_FX_LE: shear_rate = %g must be finite and non-zero and geom.le_on = %d set", p->shear_rate,
             (int)g.le_on);
  GRAN_CHECK(g.a > 0.0 && std::isfinite(g.a) && std::isfinite(g.inv_a), GRAN_ERR_ARG,
             "geom.a = %g must be positive (and 1 / a finite)", g.a);
  for (int k = 0; k < 3; ++k) {
    GRAN_CHECK(g.nc[k] >= 1 && g.L[k] >= 1, GRAN_ERR_ARG, "geom.nc[%d] / geom.L[%d] must be >= 1", k, k);
    GRAN_CHECK(k >= g.dim || (g.box[k] > 0.0 && std::isfinite(g.box[k])), GRAN_ERR_ARG,
               "geom.box[%d] = %g must be positive and finite", k, g.box[k]);
  }
  /* the sorts (CUB radix sort on the GPU, the reference's counting sort) key cells and index
   * particles with 32 bits */
  GRAN_CHECK(p->n <= (int64_t)UINT32_MAX, GRAN_ERR_UNSUPPORTED,
             "n = " GRAN_I64_FMT " particles: the sort indices hold at most 2^32 - 1", p->n);
  GRAN_CHECK(g.nc[0] * g.nc[1] * g.nc[2] <= (int64_t)UINT32_MAX, GRAN_ERR_UNSUPPORTED,
             "binning grid of " GRAN_I64_FMT " cells: the sort keys hold at most 2^32 - 1", g.nc[0] * g.nc[1] * g.nc[2]);
  if (p->precision == 1) { /* float storage: the range of srd_limits.h, on what the parameters hold */
    double gn = 0;
    for (int k = 0; k < 3; ++k) gn += p->g[k] * p->g[k];
    const struct {
      double v, lo, hi;
      const char *what;
    } c[] = {{g.a, SRD_FLOAT_LO, SRD_FLOAT_HI, "geom.a"},
             {std::max({g.box[0], g.box[1], g.box[2]}), SRD_FLOAT_LO, SRD_FLOAT_HI, "the box length geom.box"},
             {p->T0 > 0 ? p->T0 : 1.0, SRD_FLOAT_LO, SRD_FLOAT_HI, "T0"},
             {p->wall_T > 0 ? p->wall_T : 1.0, SRD_FLOAT_LO, SRD_FLOAT_HI, "wall_T"},
             {std::fabs(g.le_dv), 0.0, 1e15, "the Lees-Edwards velocity jump geom.le_dv"},
             {std::sqrt(gn) * p->dt, 0.0, 1e15, "the speed |g| dt gained per step"}};
    for (const auto &q : c) {
      const std::string why = gran_derived_why(q.v, q.lo, q.hi, q.what);
      GRAN_CHECK(why.empty(), GRAN_ERR_ARG, "precision = 1 (float storage): %s (speeds within 1e-15 .. 1e15, "
                 "temperatures and lengths within 1e-30 .. 1e30)", why.c_str());
    }
  }
  return GRAN_SUCCESS;
}

/* ---- (2) host reference of the device algorithm --------------------------------------------- */

namespace {

struct RefState {
  gran_cuda_srd_params p{};
  srd_rule_const k{};
  int64_t ncell = 0;
  bool f32 = false;
  std::vector<double> x[3], v[3], vref;
  std::vector<gran_rng> rng;
  std::vector<srd_cell_sum> sum;
  std::vector<srd_cell_rot> rot;
  srd_geom last_gm{};
  double last_s[3] = {0, 0, 0};
  double acc[SRD_ACC_N] = {};
  int64_t clamped = 0;
  double dt_max = INFINITY;
  double store(double a) const { return f32 ? (double)(float)a : a; }
  double store_x(int k, double a) const { return f32 ? (double)srd_dev_float_pos(&p.geom, k, a) : a; }
};

RefState *ref_of(gran_cuda_srd *h) { return reinterpret_cast<RefState *>(h); }
const RefState *ref_of(const gran_cuda_srd *h) { return reinterpret_cast<const RefState *>(h); }

}  // namespace

int gran_ref_srd_create(const gran_cuda_srd_params *p, const double *const x[3], const double *const v[3],
                        const gran_rng *cell_rng, gran_cuda_srd **out) {
  GRAN_CHECK_PTR(out);
  *out = nullptr;
  GRAN_CALL(gran_srd_dev_check_params(p));
  GRAN_CHECK_PTR(x);
  GRAN_CHECK_PTR(v);
  GRAN_CHECK_PTR(cell_rng);
  for (int k = 0; k < p->geom.dim; ++k)
    GRAN_CHECK(p->n == 0 || (x[k] && v[k]), GRAN_ERR_ARG, "x[%d] or v[%d] is NULL", k, k);
  GRAN_TRY {
    RefState *r = new RefState;
    r->p = *p;
    r->k = srd_rule_const_of(p);
    r->ncell = p->geom.nc[0] * p->geom.nc[1] * p->geom.nc[2];
    r->f32 = p->precision == 1;
    const size_t n = (size_t)p->n, nc = (size_t)r->ncell;
    try {
      for (int k = 0; k < p->geom.dim; ++k) {
        r->x[k].resize(n);
        r->v[k].resize(n);
        for (size_t i = 0; i < n; ++i) {
          r->x[k][i] = r->store_x(k, x[k][i]);
          r->v[k][i] = r->store(v[k][i]);
        }
      }
      r->vref.assign(3 * nc, 0.0);
      r->rng.assign(cell_rng, cell_rng + nc);
      r->sum.resize(nc);
      for (auto &c : r->sum) srd_sum_clear(&c);
      r->rot.resize(nc);
    } catch (...) {
      delete r;
      throw;
    }
    r->last_gm = p->geom;
    *out = reinterpret_cast<gran_cuda_srd *>(r);
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int gran_ref_srd_step(gran_cuda_srd *h, const srd_geom *gm, const double s[3], int64_t *n_clamped, double *dt_max) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(gm);
  GRAN_CHECK_PTR(s);
  RefState &r = *ref_of(h);
  GRAN_CHECK(gm->dim == r.p.geom.dim && gm->nc[0] == r.p.geom.nc[0] && gm->nc[1] == r.p.geom.nc[1] &&
                 gm->nc[2] == r.p.geom.nc[2] && gm->wall_axis == r.p.geom.wall_axis,
             GRAN_ERR_ARG, "gm: dimension, grid or walls differ from the state's");
  for (int k = 0; k < gm->dim; ++k)
    GRAN_CHECK(s[k] >= 0.0 && s[k] <= gm->a, GRAN_ERR_ARG, "shift s[%d] = %g outside [0, a]", k, s[k]);
  const int dim = gm->dim, fx = r.k.fx;
  const int64_t n = r.p.n;
  /* pass 1: move, store, bin what is stored, sums in particle order */
  for (int64_t i = 0; i < n; ++i) {
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < dim; ++k) {
      p[k] = r.x[k][i];
      v[k] = r.v[k][i];
    }
    srd_rule_move(fx, dim, &r.k, gm, p, v, r.acc);
    if (srd_nonfinite(p, v) != 0.0) r.acc[SRD_ACC_BAD] += 1.0; /* non-finite stays non-finite: see srd_wrap1 */
    for (int k = 0; k < dim; ++k) {
      p[k] = r.x[k][i] = r.store_x(k, p[k]);
      v[k] = r.v[k][i] = r.store(v[k]);
    }
    const int64_t c = srd_bin(gm, s, p, &dvx);
    v[0] += dvx;
    srd_sum_add(&r.sum[c], v, &r.vref[3 * c], dim);
  }
  /* the global thermostat's factor: every cell's thermal energy, in cell order */
  double gscale = 1.0;
  if (fx & SRD_FX_GTHERMO) {
    double e = 0.0, dof = 0.0;
    for (int64_t c = 0; c < r.ncell; ++c) {
      double ec, dc;
      if (!srd_rule_thermal(dim, &r.sum[c], &r.vref[3 * c], &ec, &dc)) continue;
      e += ec;
      dof += dc;
    }
    gscale = srd_rule_gscale(e, dof, r.k.T0);
  }
  /* cells */
  int64_t ncl = 0;
  double dtm = INFINITY;
  for (int64_t c = 0; c < r.ncell; ++c) {
    int cl;
    double d;
    const srd_cell_sum cs = r.sum[c];
    srd_rule_cell(fx, dim, &r.k, gm, s, c, &cs, gscale, &r.vref[3 * c], &r.rng[c], &r.rot[c], &cl, &d);
    if (cl) {
      ++ncl;
      dtm = std::min(dtm, d);
    }
    srd_sum_clear(&r.sum[c]);
  }
  /* pass 2: collisions (a cell that does not collide leaves its particles as they are) */
  for (int64_t i = 0; i < n; ++i) {
    double p[3] = {0, 0, 0}, v[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < dim; ++k) p[k] = r.x[k][i];
    const int64_t c = srd_bin(gm, s, p, &dvx);
    for (int k = 0; k < dim; ++k) v[k] = r.v[k][i];
    srd_rule_collide(fx, dim, &r.k, gm, &r.rot[c], dvx, p[1], v, r.acc);
    for (int k = 0; k < dim; ++k) r.v[k][i] = r.store(v[k]);
  }
  r.p.geom = *gm;
  r.last_gm = *gm;
  for (int k = 0; k < 3; ++k) r.last_s[k] = s[k];
  r.clamped += ncl;
  r.dt_max = std::min(r.dt_max, dtm);
  if (n_clamped || dt_max) {
    if (n_clamped) *n_clamped += r.clamped;
    if (dt_max && r.dt_max < *dt_max) *dt_max = r.dt_max;
    r.clamped = 0;
    r.dt_max = INFINITY;
  }
  return GRAN_SUCCESS;
}

int gran_ref_srd_sort(gran_cuda_srd *h) {
  GRAN_CHECK_PTR(h);
  GRAN_TRY {
    RefState &r = *ref_of(h);
    const int64_t n = r.p.n;
    const int dim = r.p.geom.dim;
    std::vector<uint32_t> key((size_t)n), perm((size_t)n);
    std::vector<int64_t> start((size_t)r.ncell + 1, 0);
    for (int64_t i = 0; i < n; ++i) {
      double p[3] = {0, 0, 0}, dvx;
      for (int k = 0; k < dim; ++k) p[k] = r.x[k][i];
      key[i] = (uint32_t)srd_bin(&r.last_gm, r.last_s, p, &dvx);
      start[key[i] + 1]++;
    }
    for (int64_t c = 0; c < r.ncell; ++c) start[c + 1] += start[c];
    for (int64_t i = 0; i < n; ++i) perm[start[key[i]]++] = (uint32_t)i; /* stable */
    std::vector<double> tmp((size_t)n);
    for (int k = 0; k < dim; ++k)
      for (std::vector<double> *a : {&r.x[k], &r.v[k]}) {
        for (int64_t i = 0; i < n; ++i) tmp[i] = (*a)[perm[i]];
        a->swap(tmp);
      }
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

int gran_ref_srd_upload(gran_cuda_srd *h, const double *const x[3], const double *const v[3], const double *vref,
                        const gran_rng *cell_rng) {
  GRAN_CHECK_PTR(h);
  RefState &r = *ref_of(h);
  for (int k = 0; k < r.p.geom.dim; ++k)
    for (int64_t i = 0; i < r.p.n; ++i) {
      if (x && x[k]) r.x[k][i] = r.store_x(k, x[k][i]);
      if (v && v[k]) r.v[k][i] = r.store(v[k][i]);
    }
  if (vref) std::copy(vref, vref + 3 * r.ncell, r.vref.begin());
  if (cell_rng) std::copy(cell_rng, cell_rng + r.ncell, r.rng.begin());
  return GRAN_SUCCESS;
}

int gran_ref_srd_download(const gran_cuda_srd *h, double *const x[3], double *const v[3], double *vref,
                          gran_rng *cell_rng) {
  GRAN_CHECK_PTR(h);
  const RefState &r = *ref_of(h);
  const size_t n = (size_t)r.p.n;
  for (int k = 0; k < r.p.geom.dim; ++k) {
    if (x && x[k] && n) std::memcpy(x[k], r.x[k].data(), n * sizeof(double));
    if (v && v[k] && n) std::memcpy(v[k], r.v[k].data(), n * sizeof(double));
  }
  if (vref) std::copy(r.vref.begin(), r.vref.end(), vref);
  if (cell_rng) std::copy(r.rng.begin(), r.rng.end(), cell_rng);
  return GRAN_SUCCESS;
}

int gran_ref_srd_ledger(gran_cuda_srd *h, double acc[SRD_ACC_N], int64_t *clamped, double *dt_max) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(acc);
  RefState &r = *ref_of(h);
  for (int q = 0; q < SRD_ACC_N; ++q) {
    acc[q] = r.acc[q];
    r.acc[q] = 0.0;
  }
  if (clamped) *clamped += r.clamped;
  if (dt_max && r.dt_max < *dt_max) *dt_max = r.dt_max;
  r.clamped = 0;
  r.dt_max = INFINITY;
  return GRAN_SUCCESS;
}

int gran_ref_srd_counts(const gran_cuda_srd *h, double *counts) {
  GRAN_CHECK_PTR(h);
  GRAN_CHECK_PTR(counts);
  const RefState &r = *ref_of(h);
  srd_geom g = r.p.geom;
  g.le_on = 0;
  const double zero[3] = {0, 0, 0};
  std::fill(counts, counts + r.ncell, 0.0);
  for (int64_t i = 0; i < r.p.n; ++i) {
    double p[3] = {0, 0, 0}, dvx;
    for (int k = 0; k < g.dim; ++k) p[k] = r.x[k][i];
    counts[srd_bin(&g, zero, p, &dvx)] += 1.0;
  }
  return GRAN_SUCCESS;
}

int gran_ref_srd_destroy(gran_cuda_srd **h) {
  if (h && *h) {
    delete ref_of(*h);
    *h = nullptr;
  }
  return GRAN_SUCCESS;
}

const gran_srd_launchers *gran_srd_launchers_get(int device) {
  static const gran_srd_launchers cuda = {"cuda",
                                          gran_cuda_srd_create,
                                          gran_cuda_srd_step,
                                          gran_cuda_srd_sort,
                                          gran_cuda_srd_upload,
                                          gran_cuda_srd_download,
                                          gran_cuda_srd_ledger,
                                          gran_cuda_srd_counts,
                                          gran_cuda_srd_destroy};
  static const gran_srd_launchers ref = {"reference",
                                         gran_ref_srd_create,
                                         gran_ref_srd_step,
                                         gran_ref_srd_sort,
                                         gran_ref_srd_upload,
                                         gran_ref_srd_download,
                                         gran_ref_srd_ledger,
                                         gran_ref_srd_counts,
                                         gran_ref_srd_destroy};
  return device == GRAN_SRD_DEVICE_CUDA ? &cuda : device == GRAN_SRD_DEVICE_REFERENCE ? &ref : nullptr;
}

/* ---- (3) engine hooks ----------------------------------------------------------------------- */

struct gran_srd_dev {
  const gran_srd_launchers *L = nullptr;
  gran_cuda_srd *h = nullptr;
  int32_t device = GRAN_SRD_DEVICE_CPU; /* CUDA or REFERENCE */
  bool host_current = true;             /* the host arrays hold the device's particles */
  bool host_dirty = false;              /* the host arrays were handed out: upload before stepping */
};

void gran_srd_dev_free(gran_srd_dev *d) {
  if (!d) return;
  if (d->L && d->h) d->L->destroy(&d->h);
  delete d;
}

gran_cuda_srd_params srd_params_of(const gran_srd *s) {
  const gran_srd_options &o = s->opt;
  gran_cuda_srd_params p;
  std::memset(&p, 0, sizeof p);
  p.geom = s->gm;
  p.n = s->n;
  p.precision = o.precision;
  p.fx = srd_fx_of(&o);
  p.dt = o.dt;
  p.alpha = o.alpha_deg * M_PI / 180.0;
  p.coef = (1.0 - o.eps * o.eps) * o.sigma * o.sigma * o.dt;
  for (int k = 0; k < 3; ++k) p.g[k] = o.accel[k];
  p.n0 = o.n0;
  p.wall_T = o.wall_T > 0 ? o.wall_T : o.T0;
  p.T0 = o.T0;
  p.shear_rate = o.shear_rate;
  return p;
}

namespace {

void host_arrays(gran_srd *s, double *x[3], double *v[3]) {
  const bool d3 = s->opt.dim == 3;
  x[0] = s->x.data();
  x[1] = s->y.data();
  x[2] = d3 ? s->z.data() : nullptr;
  v[0] = s->vx.data();
  v[1] = s->vy.data();
  v[2] = d3 ? s->vz.data() : nullptr;
}

/* start the run on device (CUDA or REFERENCE) from the host state, cells included */
int dev_start(gran_srd *s, int32_t device) {
  const gran_srd_launchers *L = gran_srd_launchers_get(device);
  GRAN_CHECK(L != nullptr, GRAN_ERR_INTERNAL, "no launchers for device %d", (int)device);
  GRAN_CALL(srd_check_finite(s, "when copied to the device"));
  const gran_cuda_srd_params p = srd_params_of(s);
  double *x[3], *v[3];
  host_arrays(s, x, v);
  gran_cuda_srd *h = nullptr;
  GRAN_CALL(L->create(&p, x, v, s->rng.data(), &h));
  std::vector<double> ref;
  srd_refs_get(s, ref); /* the cells' reference velocities (engine.cpp keeps them in its cell records) */
  int e = L->upload(h, nullptr, nullptr, ref.data(), nullptr);
  gran_srd_dev *d = e == GRAN_SUCCESS ? new (std::nothrow) gran_srd_dev : nullptr;
  if (!d) {
    L->destroy(&h);
    return e != GRAN_SUCCESS ? e : GRAN_ERROR(GRAN_ERR_NOMEM, "out of memory");
  }
  d->L = L;
  d->h = h;
  d->device = device;
  d->host_current = p.precision == 0; /* float storage: the device holds rounded values */
  gran_srd_dev_free(s->dev.p);
  s->dev.p = d;
  /* the CPU engine's step buffers are not used while the run is on a device */
  decltype(s->slab_list)().swap(s->slab_list);
  decltype(s->slab_off)().swap(s->slab_off);
  std::vector<double>().swap(s->part);
  return GRAN_SUCCESS;
}

/* bring the run back to the host (state and cells) and drop the device state */
int dev_stop(gran_srd *s) {
  if (!s->dev.p) return GRAN_SUCCESS;
  GRAN_CALL(gran_srd_dev_sync(s, 1));
  /* the CPU engine allocates its step buffers as it needs them */
  gran_srd_dev_free(s->dev.p);
  s->dev.p = nullptr;
  return GRAN_SUCCESS;
}

}  // namespace

int gran_srd_dev_attach(gran_srd *s, int from_checkpoint) {
  const gran_srd_options &o = s->opt;
  GRAN_CHECK(o.precision == 0 || o.precision == 1, GRAN_ERR_ARG,
             "option 'precision' = %d: must be 0 (double) or 1 (float; device storage)", (int)o.precision);
  int32_t dev = 0;
  GRAN_CALL(resolve_id(o.device, from_checkpoint != 0, &dev));
  if (dev == GRAN_SRD_DEVICE_CPU) return GRAN_SUCCESS;
  return dev_start(s, dev);
}

int gran_srd_dev_sync(const gran_srd *cs, int cells) {
  gran_srd *s = const_cast<gran_srd *>(cs); /* the host arrays are a cache of the device state */
  gran_srd_dev *d = s->dev.p;
  if (!d) return GRAN_SUCCESS;
  if (!d->host_current) {
    double *x[3], *v[3];
    host_arrays(s, x, v);
    GRAN_CALL(d->L->download(d->h, x, v, nullptr, nullptr));
    d->host_current = true;
    GRAN_CALL(srd_check_finite(s, "after the copy back from the device"));
  }
  if (cells) {
    std::vector<double> ref((size_t)s->ncell * 3);
    GRAN_CALL(d->L->download(d->h, nullptr, nullptr, ref.data(), s->rng.data()));
    srd_refs_set(s, ref.data());
  }
  return GRAN_SUCCESS;
}

void gran_srd_dev_touch(gran_srd *s) {
  if (s->dev.p) s->dev.p->host_dirty = true;
}

int gran_srd_dev_advance(gran_srd *s, int64_t steps) {
  gran_srd_dev *d = s->dev.p;
  GRAN_CHECK(d != nullptr, GRAN_ERR_INTERNAL, "the run is not on a device");
  const gran_srd_options &o = s->opt;
  if (d->host_dirty) {
    GRAN_CALL(srd_check_finite(s, "when copied to the device (written through gran_srd_particles)"));
    double *x[3], *v[3];
    host_arrays(s, x, v);
    GRAN_CALL(d->L->upload(d->h, x, v, nullptr, nullptr));
    d->host_dirty = false;
  }
  if (steps == 0) return GRAN_SUCCESS;
  d->host_current = false;
  const double dt = o.dt;
  int e = GRAN_SUCCESS;
  for (int64_t st = 0; st < steps && e == GRAN_SUCCESS; ++st) {
    srd_geom gm = s->gm;
    if (gm.le_on) { /* offset at the end of the step, as the CPU engine */
      double dx = std::fmod(o.shear_rate * gm.box[1] * (s->time + dt), gm.box[0]);
      if (dx < 0) dx += gm.box[0];
      gm.le_dx = dx;
    }
    if (gm.wall_axis >= 0) gm.wall_u_lo = o.vib_amp * o.vib_omega * std::cos(o.vib_omega * (s->time + dt));
    s->time += dt;
    for (int k = 0; k < 3; ++k) s->shift[k] = k < o.dim ? srd_rng_uniform(&s->shift_rng) * o.a : 0.0;
    e = d->L->step(d->h, &gm, s->shift, nullptr, nullptr);
    if (e != GRAN_SUCCESS) break;
    s->step += 1;
    if (o.sort_every > 0 && s->step % o.sort_every == 0) e = d->L->sort(d->h);
  }
  double acc[SRD_ACC_N];
  const int e2 = d->L->ledger(d->h, acc, &s->clamped, &s->dt_max);
  if (e2 == GRAN_SUCCESS) {
    s->flux_kin += acc[SRD_ACC_FLUX];
    s->e_ext += acc[SRD_ACC_EXT] + acc[SRD_ACC_LEW];
    if (o.wall_axis >= 0) s->wall_impulse[o.wall_axis] += acc[SRD_ACC_IMP];
    s->e_coll += acc[SRD_ACC_DE];
    s->flux_coll += acc[SRD_ACC_VIR];
    if (e == GRAN_SUCCESS && acc[SRD_ACC_BAD] > 0) {
      /* the per-step check of the device (after each srd_rule_move): name the first such particle from the
       * state copied back; a non-finite value stays one, so the copy shows it */
      GRAN_CALL(gran_srd_dev_sync(s, 0));
      return GRAN_ERROR(GRAN_ERR_NUMERIC, "GSRD on the device: %.0f particle moves met a non-finite position or velocity "
                        "in the last %lld steps; the run cannot continue", acc[SRD_ACC_BAD], (long long)steps);
    }
  }
  return e != GRAN_SUCCESS ? e : e2;
}

/* S(k) of a run on a device: the cell counts come from the device (ncell doubles instead of the
 * particles); the GPU transforms them with cuFFT and returns the power of the half spectrum
 * (gran_cuda_srd_sk_power), the reference with FFTW; both are binned in shells here exactly as
 * the CPU engine does (engine.cpp, gran_srd_structure_factor). */
int gran_srd_dev_structure_factor(gran_srd *s, int64_t nbins, double *k, double *sk, int64_t *count) {
  gran_srd_dev *d = s->dev.p;
  GRAN_CHECK(d != nullptr, GRAN_ERR_INTERNAL, "the run is not on a device");
  const int dim = s->opt.dim;
  const int n0 = (int)s->gm.L[0], n1 = (int)s->gm.L[1], n2 = dim == 3 ? (int)s->gm.L[2] : 1;
  const int nh = n0 / 2 + 1;
  const int64_t ncplx = (int64_t)n2 * n1 * nh;
  std::vector<double> power((size_t)ncplx);
  if (d->device == GRAN_SRD_DEVICE_CUDA) {
    GRAN_CALL(gran_cuda_srd_sk_power(d->h, power.data()));
  } else {
    std::vector<double> cnt((size_t)s->ncell);
    GRAN_CALL(d->L->counts(d->h, cnt.data()));
    GRAN_CALL(srd_sk_power(s, cnt.data(), power));
  }
  srd_sk_shells(s, power.data(), nbins, k, sk, count);
  return GRAN_SUCCESS;
}

/* ---- public -------------------------------------------------------------------------------- */

GRAN_EXTERN int gran_srd_set_device(gran_srd *s, int32_t device) {
  GRAN_TRY {
    GRAN_CHECK_PTR_AS(s, srd);
    int32_t target = 0;
    GRAN_CALL(resolve_id(device, false, &target));
    const int32_t now = s->dev.p ? s->dev.p->device : GRAN_SRD_DEVICE_CPU;
    if (target != now) {
      GRAN_CALL(dev_stop(s));
      if (target != GRAN_SRD_DEVICE_CPU) {
        const int e = dev_start(s, target);
        if (e != GRAN_SUCCESS) {
          s->opt.device = GRAN_SRD_DEVICE_CPU; /* stays on the CPU, state intact */
          return e;
        }
      }
    }
    s->opt.device = device; /* what checkpoints record */
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

GRAN_EXTERN int gran_srd_get_device(const gran_srd *s, int32_t *device) {
  GRAN_CHECK_PTR_AS(s, srd);
  GRAN_CHECK_PTR(device);
  *device = s->dev.p ? s->dev.p->device : GRAN_SRD_DEVICE_CPU;
  return GRAN_SUCCESS;
}
