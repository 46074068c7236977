/* dsmc_util.h - helpers shared by the DSMC tests (t5xx): sanitizer detection, small mixtures,
 * batch-means standard errors, checkpoint files and the bit-for-bit comparison of two engines. */
#ifndef GRANARY_DSMC_UTIL_H
#define GRANARY_DSMC_UTIL_H

#include <unistd.h>

#include "granary_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* 1 under AddressSanitizer (gcc defines __SANITIZE_ADDRESS__, clang has __has_feature): the
 * statistical tests then run fewer collisions and widen nothing but the sample size. */
#if defined(__SANITIZE_ADDRESS__)
#define DSMC_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define DSMC_ASAN 1
#endif
#endif
#ifndef DSMC_ASAN
#define DSMC_ASAN 0
#endif

/* GRAN_TEST_SCALE=s (> 0) multiplies the work of the statistical tests (default 1; 0.1 under ASan). */
static inline double dsmc_scale(void) {
  const char *s = getenv("GRAN_TEST_SCALE");
  double x = s ? atof(s) : 0.0;
  if (x > 0) return x;
  return DSMC_ASAN ? 0.1 : 1.0;
}

/* One species, m = sigma = 1, density n, constant eps. */
static inline gran_mixture *dsmc_mono(double n, double eps) {
  gran_mixture *mix = NULL;
  double m = 1, s = 1;
  GRAN_ASSERT_OK(gran_mixture_create(1, &m, &s, &n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

static inline gran_dsmc_options dsmc_opts(int selector, uint64_t seed, double volume, int observe) {
  gran_dsmc_options o;
  GRAN_ASSERT_OK(gran_dsmc_options_default(&o));
  o.selector = selector;
  o.seed = seed;
  o.volume = volume;
  o.observe = observe;
  return o;
}

/* mean and standard error of the mean of x[0..n-1] */
static inline void dsmc_mean_se(const double *x, int n, double *mean, double *se) {
  double s = 0, s2 = 0;
  for (int i = 0; i < n; i++) s += x[i];
  const double m = s / n;
  for (int i = 0; i < n; i++) s2 += (x[i] - m) * (x[i] - m);
  *mean = m;
  *se = n > 1 ? sqrt(s2 / (n - 1) / n) : INFINITY;
}

static inline int64_t dsmc_collisions(const gran_dsmc *sim) {
  gran_dsmc_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
  return st.collisions;
}

/* temperature of the first species */
static inline double dsmc_T1(const gran_dsmc *sim) {
  gran_dsmc_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
  double *T = (double *)malloc(sizeof(double) * (size_t)st.nspecies);
  GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
  const double t1 = T[0];
  free(T);
  return t1;
}

/* ---- checkpoints ---- */
/* The path /tmp/granary-NAME-PID.h5 in `buf` (n bytes), with no file there yet. */
static inline const char *dsmc_ckpt_path(char *buf, size_t n, const char *name) {
  snprintf(buf, n, "/tmp/granary-%s-%ld.h5", name, (long)getpid());
  remove(buf);
  return buf;
}

/* Two engines hold the same state, bit for bit, in everything a resume must reproduce: the
 * velocities (and positions with `cell`), displacements and their clocks where `observe` keeps
 * them, the statistics, the energy ledger, the collision counts of the M x M pairs and the
 * trajectories where `observe` records them; with `cell` also the closed ledger and the cell
 * geometry. */
static inline void dsmc_assert_same_state(const gran_dsmc *a, const gran_dsmc *b, int observe, int64_t M, int cell) {
  const gran_particles *pa, *pb;
  GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
  GRAN_ASSERT_OK(gran_dsmc_particles(b, &pb));
  assert_int_equal(pa->n, pb->n);
  assert_memory_equal(pa->v, pb->v, sizeof(double) * 3 * (size_t)pa->n);
  if (cell) assert_memory_equal(pa->x, pb->x, sizeof(double) * 3 * (size_t)pa->n);
  if (observe & (GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_TRAJECTORIES)) {
    assert_memory_equal(pa->r, pb->r, sizeof(double) * 3 * (size_t)pa->n);
    if (pa->t_last || pb->t_last) {
      assert_true(pa->t_last && pb->t_last);
      assert_memory_equal(pa->t_last, pb->t_last, sizeof(double) * (size_t)pa->n);
    }
  }
  gran_dsmc_stats sa, sb;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(a, &sa));
  GRAN_ASSERT_OK(gran_dsmc_get_stats(b, &sb));
  assert_memory_equal(&sa, &sb, sizeof sa);
  double ea[3], eb[3];
  GRAN_ASSERT_OK(gran_dsmc_energy(a, &ea[0], &ea[1], &ea[2]));
  GRAN_ASSERT_OK(gran_dsmc_energy(b, &eb[0], &eb[1], &eb[2]));
  assert_memory_equal(ea, eb, sizeof ea);
  if (cell) {
    GRAN_ASSERT_REL(ea[0], ea[1] - ea[2], 1e-12); /* the ledger closes */
    int64_t na, nb;
    double La, Lb, qa, qb;
    GRAN_ASSERT_OK(gran_dsmc_cell_info(a, &na, &La, &qa));
    GRAN_ASSERT_OK(gran_dsmc_cell_info(b, &nb, &Lb, &qb));
    assert_int_equal(na, nb);
    assert_true(La == Lb && qa == qb);
  }
  if (observe & GRAN_OBSERVE_COLLISION_COUNTS) {
    int64_t *ca = (int64_t *)calloc((size_t)(M * M), sizeof *ca), *cb = (int64_t *)calloc((size_t)(M * M), sizeof *cb);
    GRAN_ASSERT_OK(gran_dsmc_collision_counts(a, ca));
    GRAN_ASSERT_OK(gran_dsmc_collision_counts(b, cb));
    assert_memory_equal(ca, cb, sizeof *ca * (size_t)(M * M));
    free(ca);
    free(cb);
  }
  if (observe & GRAN_OBSERVE_TRAJECTORIES) {
    int64_t na, nb, sa_, sb_;
    const double *xa, *xb;
    GRAN_ASSERT_OK(gran_dsmc_trajectories(a, &na, &sa_, &xa, NULL));
    GRAN_ASSERT_OK(gran_dsmc_trajectories(b, &nb, &sb_, &xb, NULL));
    assert_int_equal(na, nb);
    assert_int_equal(sa_, sb_);
    assert_memory_equal(xa, xb, sizeof(double) * 3 * (size_t)(na * sa_));
  }
}

#endif
