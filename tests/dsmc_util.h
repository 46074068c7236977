/* dsmc_util.h - helpers shared by the DSMC tests (t5xx): sanitizer detection, small mixtures,
 * batch-means standard errors. */
#ifndef GRANARY_DSMC_UTIL_H
#define GRANARY_DSMC_UTIL_H

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

#endif
