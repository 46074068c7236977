/*
 * granary.h - the one public header of granary: simulation and kinetic theory of granular gases.
 *
 * Valid C99 and C++. Every function returns an int status (GRAN_SUCCESS = 0, negative on error)
 * and hands results back through out-pointers; gran_strerror() names a code and
 * gran_last_error_message() (thread-local) names the argument or scene key that was wrong.
 * Nothing aborts, prints or throws across this interface.
 *
 * Ownership: arrays passed in are borrowed for the duration of the call unless a function says
 * otherwise; arrays inside the plain structs (gran_segtree, gran_particles) belong to the struct and
 * are released by its *_free function; opaque handles are released by *_destroy(&h), which is
 * NULL-safe and sets h to NULL.
 *
 * Counts are int64_t (print with GRAN_I64_FMT). Flags are int, not bool.
 * Fortran: module `granary` (bindings/granary.f90) mirrors everything here with bind(C).
 */
#ifndef GRANARY_H
#define GRANARY_H

#include <stddef.h>
#include <stdint.h>
#include <inttypes.h>

#ifdef __cplusplus
#define GRAN_EXTERN extern "C" __attribute__((visibility("default")))
#else
#define GRAN_EXTERN extern __attribute__((visibility("default")))
#endif

#define GRAN_I64_FMT "%" PRId64

/* ---------------------------------------------------------------------------------------------
 * Version and build
 * ------------------------------------------------------------------------------------------- */
#define GRAN_VERSION_MAJOR 0
#define GRAN_VERSION_MINOR 1
#define GRAN_VERSION_PATCH 0
#define GRAN_VERSION_STRING "0.1.0"
/* The ABI number: the shared library's SONAME is libgranary.so.GRAN_ABI_VERSION. It rises with
 * every change that can break a program built against an older header (a struct's fields, a
 * function's parameters, a constant's value, a removed name); additions leave it. The rules are in
 * the developers' pages (abi.md); include/granary.abi records the ABI it names. At run time,
 * gran_abi_query("GRAN_ABI_VERSION", &v) gives the library's number. */
#define GRAN_ABI_VERSION 1

GRAN_EXTERN int gran_get_version(int *major, int *minor, int *patch);
/* Build configuration, e.g. "cxx=g++ 12.2 flags=-O3 -march=native cuda=yes". Static storage. */
GRAN_EXTERN int gran_get_build_config(const char **config);
/* 1 when the CUDA backend was compiled in, else 0. */
GRAN_EXTERN int gran_cuda_compiled(int *compiled);
/* Number of visible CUDA devices (0 without a GPU or without the CUDA backend). */
GRAN_EXTERN int gran_cuda_device_count(int *count);

/* ---------------------------------------------------------------------------------------------
 * Errors: one X-macro list (numbers never reused).  X(NAME, value, "message")
 * ------------------------------------------------------------------------------------------- */
#define GRAN_ERROR_LIST(X)                                                                  \
  X(GRAN_SUCCESS, 0, "success")                                                             \
  X(GRAN_ERR_ARG, -1, "invalid argument")                                                   \
  X(GRAN_ERR_NOMEM, -2, "out of memory")                                                    \
  X(GRAN_ERR_DOMAIN, -3, "value outside the domain of the model")                           \
  X(GRAN_ERR_NOCONV, -4, "iteration did not converge")                                      \
  X(GRAN_ERR_IO, -5, "file input/output failed")                                            \
  X(GRAN_ERR_PARSE, -6, "scene file could not be parsed")                                   \
  X(GRAN_ERR_UNSUPPORTED, -7, "feature not available in this build")                        \
  X(GRAN_ERR_STATE, -8, "object is not in a state that allows this call")                   \
  X(GRAN_ERR_EMPTY, -9, "nothing to sample: all weights are zero")                          \
  X(GRAN_ERR_RANGE, -10, "index out of range")                                              \
  X(GRAN_ERR_CUDA, -11, "CUDA runtime error")                                               \
  X(GRAN_ERR_NUMERIC, -12, "numerical failure (non-finite intermediate result)")            \
  X(GRAN_ERR_INTERNAL, -99, "internal error")

#define GRAN_ERROR_ENUM_(name, value, msg) name = value,
enum gran_error { GRAN_ERROR_LIST(GRAN_ERROR_ENUM_) GRAN_ERROR_LIST_END_ = -100 };
#undef GRAN_ERROR_ENUM_

/* Static string naming the code ("GRAN_ERR_ARG: invalid argument"); never NULL. */
GRAN_EXTERN const char *gran_strerror(int code);
/* Thread-local message of the last failure in this thread ("" when none). */
GRAN_EXTERN const char *gran_last_error_message(void);
/* Copy of that message into buf (NUL-terminated, truncated to len); for Fortran. */
GRAN_EXTERN int gran_last_error_copy(char *buf, int64_t len);
/* Where that failure was detected: "function (file.cpp:line), GRAN_ERR_...: text" ("" when none);
 * for bug reports and `granary --verbose`, kept out of the message itself. */
GRAN_EXTERN int gran_last_error_location_copy(char *buf, int64_t len);
GRAN_EXTERN int gran_clear_error(void);
/* Set the thread's last error message (a check made outside the library, e.g. a Fortran wrapper's
 * array sizes); returns code, a negative GRAN_ERR_* (else GRAN_ERR_ARG and its own message). */
GRAN_EXTERN int gran_set_error_message(int code, const char *message);
/* Warnings (e.g. a clamped value) are collected per thread; 0 disables printing them to stderr
 * from the command-line driver. The library itself never prints. */
GRAN_EXTERN int gran_warning_count(int64_t *count);
GRAN_EXTERN int gran_last_warning_copy(char *buf, int64_t len);

/* ---------------------------------------------------------------------------------------------
 * RNG: xoshiro256** (xorshift family) with jump (2^128) and long_jump (2^192).
 * A POD: the four words describe the stream completely (no cached normal deviate).
 * ------------------------------------------------------------------------------------------- */
typedef struct gran_rng {
  uint64_t s[4];
} gran_rng;

/* State = four successive splitmix64 outputs of seed. */
GRAN_EXTERN int gran_rng_seed(gran_rng *rng, uint64_t seed);
/* Independent reproducible stream (thread, cell, replica): gran_rng_seed(seed) advanced by
 * stream_id * 2^128 steps (= stream_id jumps) in O(log stream_id); streams never overlap. */
GRAN_EXTERN int gran_rng_stream(uint64_t seed, uint64_t stream_id, gran_rng *rng);
GRAN_EXTERN int gran_rng_jump(gran_rng *rng);      /* advance 2^128 steps */
GRAN_EXTERN int gran_rng_long_jump(gran_rng *rng); /* advance 2^192 steps */
GRAN_EXTERN int gran_rng_u64(gran_rng *rng, int64_t n, uint64_t *out);
GRAN_EXTERN int gran_rng_uniform(gran_rng *rng, int64_t n, double *out);     /* [0,1) */
GRAN_EXTERN int gran_rng_uniform_pos(gran_rng *rng, int64_t n, double *out); /* (0,1] */
GRAN_EXTERN int gran_rng_exponential(gran_rng *rng, int64_t n, double *out); /* mean 1 */
GRAN_EXTERN int gran_rng_normal(gran_rng *rng, int64_t n, double *out);      /* N(0,1) */
/* n unit vectors, interleaved xyz (3n doubles) / xy (2n doubles). */
GRAN_EXTERN int gran_rng_unit_vector3(gran_rng *rng, int64_t n, double *xyz);
GRAN_EXTERN int gran_rng_unit_vector2(gran_rng *rng, int64_t n, double *xy);
/* GPU: stream k (states[k], host array, not modified) draws n_per_stream uniforms in [0,1) into
 * out[k*n_per_stream ...] (host array), bit-identical to gran_rng_uniform on a copy of states[k].
 * GRAN_ERR_UNSUPPORTED without the CUDA backend or without a visible GPU. */
GRAN_EXTERN int gran_cuda_rng_uniform(const gran_rng *states, int64_t nstreams, int64_t n_per_stream,
                                      double *out);

/* ---------------------------------------------------------------------------------------------
 * Segment tree: sum tree over m >= 1 nonnegative weights (any m, not only powers of two).
 * node[1] is the root; leaf i is node[base + i]; node[0] unused. Owned by the struct.
 * ------------------------------------------------------------------------------------------- */
typedef struct gran_segtree {
  int64_t m;        /* number of weights (leaves) */
  int64_t base;     /* first leaf index: smallest power of two >= m */
  int64_t nupdate;  /* updates since the last full rebuild (drift control) */
  double *node;     /* 2*base sums */
} gran_segtree;

/* O(m); w may be NULL: zeros. Overwrites *t (free an initialised tree first). */
GRAN_EXTERN int gran_segtree_init(gran_segtree *t, int64_t m, const double *w);
GRAN_EXTERN int gran_segtree_free(gran_segtree *t);
GRAN_EXTERN int gran_segtree_set(gran_segtree *t, int64_t i, double w);
/* n leaves at once (a repeated index keeps its last value); affected parents recomputed level by
 * level, O(n log(m/n) + n). */
GRAN_EXTERN int gran_segtree_set_batch(gran_segtree *t, int64_t n, const int64_t *idx, const double *w);
GRAN_EXTERN int gran_segtree_get(const gran_segtree *t, int64_t i, double *w);
GRAN_EXTERN int gran_segtree_total(const gran_segtree *t, double *total);
/* index with probability w_i/total from one uniform u in [0,1); GRAN_ERR_EMPTY when total == 0.
 * A zero-weight leaf is never returned. Weights must be finite and >= 0 (else GRAN_ERR_ARG). */
GRAN_EXTERN int gran_segtree_sample(const gran_segtree *t, double u, int64_t *index);
/* Recompute internal nodes from the leaves (after writing t->node[base+i] directly). Updates
 * already recompute parents from children, so a tree never drifts from a fresh rebuild. */
GRAN_EXTERN int gran_segtree_rebuild(gran_segtree *t);

/* ---------------------------------------------------------------------------------------------
 * Particle arrays: explicit structure of arrays. Velocity components are interleaved per
 * particle (v[3i], v[3i+1], v[3i+2]) because every hot loop reads them together; optional arrays
 * are NULL unless their flag was given.
 * ------------------------------------------------------------------------------------------- */
enum gran_particle_flags {
  GRAN_PARTICLES_DISPLACEMENT = 1, /* r (3 per particle) and t_last: for MSD / TAMSD */
  GRAN_PARTICLES_POSITION = 2,     /* x (3 per particle): spatial DSMC */
  GRAN_PARTICLES_MASS = 4          /* mass per particle: aggregation / fragmentation */
};

typedef struct gran_particles {
  int64_t n;         /* particles in use */
  int64_t capacity;  /* allocated slots */
  int32_t flags;     /* gran_particle_flags */
  int32_t pad_;
  double *v;         /* 3*capacity velocities, interleaved */
  int32_t *species;  /* capacity species indices (0-based) */
  double *r;         /* 3*capacity displacements, or NULL */
  double *t_last;    /* capacity times of last displacement update, or NULL */
  double *x;         /* 3*capacity positions, or NULL */
  double *mass;      /* capacity masses, or NULL */
} gran_particles;

/* capacity >= 0; overwrites *p (free initialised particles first). */
GRAN_EXTERN int gran_particles_init(gran_particles *p, int64_t capacity, int flags);
GRAN_EXTERN int gran_particles_free(gran_particles *p); /* NULL-safe; zeroes the struct */
GRAN_EXTERN int gran_particles_reserve(gran_particles *p, int64_t capacity); /* never shrinks */
/* O(1) amortised; optional arrays of the new particle are zeroed; index may be NULL. */
GRAN_EXTERN int gran_particles_add(gran_particles *p, const double v[3], int32_t species, int64_t *index);
/* O(1): the last particle moves into slot i. */
GRAN_EXTERN int gran_particles_swap_remove(gran_particles *p, int64_t i);
/* bytes held by the arrays: capacity * (28, +32 displacement, +24 position, +8 mass) */
GRAN_EXTERN int gran_particles_memory(const gran_particles *p, int64_t *bytes);

/* ABI self-description for bindings: "sizeof(gran_rng)" for every struct of this header,
 * "offsetof(gran_rng, s)" for every field of each, and the value of every enum constant and version
 * macro by its name ("GRAN_ERR_ARG", "GRAN_SELECTOR_BIRD", "GRAN_VERSION_MAJOR", ...). Unknown name:
 * GRAN_ERR_ARG. */
GRAN_EXTERN int gran_abi_query(const char *name, int64_t *value);

/* ---- Kinetic theory (src/theory) ------------------------------------------------------------
 * Kinetic theory of polydisperse granular gases (Bodrova & Osinsky Sec. II, App. A; the DSMC outline).
 * Species are 0-based in C (species "k" of the paper is index k-1). Arrays of per-species values
 * have length M; time series are row-major [time][species]; pair matrices are row-major M*M
 * (symmetric: checked). Tolerances rtol lie in [1e-14, 0.1]. Mixtures need M >= 1 and at least one
 * n_k > 0; the viscoelastic model has no HCS (gran_theory_hcs, _msd_hcs, _tamsd: GRAN_ERR_DOMAIN).
 * ------------------------------------------------------------------------------------------- */
typedef struct gran_mixture gran_mixture; /* opaque */

enum gran_restitution_model {
  GRAN_RESTITUTION_CONSTANT = 0,    /* one eps for every pair */
  GRAN_RESTITUTION_MATRIX = 1,      /* eps_ij per pair */
  GRAN_RESTITUTION_VISCOELASTIC = 2 /* eps(v_n), beta_ij per pair (docs/physics.md, Viscoelastic restitution) */
};
enum gran_hcs_norm {
  GRAN_HCS_NORM_MEAN = 0, /* number-weighted mean temperature <T(0)> = value (Bodrova & Osinsky Eq. 25) */
  GRAN_HCS_NORM_T1 = 1    /* T of the first species = value */
};

/* mass, sigma: NULL for the defaults m_k = k, sigma_k = k^(1/3) (k = 1..M); density: n_k >= 0
 * (n_k = 0 marks a tracer species). Restitution defaults to eps = 1, g2 to 1. */
GRAN_EXTERN int gran_mixture_create(int64_t nspecies, const double *mass, const double *sigma,
                                    const double *density, gran_mixture **mix);
/* n_k = n1 k^-theta, m_k = k m1, sigma_k = sigma1 k^(1/3). */
GRAN_EXTERN int gran_mixture_create_powerlaw(int64_t nspecies, double m1, double sigma1, double n1,
                                             double theta, gran_mixture **mix);
GRAN_EXTERN int gran_mixture_destroy(gran_mixture **mix);
GRAN_EXTERN int gran_mixture_nspecies(const gran_mixture *mix, int64_t *nspecies);
/* Any output may be NULL. */
GRAN_EXTERN int gran_mixture_get(const gran_mixture *mix, double *mass, double *sigma, double *density);
GRAN_EXTERN int gran_mixture_set_restitution(gran_mixture *mix, double eps);
GRAN_EXTERN int gran_mixture_set_restitution_matrix(gran_mixture *mix, const double *eps);
/* Viscoelastic: one beta for every pair, a matrix, or from one material (A, Y, nu) per pair. */
GRAN_EXTERN int gran_mixture_set_viscoelastic(gran_mixture *mix, double beta);
GRAN_EXTERN int gran_mixture_set_viscoelastic_matrix(gran_mixture *mix, const double *beta);
GRAN_EXTERN int gran_mixture_set_viscoelastic_material(gran_mixture *mix, double A, double Y, double nu);
GRAN_EXTERN int gran_mixture_set_g2(gran_mixture *mix, double g2);
GRAN_EXTERN int gran_mixture_set_g2_matrix(gran_mixture *mix, const double *g2);
GRAN_EXTERN int gran_mixture_restitution_model(const gran_mixture *mix, int *model);
/* Parameters of pair (i, k): eps (constant/matrix models; NaN when viscoelastic), beta (viscoelastic,
 * else 0), g2; any may be NULL. Material beta: (3/2) A (rho/m_eff)^(2/5), rho = 2 Y sqrt(R_eff)/(3(1-nu^2)),
 * R_eff = sigma_i sigma_k/(2(sigma_i+sigma_k)) (radius = sigma/2). */
GRAN_EXTERN int gran_mixture_pair(const gran_mixture *mix, int64_t i, int64_t k, double *eps,
                                  double *beta, double *g2);

/* Viscoelastic restitution eps(x), x = sqrt(beta) |v_n|^(1/10): 20-term series, [3/6] Pade beyond. */
GRAN_EXTERN int gran_viscoelastic_eps(double x, double *eps);
/* eps for a pair with parameter beta and normal relative speed |v_n|. */
GRAN_EXTERN int gran_viscoelastic_eps_vn(double beta, double vn, double *eps);

/* Cooling rates xi_k (Eq. 14-15, or A7 for viscoelastic) at temperatures T. */
GRAN_EXTERN int gran_theory_cooling_rates(const gran_mixture *mix, const double *T, double *xi);
/* Velocity correlation times tau_v,k (Eq. 10-11 / A6), diffusion coefficients D_k (Eq. 8),
 * inverse mean collision time of species 1 (Eq. 7). */
GRAN_EXTERN int gran_theory_tau_v(const gran_mixture *mix, const double *T, double *tau_v);
GRAN_EXTERN int gran_theory_diffusion(const gran_mixture *mix, const double *T, double *D);
GRAN_EXTERN int gran_theory_collision_rate1(const gran_mixture *mix, const double *T, double *inv_tau_c);
/* Homogeneous cooling state: T0 (M) with equal cooling rates and tau0 (Eq. 21; inf for eps = 1). */
GRAN_EXTERN int gran_theory_hcs(const gran_mixture *mix, int norm, double value, double *T0, double *tau0);
/* Level of the kinetic theory (the `approximation` argument): Maxwellian velocity distributions
 * (the reference level above), or the first Sonine approximation f_k = Maxwellian (1 + a2_k S2),
 * with zeta_k corrected linearly in a2 and a2_k from the fourth-moment balance (3-D hard spheres,
 * constant or matrix restitution; viscoelastic: rates and trajectories, with eps(v_n) inside the
 * collision integrals, but no HCS: GRAN_ERR_DOMAIN). docs/physics-sonine.md. */
enum gran_theory_approximation { GRAN_THEORY_MAXWELLIAN = 0, GRAN_THEORY_SONINE = 1 };
/* HCS in either approximation: T0 (M), a2 (M, may be NULL; zeros at the Maxwellian level), tau0 =
 * 2/zeta (may be NULL). One species at constant eps gives van Noije & Ernst's a2. Viscoelastic
 * restitution has no HCS: GRAN_ERR_DOMAIN at the Sonine level. */
GRAN_EXTERN int gran_theory_hcs_approx(const gran_mixture *mix, int approximation, int norm, double value, double *T0,
                                       double *a2, double *tau0);
/* First Sonine rates at (T, a2), |a2_k| < 1: zeta_k (dT_k/dt = -zeta_k T_k) and da2_k/dt (M each,
 * either may be NULL). */
GRAN_EXTERN int gran_theory_sonine_rates(const gran_mixture *mix, const double *T, const double *a2, double *zeta,
                                         double *da2dt);
/* Second Sonine approximation, f_k = Maxwellian (1 + a2_k S2 + a3_k S3), zeta_k and the <v^4>, <v^6> balances
 * linear in (a2, a3); constant or matrix restitution (viscoelastic: GRAN_ERR_DOMAIN). The HCS: T0 (M), a2, a3 (M
 * each, may be NULL), tau0 = 2/zeta (may be NULL); dense solve, up to 128 species (beyond: GRAN_ERR_DOMAIN).
 * The rates at (T, a2, a3), |a2_k|, |a3_k| < 1: zeta_k, da2_k/dt, da3_k/dt (M each, any may be NULL).
 * docs/physics-sonine.md Sec. 4. */
GRAN_EXTERN int gran_theory_hcs_sonine2(const gran_mixture *mix, int norm, double value, double *T0, double *a2,
                                        double *a3, double *tau0);
GRAN_EXTERN int gran_theory_sonine2_rates(const gran_mixture *mix, const double *T, const double *a2, const double *a3,
                                          double *zeta, double *da2dt, double *da3dt);
/* T_k(t), a2_k(t), a3_k(t) of the second Sonine approximation (ntimes*M each; a2, a3 may be NULL) from T0 (M) and
 * a20, a30 (M each, |a| < 1; NULL: 0): dT_k/dt = -zeta_k T_k with the rates above (GSL odeiv2, relative tolerance
 * rtol); GRAN_ERR_DOMAIN naming the species and the time where |a2_k| or |a3_k| reaches 1. */
GRAN_EXTERN int gran_theory_temperatures_sonine2(const gran_mixture *mix, const double *T0, const double *a20,
                                                 const double *a30, int64_t ntimes, const double *t, double rtol,
                                                 double *T, double *a2, double *a3);
/* The linear Sonine hierarchy to order nmax = 2..5 (f_k with a_2..a_nmax; nmax = 2 and 3 are the first and the
 * second Sonine HCS above): T0 (M), a (M*(nmax - 1), a[k*(nmax - 1) + q - 2] = a_q of species k; may be NULL), tau0
 * (may be NULL); up to 64 species. docs/physics-sonine.md Sec. 4. */
GRAN_EXTERN int gran_theory_hcs_sonine_n(const gran_mixture *mix, int nmax, int norm, double value, double *T0,
                                         double *a, double *tau0);
/* T_k(t) and a2_k(t) (ntimes*M each; a2 may be NULL) from T0 and a20 (NULL: 0) in either
 * approximation (Maxwellian: gran_theory_temperatures, a2 = 0); any restitution model (for
 * viscoelastic restitution a2_k depends on time even at long times). */
GRAN_EXTERN int gran_theory_temperatures_approx(const gran_mixture *mix, int approximation, const double *T0,
                                                const double *a20, int64_t ntimes, const double *t, double rtol,
                                                double *T, double *a2);
/* Diffusion and MSD beyond the single exponential (GRAN_THEORY_SONINE): the two-moment (second
 * Sonine) velocity correlation of each species, two relaxation rates per species.
 * D_k at temperatures T (M), a2 (M or NULL: 0), zeta (M cooling rates, or NULL: the Maxwellian xi_k);
 * the Maxwellian level gives T_k tau_v,k/m_k. */
GRAN_EXTERN int gran_theory_diffusion_approx(const gran_mixture *mix, int approximation, const double *T,
                                             const double *a2, const double *zeta, double *D);
/* MSD in the HCS (T0, a2, tau0 of gran_theory_hcs_approx in the same approximation; a2 may be NULL):
 * msd ntimes*M, msd_total ntimes or NULL. Maxwellian: gran_theory_msd_hcs (Eq. 22). */
GRAN_EXTERN int gran_theory_msd_hcs_approx(const gran_mixture *mix, int approximation, const double *T0,
                                           const double *a2, double tau0, int64_t ntimes, const double *t, double *msd,
                                           double *msd_total);
/* TAMSD in the HCS (Eq. 27; tamsd nlag*M) in either approximation (T0, a2, tau0 as for
 * gran_theory_msd_hcs_approx). Maxwellian: gran_theory_tamsd. */
GRAN_EXTERN int gran_theory_tamsd_approx(const gran_mixture *mix, int approximation, const double *T0,
                                         const double *a2, double tau0, double t_meas, int64_t nlag,
                                         const double *lag, double rtol, double *tamsd);
/* MSD by Eq. 4 from any start T0 (constant or matrix restitution for GRAN_THEORY_SONINE): the
 * Maxwellian temperatures T_k(t) with the two-moment correlation at T(t1) in the Sonine
 * approximation. Maxwellian: gran_theory_msd. */
GRAN_EXTERN int gran_theory_msd_approx(const gran_mixture *mix, int approximation, const double *T0, int64_t ntimes,
                                       const double *t, double rtol, double *msd, double *msd_total);
/* MSD by Eq. 4 on the first Sonine trajectory (constant or matrix restitution): T_k(t), a2_k(t) of
 * gran_theory_temperatures_approx (GRAN_THEORY_SONINE) from T0 and a20 (M, abs(a2_k) < 1; NULL: 0),
 * the two-moment correlation at T(t1) with the Sonine cooling rate zeta_k(t1), and the a2_i(t1) of all
 * species in it when correlation_a2 = 1 (collision integrals and initial fourth moment; 0: a2 = 0
 * in the correlation). From a Sonine HCS, correlation_a2 = 1 gives
 * gran_theory_msd_hcs_approx. msd ntimes*M, msd_total ntimes or NULL. docs/physics-sonine.md Sec. 5. */
GRAN_EXTERN int gran_theory_msd_sonine(const gran_mixture *mix, const double *T0, const double *a20,
                                       int correlation_a2, int64_t ntimes, const double *t, double rtol, double *msd,
                                       double *msd_total);
/* MSD by Eq. 4 on the second Sonine trajectory (constant or matrix restitution): T_k(t), a2_k(t), a3_k(t) of
 * gran_theory_temperatures_sonine2 from T0, a20 and a30 (M each, |a| < 1; NULL: 0), the two-moment correlation
 * at T(t1) with the second-level cooling rate zeta_k(t1) (a3 enters there), and the a2_i(t1) in it when
 * correlation_a2 = 1 (as gran_theory_msd_sonine). msd ntimes*M, msd_total ntimes or NULL.
 * docs/physics-sonine.md Sec. 5. */
GRAN_EXTERN int gran_theory_msd_sonine2(const gran_mixture *mix, const double *T0, const double *a20,
                                        const double *a30, int correlation_a2, int64_t ntimes, const double *t,
                                        double rtol, double *msd, double *msd_total);
/* T_k(t) from T0 by Eq. 13 (GSL odeiv2, relative tolerance rtol); T is ntimes*M. */
GRAN_EXTERN int gran_theory_temperatures(const gran_mixture *mix, const double *T0, int64_t ntimes,
                                         const double *t, double rtol, double *T);
/* T_k(t) of a driven mixture (Maxwellian level): Eq. 13 plus heating rates dT_k/dt (heating: M
 * values >= 0, the white-noise thermostat, or NULL) and the energy exchanged in elastic collisions
 * with a Maxwellian bath (bath_density n_b > 0, bath_mass, bath_T, bath_sigma: contact at
 * (sigma_k + sigma_b)/2; n_b = 0: no bath) that does not change; T is ntimes*M. docs/physics.md,
 * "Bath heating and its first Sonine correction". */
GRAN_EXTERN int gran_theory_temperatures_driven(const gran_mixture *mix, const double *T0, const double *heating,
                                                double bath_density, double bath_mass, double bath_T,
                                                double bath_sigma, int64_t ntimes, const double *t, double rtol,
                                                double *T);
/* MSD in the HCS, closed form Eq. 22 (msd ntimes*M; msd_total Eq. 3, ntimes, may be NULL). */
GRAN_EXTERN int gran_theory_msd_hcs(const gran_mixture *mix, const double *T0, double tau0,
                                    int64_t ntimes, const double *t, double *msd, double *msd_total);
/* MSD by numerical integration of Eq. 4 from any start T0 and any restitution model. */
GRAN_EXTERN int gran_theory_msd(const gran_mixture *mix, const double *T0, int64_t ntimes,
                                const double *t, double rtol, double *msd, double *msd_total);
/* TAMSD in the HCS (Eq. 27) over measurement time t_meas for nlag lags (tamsd nlag*M). */
GRAN_EXTERN int gran_theory_tamsd(const gran_mixture *mix, const double *T0, double tau0, double t_meas,
                                  int64_t nlag, const double *lag, double rtol, double *tamsd);
/* The TAMSD as a simulation measures it: averaged over the sample times j dt, j = 0..nsamples-1
 * (the discrete sum of Eq. 26 on that grid; Eq. 27 is its limit dt -> 0). Lags in samples,
 * 0 <= lag < nsamples; tamsd nlag*M. */
GRAN_EXTERN int gran_theory_tamsd_sampled(const gran_mixture *mix, const double *T0, double tau0, double dt,
                                          int64_t nsamples, int64_t nlag, const int64_t *lag, double rtol,
                                          double *tamsd);
/* The two terms of Eq. 27: delta0 (closed form, no cancellation for lag << t_meas) and Xi (GSL
 * quadrature); delta0 + Xi = tamsd up to cancellation at lags << tau_v. nlag*M each; either may be NULL. */
GRAN_EXTERN int gran_theory_tamsd_parts(const gran_mixture *mix, const double *T0, double tau0, double t_meas,
                                        int64_t nlag, const double *lag, double rtol, double *delta0, double *xi);
/* MSD of species 1 by Eq. 31 (M = 1, or every other species a tracer), from T_1(0) = T1; tau0 (Eq. 29,
 * may be NULL) out. msd has ntimes values. */
GRAN_EXTERN int gran_theory_msd_mono(const gran_mixture *mix, double T1, int64_t ntimes, const double *t,
                                     double *msd, double *tau0);
/* Reduced times tau_k(t) of Eq. 6 (units of tau_c(0), Eq. 7) from any start T0 (ODE); ntimes*M. */
GRAN_EXTERN int gran_theory_reduced_time(const gran_mixture *mix, const double *T0, int64_t ntimes,
                                         const double *t, double rtol, double *tau);
/* Tracer limit (Sec. II F): species `tracer` (0-based, n = 0) in the monodisperse gas of species 1
 * (all others tracers). gamma = T_tracer/T_1 by the mu >> 1 approximation Eqs. 34-35 (GRAN_ERR_DOMAIN
 * when b >= 1, i.e. outside its validity), and tau_v,tracer/tau_c(0) by Eq. 33 for a given gamma. */
GRAN_EXTERN int gran_theory_tracer_gamma_approx(const gran_mixture *mix, int64_t tracer, double *gamma);
GRAN_EXTERN int gran_theory_tracer_tau_v_hat(const gran_mixture *mix, int64_t tracer, double gamma,
                                             double *tau_v_hat);
/* The DSMC outline: mean relative speeds <|g_ij|> = sqrt(8/pi (T_i/m_i + T_j/m_j)) (Eq. 60), M*M. */
GRAN_EXTERN int gran_theory_mean_relative_speed(const gran_mixture *mix, const double *T, double *g);
/* Collisions per unit volume and time between species i and j (the DSMC outline Eq. 57, cross-section
 * pi sigma_ij^2 g2_ij): rates[i*M+j] = n_i n_j pi sigma_ij^2 g2_ij <|g_ij|> / (1 + delta_ij). Symmetric;
 * each unordered pair once (the convention of gran_dsmc_collision_counts): total = sum over i <= j. */
GRAN_EXTERN int gran_theory_collision_rates(const gran_mixture *mix, const double *T, double *rates);
/* Expected collisions in volume V from 0 to t along the cooling from T0 (ODE + quadrature):
 * counts ntimes*M*M, [time][i][j], same convention as gran_theory_collision_rates. */
GRAN_EXTERN int gran_theory_collision_counts(const gran_mixture *mix, const double *T0, double volume,
                                             int64_t ntimes, const double *t, double rtol, double *counts);

/* ---- Aggregation and fragmentation kinetics (src/theory/aggregation.cpp) -------------------
 * Maxwellian pair (i, j), T_ij = (m_j T_i + m_i T_j)/(m_i + m_j): fraction of collisions that stick
 * (mu g^2/2 < E_agg) 1 - (1 + q) e^-q, q = E_agg/T_ij, and that shatter (mu g_n^2/2 > E_frag, not
 * sticking) (1 + L - w) e^-L, w = E_frag/T_ij, L = max(q, w). E_frag = INFINITY: none. */
GRAN_EXTERN int gran_theory_agg_fractions(double mi, double mj, double Ti, double Tj, double E_agg, double E_frag,
                                          double *f_stick, double *f_frag);
/* Temperature-dependent Smoluchowski equations (ballistic kernels) for sizes k = 1..M: species k-1
 * of mix is the k-mer (m_k = k m_1, checked), initial densities from mix, temperatures T0 (M).
 * Outputs n, T: ntimes*M; overflow (may be NULL): ntimes*3 = number, mass (monomers) and kinetic
 * energy per volume of clusters beyond M (truncation: they leave the system). T may be NULL. */
GRAN_EXTERN int gran_theory_aggregation(const gran_mixture *mix, const double *T0, double E_agg, double E_frag,
                                        double eps_f, int64_t ntimes, const double *t, double rtol, double *n,
                                        double *T, double *overflow);
/* Constant-kernel Smoluchowski equations (rate K n_i n_j/(1 + delta_ij)), sizes 1..kmax, same
 * truncation; n: ntimes*kmax, overflow ntimes*3 (may be NULL). */
GRAN_EXTERN int gran_theory_smoluchowski_constant(int64_t kmax, double K, const double *n0, int64_t ntimes,
                                                  const double *t, double rtol, double *n, double *overflow);

/* ---- DSMC engines (src/dsmc) -----------------------------------------------------------------
 * Event-driven DSMC of the homogeneous cooling state (Bodrova & Osinsky Sec. III) with two pair selectors
 * in one engine: the low-rank selector (rank-3 bound: segment trees over the speed-dependent
 * factors u^(r), alias tables over the constant factors v^(r)) and Bird's selector (one global
 * bound C_max, Eq. 49). Effects and observables that are off cost nothing.
 * ------------------------------------------------------------------------------------------- */
typedef struct gran_dsmc gran_dsmc; /* opaque */

/* LOWRANK / BIRD accept a candidate pair with |g| against the bound and then draw e from its
 * |g.e|-weighted law; the *_PAPER variants follow Eq. 40 / 48 literally (e uniform, accept with
 * |g.e|): the same collision statistics at half the acceptance (kept as the reference). */
enum gran_selector {
  GRAN_SELECTOR_LOWRANK = 0,      /* segment trees over the rank-3 factors of C_ik N_i N_k */
  GRAN_SELECTOR_BIRD = 1,         /* one global bound C_max (Eq. 49), pairs uniform among all N */
  GRAN_SELECTOR_LOWRANK_PAPER = 2,
  GRAN_SELECTOR_BIRD_PAPER = 3,
  GRAN_SELECTOR_CELL = 4          /* time-step/cell DSMC (the DSMC outline): positions, cells, dt (gran_dsmc_create_cell) */
};
enum gran_dsmc_observe {
  GRAN_OBSERVE_DISPLACEMENT = 1,     /* per-particle displacements (MSD); else not allocated */
  GRAN_OBSERVE_COLLISION_COUNTS = 2, /* collisions per species pair (M*M counters) */
  GRAN_OBSERVE_TRAJECTORIES = 4      /* tracer trajectories on a uniform grid (TAMSD) */
};

typedef struct gran_dsmc_options {
  int32_t selector;          /* gran_selector */
  int32_t observe;           /* gran_dsmc_observe flags */
  uint64_t seed;             /* RNG seed */
  double volume;             /* > 0: N_k = round(n_k V); ignored when counts are given */
  double t_start;            /* time of the initial state (default 0) */
  int64_t bound_refresh;     /* collisions between tightenings of the speed bounds (0: N) */
  int64_t traj_per_species;  /* tracer particles per species whose trajectories are recorded */
  double traj_dt;            /* sampling interval of the trajectories */
  int64_t traj_samples;      /* samples per trajectory (first at t_start) */
  /* speed classes: 1 = the low-rank selectors bin each large species' particles by
   * speed into classes with their own bounds (higher acceptance, same statistics); particles then
   * move between slots, and gran_dsmc_particles fills its view at each call (by creation order
   * with GRAN_OBSERVE_TRAJECTORIES, else grouped by species in no fixed order within a species).
   * 0 = off (one bound per species; the view is the live state). Ignored by Bird.
   * GRAN_SPEED_CLASSES_AUTO (-1, the default): decided at creation by a measured rule (docs/developers/dsmc-speed.md)
   * (README "Speed classes": on for GRAN_SELECTOR_LOWRANK where it was measured to pay, else off);
   * gran_dsmc_get_stats' class_moves > 0 after collisions shows it was on. */
  int32_t speed_classes;
  int32_t pad_classes_;
} gran_dsmc_options;

/* gran_dsmc_options.speed_classes */
enum gran_speed_classes {
  GRAN_SPEED_CLASSES_OFF = 0,
  GRAN_SPEED_CLASSES_ON = 1,
  GRAN_SPEED_CLASSES_AUTO = -1 /* default: on or off at creation (README, "Speed classes") */
};

typedef struct gran_dsmc_stats {
  int64_t nparticles;
  int64_t nspecies;
  int64_t collisions;   /* accepted collisions */
  int64_t trials;       /* candidate pairs drawn */
  int64_t bound_raises; /* speed bound raised after a collision */
  int64_t bound_tightenings;
  double volume;
  double time;
  double acceptance;    /* collisions / trials since the last tightening of the bounds */
  int64_t class_moves;    /* speed classes: particles moved between classes (0 without) */
  int64_t class_rebuilds; /* speed classes: re-sorts of a species forced by full classes */
} gran_dsmc_stats;

GRAN_EXTERN int gran_dsmc_options_default(gran_dsmc_options *opt);
/* counts: M particle numbers (NULL: N_k = round(n_k V) with V = opt->volume; given counts with
 * volume <= 0: V = sum of N_k over species with n_k > 0 / sum n_k); T0: M initial temperatures
 * (NULL: the HCS of the mixture with <T(0)> = 1; T_k = 1 for viscoelastic restitution, which has
 * no HCS). Maxwellian start, zero momentum of the gas. The mixture is copied (it may be destroyed
 * afterwards). A species with n_k = 0 and counts[k] > 0 is a tracer (Bodrova & Osinsky Sec. II F): it
 * collides with the gas at the physical rate, only the tracer's velocity changes, and tracers
 * never collide with each other. */
GRAN_EXTERN int gran_dsmc_create(const gran_mixture *mix, const int64_t *counts, const double *T0,
                                 const gran_dsmc_options *opt, gran_dsmc **sim);
GRAN_EXTERN int gran_dsmc_destroy(gran_dsmc **sim);
/* To t_end >= the current time (the same state however the interval is cut into calls). */
GRAN_EXTERN int gran_dsmc_advance(gran_dsmc *sim, double t_end);
/* The next ncollisions accepted collisions; the time becomes that of the last one. */
GRAN_EXTERN int gran_dsmc_advance_collisions(gran_dsmc *sim, int64_t ncollisions);
GRAN_EXTERN int gran_dsmc_time(const gran_dsmc *sim, double *t);
GRAN_EXTERN int gran_dsmc_get_stats(const gran_dsmc *sim, gran_dsmc_stats *stats);
/* Per-species observables are NaN for an empty species. T_k = m_k <|v - u|^2>/3 with u the
 * mean flow of the gas (all species but tracers; 0 up to rounding). MSD (Eq. 3 total; either output may be NULL) needs
 * GRAN_OBSERVE_DISPLACEMENT; collision counts (symmetric, [i*M+k]) GRAN_OBSERVE_COLLISION_COUNTS. */
GRAN_EXTERN int gran_dsmc_counts(const gran_dsmc *sim, int64_t *counts);           /* M */
GRAN_EXTERN int gran_dsmc_temperatures(const gran_dsmc *sim, double *T);           /* M */
GRAN_EXTERN int gran_dsmc_msd(const gran_dsmc *sim, double *msd, double *msd_total); /* M, 1 */
GRAN_EXTERN int gran_dsmc_collision_counts(const gran_dsmc *sim, int64_t *counts);  /* M*M */
GRAN_EXTERN int gran_dsmc_sonine_a2(const gran_dsmc *sim, double *a2);              /* M */
/* Kinetic energy now, at the start, dissipated so far (e_initial - e_dissipated == e_kin; a
 * tracer collision books minus the tracer's energy change); any output may be NULL. Momentum:
 * the total, tracers included (conserved without tracers; with them only the gas's part). */
GRAN_EXTERN int gran_dsmc_energy(const gran_dsmc *sim, double *e_kin, double *e_initial, double *e_dissipated);
GRAN_EXTERN int gran_dsmc_momentum(const gran_dsmc *sim, double p[3]);
/* Borrowed view of the particles (species stored contiguously; offsets has M+1 entries). With
 * displacements, R_j(t) = r_j + v_j (t - t_last_j) (Eq. 45; the engine keeps t_last_j = t_start). */
GRAN_EXTERN int gran_dsmc_particles(const gran_dsmc *sim, const gran_particles **p);
GRAN_EXTERN int gran_dsmc_species_offsets(const gran_dsmc *sim, int64_t *offsets);
/* Copy of species k's velocities (counts[k] x 3, the view's order without trajectories; v may be
 * NULL when counts[k] = 0): no memory beyond v, where the view with speed classes is a kept copy of
 * every particle. GRAN_ERR_STATE with aggregation (particles not grouped by species). */
GRAN_EXTERN int gran_dsmc_species_velocities(const gran_dsmc *sim, int64_t k, double *v);
/* Borrowed trajectories: ntraj tracers (the first traj_per_species particles of each species),
 * nsamples = traj_samples each, xyz layout [traj][sample][3], NaN for samples not reached yet;
 * needs GRAN_OBSERVE_TRAJECTORIES (which implies displacement tracking). Outputs may be NULL. */
GRAN_EXTERN int gran_dsmc_trajectories(const gran_dsmc *sim, int64_t *ntraj, int64_t *nsamples,
                                       const double **xyz, const int32_t **species);
/* Complete engine state into group `group` of HDF5 file `path` (created if missing; an existing
 * group of that name is replaced). Reading needs the mixture the engine was made with (checked);
 * the engine read back continues bit for bit. */
GRAN_EXTERN int gran_dsmc_checkpoint_write(const gran_dsmc *sim, const char *path, const char *group);
GRAN_EXTERN int gran_dsmc_checkpoint_read(const char *path, const char *group, const gran_mixture *mix,
                                          gran_dsmc **sim);

/* ---- Time-step/cell DSMC, aggregation, fragmentation, thermostat (src/dsmc/cell.cpp, agg.cpp) ---
 * The DSMC outline: particles in a cubic periodic box of side L = (F_N V)^(1/3) (V the volume
 * per simulated particle of the event selectors: rates are the same), nc^3 cells; every step dt
 * all particles stream (r += v dt), then in each cell N_p = F_N N_c^2 (sigma g)_max dt / (2 V_c)
 * candidate pairs (Eq. 8; the fractional part carried to the next step) are drawn with
 * replacement (j == l is no pair) and accepted with sigma g / (sigma g)_max (Eq. 7), where
 * (sigma g)_max = pi sigma_max,c^2 g2_max 2 max_c|v| is an exact bound of the cell, raised at once
 * (and N_p with it) when a collision speeds a particle up. Collisions as the event selectors.
 * Aggregation (e_agg > 0): species are cluster sizes (species k-1 = k-mer, m_k = k m_1,
 * sigma_k = sigma_1 k^(1/3); the mixture must say so); a pair with mu g^2/2 < e_agg merges, a pair
 * with normal impact energy mu g_n^2/2 > e_frag shatters into monomers (Eqs. 13-14, CM energy
 * eps_f^2 mu g^2/2), otherwise it bounces. White-noise thermostat (heat_rate > 0): every step
 * each velocity component of a particle of mass m gets a Gaussian kick of variance
 * heat_rate dt / m, minus the mass-weighted mean kick (momentum conserved). */
enum gran_cell_placement {
  GRAN_PLACE_RANDOM = 0,   /* merged clusters and fragments at random positions in the box (the DSMC outline) */
  GRAN_PLACE_COLLISION = 1 /* at the pair's centre of mass */
};
/* gran_dsmc_cell_options.streams: where a step's random numbers come from. */
enum gran_cell_streams {
  GRAN_CELL_STREAMS_SERIAL = 0, /* one stream, drawn cell after cell (the default; its bits are those of earlier releases) */
  GRAN_CELL_STREAMS_CELLS = 1   /* one stream per cell and step, keyed by (seed, step, cell), the particles of a
                                   cell in the order of their keys, the global sums exact: the run is the same, bit
                                   for bit, for any number of OpenMP threads (the cells are collided in parallel);
                                   the initial state is drawn cell by cell (docs/guide/cell-selector.md) */
};
typedef struct gran_dsmc_cell_options {
  int64_t cells;      /* cells per side of the box (>= 1; nc^3 cells) */
  double dt;          /* time step (> 0) */
  double fn;          /* F_N: real particles per simulated particle (> 0, default 1) */
  double e_agg;       /* aggregation: merge when mu g^2 / 2 < e_agg (0: off) */
  double e_frag;      /* fragmentation: shatter when mu g_n^2 / 2 > e_frag (INFINITY: off) */
  double eps_f;       /* fragments share eps_f^2 of the impact energy in the CM frame, [0, 1] */
  double heat_rate;   /* white-noise thermostat: heating dT/dt per particle (0: off) */
  double bath_density; /* molecular-gas bath: number density n_b of bath particles (0: off) */
  double bath_mass;   /* their mass m_b (> 0 when the bath is on) */
  double bath_T;      /* their temperature T_b (>= 0) */
  double bath_sigma;  /* their diameter sigma_b (>= 0; contact at (sigma_k + sigma_b)/2) */
  int32_t placement;  /* gran_cell_placement */
  int32_t frag_law;   /* gran_frag_law: the pieces of a breakup (default GRAN_FRAG_MONOMERS) */
  int32_t streams;    /* gran_cell_streams (default GRAN_CELL_STREAMS_SERIAL) */
} gran_dsmc_cell_options;

/* Defaults: 1 cell, dt 0 (must be set), F_N 1, no aggregation (e_agg 0), no fragmentation
 * (e_frag INFINITY), eps_f 1, no thermostat, no bath (bath_mass 1, bath_T 1, bath_sigma 1),
 * GRAN_PLACE_RANDOM. Bath: every particle collides elastically with Maxwellian bath particles
 * (n_b, m_b, T_b, sigma_b; the bath does not change) at the rate n_b pi sigma_kb^2 <|v - w|>,
 * sampled exactly in continuous time within each step; the energy exchanged is booked as heat. */
GRAN_EXTERN int gran_dsmc_cell_options_default(gran_dsmc_cell_options *cell);
/* As gran_dsmc_create with opt->selector = GRAN_SELECTOR_CELL (set by this call) and the cell
 * options; counts NULL: N_k = round(n_k V / F_N) with V = opt->volume the box volume. A dt whose
 * expected candidates per cell exceed N_c^2 (F_N (sigma g)_max dt / V_c > 2) is refused naming
 * 'dt' (also by gran_dsmc_advance, which then leaves the state unchanged). Tracers are refused.
 * gran_dsmc_advance runs whole steps up to t_end; gran_dsmc_advance_collisions stops after the
 * step in which the count is reached. Positions: gran_dsmc_particles (x, wrapped into [0, L)).
 * From 3e5 particles, without aggregation and trajectories, each species' particles are moved into
 * cell order every 8th step (inside the species' range): an index then names no fixed particle. */
GRAN_EXTERN int gran_dsmc_create_cell(const gran_mixture *mix, const int64_t *counts, const double *T0,
                                      const gran_dsmc_options *opt, const gran_dsmc_cell_options *cell,
                                      gran_dsmc **sim);
/* Steps done, box side L, and the largest F_N (sigma g)_max dt / V_c of the last step (any may be
 * NULL); GRAN_ERR_STATE for an engine of another selector. */
GRAN_EXTERN int gran_dsmc_cell_info(const gran_dsmc *sim, int64_t *steps, double *box, double *pmax);
/* Aggregating engines (e_agg > 0 or e_frag finite, any selector; else GRAN_ERR_STATE). The
 * per-species calls (counts, temperatures, sonine_a2) report the sizes 1..M of the mixture;
 * energy and momentum count every cluster; displacements, trajectories, per-pair collision counts
 * and species offsets do not exist (particles are unordered). Collisions = bounces + merges +
 * breakups; e_dissipated of gran_dsmc_energy = e_bounce + e_merge + e_break - e_heat. */
typedef struct gran_dsmc_cluster_stats {
  int64_t nclusters;  /* simulated clusters (particles) */
  int64_t mass;       /* total mass in monomers (conserved exactly) */
  int64_t largest;    /* largest size present */
  int64_t nsizes;     /* distinct sizes present */
  int64_t merges, breakups, bounces;
  double mean_size;   /* mass / nclusters */
  double e_bounce;    /* energy dissipated in bounces */
  double e_merge;     /* lost in merges (mu g^2 / 2 each) */
  double e_break;     /* lost in breakups ((1 - eps_f^2) mu g^2 / 2 each) */
  double e_heat;      /* added by the thermostat */
} gran_dsmc_cluster_stats;
GRAN_EXTERN int gran_dsmc_get_cluster_stats(const gran_dsmc *sim, gran_dsmc_cluster_stats *st);
/* Sparse n_k: the nsizes sizes present in increasing order into sizes/counts (cap entries at
 * least, else GRAN_ERR_RANGE; cap = 0: only *nsizes), T (may be NULL) their temperatures. */
GRAN_EXTERN int gran_dsmc_size_distribution(const gran_dsmc *sim, int64_t cap, int64_t *nsizes, int64_t *sizes,
                                            int64_t *counts, double *T);

/* ---- Aggregation and fragmentation in the event selectors (src/dsmc/agg_event.cpp) -----------
 * The same processes as the cell selector's (the rules are shared) in the low-rank and Bird event
 * selectors: species are cluster sizes (species k-1 of the mixture = the k-mer; sizes beyond the
 * mixture's appear on the fly), exact rates by rejection, particles unordered. gran_dsmc_create_agg
 * with e_agg = 0 and e_frag = INFINITY is gran_dsmc_create (no aggregation, no cost). The fragment
 * law (every selector): GRAN_FRAG_MONOMERS, the (k+j)-mer shatters into k+j monomers (the DSMC outline
 * Eqs. 13-14); GRAN_FRAG_BINARY, into two pieces of sizes a and k+j-a, a uniform in 1..k+j-1; in
 * both the momentum is exact and the pieces share eps_f^2 mu g^2/2 in the centre-of-mass frame. */
enum gran_frag_law {
  GRAN_FRAG_MONOMERS = 0, /* into monomers (the DSMC outline) */
  GRAN_FRAG_BINARY = 1    /* into two pieces of a uniform size */
};
typedef struct gran_dsmc_agg_options {
  double e_agg;       /* merge when mu g^2 / 2 < e_agg (0: off) */
  double e_frag;      /* shatter when mu g_n^2 / 2 > e_frag (INFINITY: off) */
  double eps_f;       /* the pieces share eps_f^2 of the impact energy in the CM frame, [0, 1] */
  int32_t frag_law;   /* gran_frag_law */
  int32_t pad_;
} gran_dsmc_agg_options;
/* Defaults: e_agg 0, e_frag INFINITY, eps_f 1, GRAN_FRAG_MONOMERS. */
GRAN_EXTERN int gran_dsmc_agg_options_default(gran_dsmc_agg_options *agg);
/* As gran_dsmc_create for opt->selector GRAN_SELECTOR_LOWRANK or GRAN_SELECTOR_BIRD (the paper
 * variants and speed_classes = 1: GRAN_ERR_UNSUPPORTED with aggregation; auto: off) with the processes of agg;
 * the mixture must be k-mers with one constant restitution (as the cell selector); no tracers,
 * displacements, trajectories or per-pair collision counts. gran_dsmc_get_cluster_stats,
 * gran_dsmc_size_distribution, checkpoints and every observable work on it. */
/* gran_theory_aggregation (theory block) with the fragment law: GRAN_FRAG_BINARY gives size s of a
 * breaking (i+j)-mer 2/(i+j-1) pieces on average, each with the share (i+j-s)/(i+j) of the
 * eps_f^2 mu g^2/2 kept in the CM frame; pieces above M go to the overflow reservoir. */
GRAN_EXTERN int gran_theory_aggregation_law(const gran_mixture *mix, const double *T0, double E_agg, double E_frag,
                                            double eps_f, int frag_law, int64_t ntimes, const double *t, double rtol,
                                            double *n, double *T, double *overflow);
GRAN_EXTERN int gran_dsmc_create_agg(const gran_mixture *mix, const int64_t *counts, const double *T0,
                                     const gran_dsmc_options *opt, const gran_dsmc_agg_options *agg,
                                     gran_dsmc **sim);

/* ---- Analysis (src/analysis) -----------------------------------------------------------------
 * Observables from trajectories and velocities. Trajectories: ntraj tracers sampled on a uniform
 * time grid, xyz layout [traj][sample][3] (as gran_dsmc_trajectories hands them out); lags are
 * counted in samples (multiply by the sampling interval). Velocities: 3n doubles, interleaved.
 * ------------------------------------------------------------------------------------------- */
/* TAMSD delta^2(L) = 1/(N-L) sum_{i=0}^{N-1-L} |R_{i+L} - R_i|^2, L = 0..nlag-1 (1 <= nlag <= N),
 * averaged over the trajectories; by FFT autocorrelation in O(N log N) per trajectory (FFTW). */
typedef struct gran_tamsd_plan gran_tamsd_plan; /* opaque: FFT plan and buffers for N samples */
GRAN_EXTERN int gran_tamsd_plan_create(int64_t nsamples, gran_tamsd_plan **plan);
GRAN_EXTERN int gran_tamsd_plan_destroy(gran_tamsd_plan **plan);
/* Executes many times; holds working buffers, so one plan per thread. */
GRAN_EXTERN int gran_tamsd_plan_execute(gran_tamsd_plan *plan, int64_t ntraj, const double *xyz,
                                        int64_t nlag, double *tamsd);
/* One shot: create, execute, destroy. */
GRAN_EXTERN int gran_tamsd(int64_t ntraj, int64_t nsamples, const double *xyz, int64_t nlag, double *tamsd);
/* The definition summed directly, O(N nlag) per trajectory: the reference for tests and benches. */
GRAN_EXTERN int gran_tamsd_direct(int64_t ntraj, int64_t nsamples, const double *xyz, int64_t nlag,
                                  double *tamsd);
/* Sonine a2 = (3/5) <E^2>/<E>^2 - 1 with E_i = m_i |v_i - u|^2, u the (mass-weighted) mean flow;
 * mass may be NULL (equal masses: (3/5)<c^4>/<c^2>^2 - 1). GRAN_ERR_DOMAIN if all v_i == u. */
GRAN_EXTERN int gran_sonine_a2(int64_t n, const double *v, const double *mass, double *a2);
/* Density of c = |v_i - u|/scale on [0, cmax), nbins bins: hist[k] = count_k / (n dc), so
 * sum hist*dc = fraction below cmax; nbeyond (may be NULL) = particles with c >= cmax. */
GRAN_EXTERN int gran_speed_histogram(int64_t n, const double *v, double scale, int64_t nbins, double cmax,
                                     double *hist, int64_t *nbeyond);

/* ---- Scenes, runs, output (src/io) -----------------------------------------------------------
 * Scene files (TOML; every key is listed in README.md with its C API equivalent), runs that write
 * HDF5, and checkpoints that continue a run bit for bit. A scene is validated completely when it
 * is loaded: a bad key fails with GRAN_ERR_PARSE and a message "FILE:LINE: key 'table.key': why".
 * Output and checkpoint files are written to PATH.tmp, fsync'ed and renamed: a killed run never
 * leaves a half-written file under the final name.
 * ------------------------------------------------------------------------------------------- */
typedef struct gran_scene gran_scene; /* opaque; changed only by gran_scene_set and gran_scene_set_replicas */

GRAN_EXTERN int gran_scene_load(const char *path, gran_scene **scene);
/* The same from text in memory; `name` (may be NULL) is the file name used in messages. */
GRAN_EXTERN int gran_scene_parse(const char *text, const char *name, gran_scene **scene);
GRAN_EXTERN int gran_scene_destroy(gran_scene **scene);
/* Override one key of a loaded scene, as if its file said `key = value`: key "table.key"
 * ("engine.seed", "output.path", "observables.msd"; a top-level key alone: "title"), value one line
 * of TOML ("7", "\"x.h5\"", "[1.0, 2.0]", "false"). The key's line in the scene text is replaced
 * (or the line is added to its table) and the whole scene is validated again: an unknown key, a
 * wrong type or a value out of bounds fails (GRAN_ERR_PARSE, the message names the key) and leaves
 * the scene as it was. gran_scene_text returns the edited text; a checkpoint stores it, so a resume
 * continues the overridden run. Replicas set by gran_scene_set_replicas are kept. */
GRAN_EXTERN int gran_scene_set(gran_scene *scene, const char *key, const char *value);
/* Borrowed, NUL-terminated, valid while the scene lives: the scene text / the output path. */
GRAN_EXTERN int gran_scene_text(const gran_scene *scene, const char **text);
GRAN_EXTERN int gran_scene_output_path(const gran_scene *scene, const char **path);
/* Sizes: species, output times, TAMSD lags (0 when off); start and end time. Any may be NULL. */
GRAN_EXTERN int gran_scene_sizes(const gran_scene *scene, int64_t *nspecies, int64_t *ntimes,
                                 int64_t *nlags, double *t_start, double *t_end);
GRAN_EXTERN int gran_scene_times(const gran_scene *scene, double *times); /* ntimes, absolute */
GRAN_EXTERN int gran_scene_lags(const gran_scene *scene, double *lags);   /* nlags */
/* A new mixture (caller destroys it) with the scene's species, restitution and g2. */
GRAN_EXTERN int gran_scene_mixture(const gran_scene *scene, gran_mixture **mix);
/* Initial temperatures T0 (nspecies) as the scene's [initial] asks, and tau0 = 2/xi_1(T0)
 * (Eq. 21: the HCS relaxation time when the scene starts in the HCS; tau0 may be NULL). */
GRAN_EXTERN int gran_scene_initial_temperatures(const gran_scene *scene, const gran_mixture *mix,
                                                double *T0, double *tau0);
/* The engine options of [engine] / [observables] and the particle numbers: counts (nspecies) is
 * filled with N_k when the scene lists them (*have_counts = 1), else with round(n_k V) and
 * opt->volume = V (*have_counts = 0). counts and have_counts may be NULL. */
GRAN_EXTERN int gran_scene_dsmc_options(const gran_scene *scene, gran_dsmc_options *opt, int64_t *counts,
                                        int *have_counts);
/* A new engine exactly as `granary run` creates it (counts, seed, selector, observables). */
GRAN_EXTERN int gran_scene_dsmc(const gran_scene *scene, const gran_mixture *mix, gran_dsmc **sim);
/* The [cell] table of a scene (engine selector = "cell"): cells, dt, fn, e_agg, e_frag, eps_f,
 * heat_rate, bath_density, bath_mass, bath_T, bath_sigma, placement; defaults of gran_dsmc_cell_options_default for keys not given. */
GRAN_EXTERN int gran_scene_dsmc_cell_options(const gran_scene *scene, gran_dsmc_cell_options *cell);
/* The scene's aggregation and fragmentation ([aggregation] table, or the [cell] table's keys of the
 * cell selector), for any selector; defaults of gran_dsmc_agg_options_default when off. */
GRAN_EXTERN int gran_scene_dsmc_agg_options(const gran_scene *scene, gran_dsmc_agg_options *agg);

/* What gran_run_progress.collisions counts (work_unit): DSMC accepted collisions, or GSRD
 * particle-steps (particles x collision steps). */
#define GRAN_WORK_COLLISIONS 0
#define GRAN_WORK_PARTICLE_STEPS 1

/* Progress of a run, handed to the optional callback after every output time. */
typedef struct gran_run_progress {
  double time;           /* simulated time reached */
  double t_start, t_end;
  double fraction;       /* estimated share of the work done (0..1): collisions from the kinetic
                          * theory's collision rate to the time reached, over those to t_end */
  double wall_seconds;   /* since this process started the run */
  double collisions_per_second; /* in this process */
  double eta_seconds;    /* wall time per unit of that work so far x the work left; < 0 when unknown */
  int64_t collisions;    /* total work events, including those before a resume (work_unit) */
  int64_t output_index;  /* output times recorded so far */
  int64_t noutputs;
  int64_t checkpoints;   /* written in this process */
  double temperature;    /* the gas temperature at `time` in replica 0 (DSMC: 2 E_kin / (3 N), the
                          * number-weighted mean of the T_k; GSRD: gran_srd_obs.temperature); NaN
                          * before the first output time */
  int32_t work_unit;     /* GRAN_WORK_COLLISIONS or GRAN_WORK_PARTICLE_STEPS: what `collisions`
                          * and `collisions_per_second` count */
  int32_t pad_;
} gran_run_progress;
/* Return 0 to continue; anything else stops the run there: a checkpoint is written (when the run
 * has a checkpoint path) and the run returns GRAN_SUCCESS with result->finished = 0. */
typedef int (*gran_progress_fn)(const gran_run_progress *progress, void *params);

typedef struct gran_run_control {
  int64_t stop_after_checkpoints; /* > 0: stop (finished = 0) right after writing this many */
  gran_progress_fn progress;      /* may be NULL */
  void *progress_params;
} gran_run_control;

typedef struct gran_run_result {
  int32_t finished;     /* 1: output written; 0: stopped after a checkpoint (resume to go on) */
  int32_t pad_;
  int64_t checkpoints;  /* checkpoints written in this call */
  int64_t collisions;   /* accepted collisions at the end of this call */
  double time;          /* simulated time reached */
  double wall_seconds;  /* spent in this call */
} gran_run_result;

/* Run a scene: output to `output` (NULL: the scene's [output] path), checkpoints to `checkpoint`
 * (NULL: the scene's; its default OUTPUT.ckpt follows `output`; "" : none). Both paths are checked
 * for writability before any work; output, checkpoint and scene file must be different files
 * (compared by device and inode / real path; GRAN_ERR_ARG). A run stopped early writes the output
 * times recorded so far to OUTPUT.partial.h5 (root attribute complete = 0). ctl and result may be NULL. */
GRAN_EXTERN int gran_scene_run(const gran_scene *scene, const char *output, const char *checkpoint,
                               const gran_run_control *ctl, gran_run_result *result);
/* Continue a run from its checkpoint file (scene text, engine and recorded observables are all
 * inside); output NULL: the path the run was started with. Same result as an uninterrupted run,
 * bit for bit. New checkpoints go to the same checkpoint path. */
GRAN_EXTERN int gran_scene_resume(const char *checkpoint, const char *output, const gran_run_control *ctl,
                                  gran_run_result *result);

/* ---- replicas and threads (src/io/run.cpp) ---------------------------------------------------
 * A run of R replicas is R independent runs of one scene: replica 0 uses the scene's seed (R = 1 is
 * the run without replicas, bit for bit), replica r >= 1 the first number of RNG stream r of the
 * seed (gran_rng_stream). Replicas run in OpenMP threads and are reduced in replica order: the
 * output (X = mean, X_se = its standard error; event counts summed) is the same for any thread
 * count. A stopped run's checkpoint holds every replica; resume restores their number. */
GRAN_EXTERN int gran_scene_set_replicas(gran_scene *scene, int64_t replicas, int32_t keep_replicas);
GRAN_EXTERN int gran_scene_replicas(const gran_scene *scene, int64_t *replicas, int32_t *keep_replicas);
/* Threads for the replicas of a run, process-wide; 0 (default): OMP_NUM_THREADS or all cores. The
 * cell DSMC with GRAN_CELL_STREAMS_CELLS steps its cells on this many threads too (one inside a
 * parallel region of the replicas); its results do not depend on the number. */
GRAN_EXTERN int gran_set_threads(int32_t nthreads);
GRAN_EXTERN int gran_get_threads(int32_t *nthreads);
/* ---------------------------------------------------------------------------------------------
 * GSRD: granular stochastic rotation dynamics (Zantop), CPU engine (src/srd/).
 * Units: particle mass m = 1, k_B = 1. Point particles in a box of cells[0] x cells[1] (x cells[2])
 * cells of size a; periodic except on wall_axis; Lees-Edwards shear (flow x, gradient y) when
 * shear_rate != 0. Every effect is off unless its option is set, and then costs nothing.
 * ------------------------------------------------------------------------------------------- */
typedef struct gran_srd gran_srd; /* opaque */

typedef struct gran_srd_options {
  int32_t dim;          /* 2 or 3 */
  int32_t wall_axis;    /* -1: periodic everywhere; 0..dim-1: walls at 0 and cells[wall_axis]*a */
  int32_t wall_rule;    /* 1: no-slip (bounce-back + virtual particles), 2: slip (specular) */
  int32_t thermostat;   /* 1: cell-level Maxwell-Boltzmann thermostat at T0; 2: global rescaling of
                           the velocities relative to the cell means to T0 (viscosity runs) */
  int64_t cells[3];     /* cells per axis (cells[2] ignored in 2-D) */
  double a;             /* cell size (> 0) */
  double n0;            /* mean particles per cell (> 0); N = round(n0 * cells) */
  double dt;            /* time step (> 0) */
  double alpha_deg;     /* rotation angle in degrees, (0, 180] */
  double eps;           /* coefficient of restitution, [0, 1]; 1 = standard SRD */
  double sigma;         /* particle diameter in Eq. 2.1 */
  double T0;            /* initial (and thermostat) temperature (> 0) */
  double shear_rate;    /* Lees-Edwards shear rate (0: off); flow x, gradient y */
  double accel[3];      /* uniform acceleration: gravity + body force per mass (0: off) */
  double vib_amp;       /* vibrating lower wall: velocity amplitude * sin(omega t) = vib_amp omega cos */
  double vib_omega;     /* angular frequency of the lower wall (0: at rest) */
  double wall_T;        /* temperature of the virtual particles in cut cells (0: T0) */
  uint64_t seed;        /* RNG seed (streams: 0 grid shift, c + 1 cell c, long jump: init) */
  int32_t sort_every;   /* sort particles by cell every this many steps (0: never) */
  int32_t threads;      /* OpenMP threads (0: all); results do not depend on it */
  /* ---- device (CUDA backend, src/srd/device_cuda.cpp) ---- */
  int32_t device;       /* GRAN_SRD_DEVICE_*: 0 CPU engine (default), 1 CUDA, 2 auto, 3 host reference */
  int32_t precision;    /* particle storage on the device: 0 double, 1 float (CPU engine: double) */
  /* ---- creation of the initial particles ---- */
  int32_t creation;     /* GRAN_SRD_CREATE_*: 0 serial (one stream draws every particle; default), 1 by
                           cells (a multinomial split of N over the cells, then each cell's particles
                           from its own generator: the same particles however the cells are split; the
                           CPU engine then steps as the decomposable engine: particle keys and exact global
                           sums, results independent of the split into bricks, docs/guide/gsrd.md) */
  int32_t pad_;
} gran_srd_options;
/* gran_srd_options.creation */
enum { GRAN_SRD_CREATE_SERIAL = 0, GRAN_SRD_CREATE_CELLS = 1 };

typedef struct gran_srd_obs {
  double time;          /* simulated time */
  int64_t steps;        /* steps done */
  int64_t n;            /* particles */
  double temperature;   /* sum |v - <v>|^2 / (d N) (global mean removed) */
  double theta_cells;   /* mean thermal temperature over particles of the unshifted cells */
  double energy;        /* sum |v|^2 / 2 */
  double e_initial;     /* energy at creation */
  double e_collisions;  /* energy change in collisions: dissipation, thermostat, virtual particles */
  double e_external;    /* work of walls, Lees-Edwards boundary, forces (incl. potential) */
  double ledger_error;  /* (e_initial + e_collisions + e_external - energy - potential) / e_initial */
  double momentum[3];   /* sum v */
  double e_kin;         /* convective kinetic energy, Eq. 3.1: (1/N) sum_cells n V^2 */
  double mach;          /* global Mach number sqrt(e_kin / theta_cells) */
  double sigma_rho;     /* standard deviation of the cell number density (unshifted cells) */
  double a2;            /* Sonine coefficient of v relative to the cell means */
  int64_t clamped;      /* eps_eff clamps since the last call (a warning is recorded) */
  double dt_max;        /* largest dt that would have avoided them (inf: none) */
  double stress_xy;     /* Lees-Edwards: -(momentum flux), kinetic + collisional, since reset */
  double stress_kin;    /* its kinetic (streaming) part */
} gran_srd_obs;

GRAN_EXTERN int gran_srd_options_default(gran_srd_options *opt);
GRAN_EXTERN int gran_srd_create(const gran_srd_options *opt, gran_srd **srd);
GRAN_EXTERN int gran_srd_destroy(gran_srd **srd); /* NULL-safe, NULLs the handle */
GRAN_EXTERN int gran_srd_advance(gran_srd *srd, int64_t steps);
GRAN_EXTERN int gran_srd_observe(gran_srd *srd, gran_srd_obs *obs);
/* Reset the Lees-Edwards stress accumulators (start of a measurement window). */
GRAN_EXTERN int gran_srd_stress_reset(gran_srd *srd);
/* Borrowed pointers to the particle arrays (length *n, valid until the next advance/destroy;
 * z and vz are NULL in 2-D). The caller may modify velocities between steps. */
GRAN_EXTERN int gran_srd_particles(gran_srd *srd, int64_t *n, double **x, double **y, double **z,
                                   double **vx, double **vy, double **vz);
/* Density structure factor S(k) of the unshifted cell counts (FFTW r2c), radially averaged in
 * nbins shells of width 2 pi / (L a), k = 0 removed; k[i], s[i] and the mode count per shell. */
GRAN_EXTERN int gran_srd_structure_factor(gran_srd *srd, int64_t nbins, double *k, double *s, int64_t *count);
/* The complete engine state (options, counters, energies, particles, cell reference velocities,
 * every RNG state) as group `group` of the HDF5 file `path`, format "granary-srd-state 1", named
 * fields (docs/developers/state-format.md); the file is created if missing, an existing group of
 * that name replaced, the file written to PATH.tmp with a checksum header, fsync'ed and renamed
 * (the same shape as gran_dsmc_checkpoint_write). Read validates every value and refuses
 * (GRAN_ERR_IO, naming the field) what no run writes; files of the older binary format (GSRDCKP2)
 * are refused. Resume is bit for bit with any thread count. */
GRAN_EXTERN int gran_srd_checkpoint_write(const gran_srd *srd, const char *path, const char *group);
GRAN_EXTERN int gran_srd_checkpoint_read(const char *path, const char *group, gran_srd **srd);
/* ---- GSRD velocity profile (shear and Poiseuille flow analysis, run driver) ----
 * Instantaneous mean of velocity component `component` (0..dim-1) of the particles in nbins equal
 * slabs along `axis` (0..dim-1) spanning [0, cells[axis] a): mean[b] (0 where count[b] = 0) and
 * count[b]. Time averages: sum mean[b] * count[b] and count[b] over calls. */
GRAN_EXTERN int gran_srd_velocity_profile(const gran_srd *srd, int32_t axis, int32_t component, int64_t nbins,
                                          double *mean, int64_t *count);

/* ---- GSRD cell fields (src/srd/fields.cpp; snapshots of `granary run`) ----------------------
 * Fields of the unshifted lattice, cells[0] x cells[1] (x cells[2]) cells, cell (i, j, k) at index
 * i + cells[0] (j + cells[1] k): particles per cell (count), mean velocity [cell][3] (third
 * component 0 in 2-D) and temperature sum |v - V|^2 / (d n); empty cells give 0. Any output may
 * be NULL. Sum of count = N; sum of count x velocity = total momentum. */
GRAN_EXTERN int gran_srd_fields(gran_srd *srd, double *count, double *velocity, double *temperature);

/* ---- GSRD devices (CUDA backend; src/srd/device_cuda.cpp, cuda/) ------------------------------
 * options.device: CPU = the CPU engine; CUDA = the GPU (GRAN_ERR_UNSUPPORTED, naming why, when the
 * backend was not compiled or no GPU is visible); AUTO = the GPU when one is visible, else the CPU
 * and a warning; REFERENCE = the GPU algorithm run on the host, serially (the test oracle of the
 * CUDA backend). On a device the particles live there: observe, particles, structure_factor and
 * checkpoint_write copy them back; velocities changed through gran_srd_particles are copied to the
 * device at the next advance. Checkpoints are the same file on every device; checkpoint_read
 * resumes on the device its options name (CUDA without a GPU: the CPU, with a warning). */
enum { GRAN_SRD_DEVICE_CPU = 0, GRAN_SRD_DEVICE_CUDA = 1, GRAN_SRD_DEVICE_AUTO = 2, GRAN_SRD_DEVICE_REFERENCE = 3 };
/* Move a run to another device (GRAN_SRD_DEVICE_*), state and RNG streams included. */
GRAN_EXTERN int gran_srd_set_device(gran_srd *srd, int32_t device);
/* The device the run is on now (CPU, CUDA or REFERENCE; AUTO resolved). */
GRAN_EXTERN int gran_srd_get_device(const gran_srd *srd, int32_t *device);

#endif /* GRANARY_H */
