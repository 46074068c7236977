/* granary_impl.h - private declarations shared by the library's modules (never installed). */
#ifndef GRANARY_IMPL_H
#define GRANARY_IMPL_H

#include "granary.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <new>
#include <stdexcept>

/* ---- error recording -------------------------------------------------------------------------
 * gran_error_set() stores "func (file:line): message" in the thread-local buffer and returns code;
 * it never prints or aborts. Use through the macros below. */
int gran_error_set(int code, const char *file, int line, const char *func, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));
/* Record a warning (for instance a value that was clamped); the library never prints it. */
void gran_warning_add(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

#define GRAN_ERROR(code, ...) gran_error_set((code), __FILE__, __LINE__, __func__, __VA_ARGS__)

/* Return `code` with a message when `cond` is false. */
#define GRAN_CHECK(cond, code, ...)                         \
  do {                                                      \
    if (!(cond)) return GRAN_ERROR((code), __VA_ARGS__);    \
  } while (0)

/* Propagate a failing status (the callee already recorded the message). */
#define GRAN_CALL(expr)                 \
  do {                                  \
    int gran_ierr_ = (expr);            \
    if (gran_ierr_ != GRAN_SUCCESS) return gran_ierr_; \
  } while (0)

#define GRAN_CHECK_PTR(p) GRAN_CHECK((p) != nullptr, GRAN_ERR_ARG, "argument '%s' is NULL", #p)
/* the same for a pointer held under another name than the public parameter it names */
#define GRAN_CHECK_PTR_AS(p, name) GRAN_CHECK((p) != nullptr, GRAN_ERR_ARG, "argument '%s' is NULL", #name)
#define GRAN_CHECK_FINITE(x) \
  GRAN_CHECK(std::isfinite(x), GRAN_ERR_ARG, "argument '%s' is not finite (%g)", #x, (double)(x))

/* Exception barrier for every C entry point (FINUFFT safe_call): no C++ exception crosses the ABI.
 *   int gran_foo(...) { GRAN_TRY { ... return GRAN_SUCCESS; } GRAN_CATCH }               */
#define GRAN_TRY try
#define GRAN_CATCH                                                                   \
  catch (const std::bad_alloc &) {                                                   \
    return GRAN_ERROR(GRAN_ERR_NOMEM, "out of memory");                              \
  }                                                                                  \
  catch (const std::exception &e) {                                                  \
    return GRAN_ERROR(GRAN_ERR_INTERNAL, "unexpected exception: %s", e.what());      \
  }                                                                                  \
  catch (...) {                                                                      \
    return GRAN_ERROR(GRAN_ERR_INTERNAL, "unexpected exception");                    \
  }

/* DSMC engine state into / from a group of an HDF5 file that is already open (the run driver
 * builds its files in memory: src/io/h5.cpp); `path` names the file in messages. Read: with
 * `expect` (the run driver: the options of its scene with the replica's seed), the stored options
 * must equal it, and so must the stored cell options (`expect_cell`, the scene's [cell] table,
 * for the cell selector) and aggregation options (`expect_agg`, the scene's processes: a stored
 * state with aggregation for a scene without, or the reverse, is refused too); refused naming the
 * option. */
int gran_dsmc_checkpoint_write_h5_(const gran_dsmc *sim, int64_t file_id, const char *group, const char *path);
int gran_dsmc_checkpoint_read_h5_(int64_t file_id, const char *group, const gran_mixture *mix,
                                  const gran_dsmc_options *expect, const gran_dsmc_cell_options *expect_cell,
                                  const gran_dsmc_agg_options *expect_agg, gran_dsmc **sim, const char *path);
/* GSRD engine state likewise (src/srd/checkpoint.cpp); read: with `expect` (the options the run's
 * scene gives), every stored physics option must equal the expected one (refused naming it). */
int gran_srd_checkpoint_write_h5_(const gran_srd *srd, int64_t file_id, const char *group, const char *path);
int gran_srd_checkpoint_read_h5_(int64_t file_id, const char *group, const char *path, const gran_srd_options *expect,
                                 gran_srd **srd);

/* The FFTW planner is not thread-safe: every plan creation/destruction in the library holds this
 * lock (defined in src/analysis/tamsd.cpp). Execution of a made plan needs no lock. */
std::mutex &gran_fftw_planner_mutex();

/* Checked allocation helpers (return nullptr on failure; callers map to GRAN_ERR_NOMEM). */
template <class T> static inline T *gran_alloc(int64_t n) {
  if (n <= 0) return nullptr;
  return static_cast<T *>(std::malloc(sizeof(T) * (size_t)n));
}
template <class T> static inline T *gran_calloc(int64_t n) {
  if (n <= 0) return nullptr;
  return static_cast<T *>(std::calloc((size_t)n, sizeof(T)));
}

/* ---- RNG core (inline, for hot loops; the public gran_rng_* functions wrap these) ----------- */
/* GRAN_HD: the RNG core is __host__ __device__ under nvcc, so CUDA kernels draw the same bits
 * (cuda/rng.cu); plain host code elsewhere. The draws themselves are in core/xoshiro.h (plain C,
 * shared with the GSRD kernels). */
#include "core/xoshiro.h"
namespace gran {

GRAN_HD static inline uint64_t splitmix64(uint64_t *x) {
  uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

GRAN_HD static inline uint64_t rng_next(gran_rng *r) { return gran_xo_next(r); }
GRAN_HD static inline double rng_uniform(gran_rng *r) { return gran_xo_uniform(r); }         /* [0,1) */
GRAN_HD static inline double rng_uniform_pos(gran_rng *r) { return gran_xo_uniform_pos(r); } /* (0,1] */
GRAN_HD static inline double rng_exponential(gran_rng *r) { return -std::log(rng_uniform_pos(r)); }
GRAN_HD static inline double rng_normal(gran_rng *r) { return gran_xo_normal(r); }
GRAN_HD static inline void rng_unit3(gran_rng *r, double e[3]) { gran_xo_unit3(r, e); }

GRAN_HD static inline void rng_unit2(gran_rng *r, double e[2]) {
  double u, v, s;
  do {
    u = 2.0 * rng_uniform(r) - 1.0;
    v = 2.0 * rng_uniform(r) - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  e[0] = (u * u - v * v) / s;
  e[1] = 2.0 * u * v / s;
}

/* ---- segment tree core ------------------------------------------------------------------------
 * Descend from the root with target = u * total. Ties and rounding never select a zero leaf: at
 * each node we go right only when the right subtree has positive weight. */
static inline int64_t segtree_sample(const gran_segtree *t, double u) {
  const double *node = t->node;
  double x = u * node[1];
  int64_t i = 1;
  while (i < t->base) {
    const int64_t l = 2 * i;
    const double wl = node[l];
    if ((x < wl || node[l + 1] <= 0.0) && wl > 0.0) {
      i = l;
    } else {
      x -= wl;
      i = l + 1;
    }
  }
  return i - t->base;
}

static inline void segtree_set(gran_segtree *t, int64_t leaf, double w) {
  double *node = t->node;
  int64_t i = t->base + leaf;
  node[i] = w;
  for (i >>= 1; i >= 1; i >>= 1) node[i] = node[2 * i] + node[2 * i + 1];
  t->nupdate++;
}

}  // namespace gran

#endif /* GRANARY_IMPL_H */
