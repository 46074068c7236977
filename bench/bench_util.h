/* bench_util.h - timing helpers shared by the benchmarks (monotonic clock, peak RSS). */
#ifndef GRANARY_BENCH_UTIL_H
#define GRANARY_BENCH_UTIL_H
#define _POSIX_C_SOURCE 200809L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/resource.h>

#include "granary.h"

static inline double bench_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU seconds of this process (user time): the steadier clock on a shared machine */
static inline double bench_cpu_now(void) {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec;
}

/* peak resident set size of this process in bytes */
static inline double bench_peak_rss(void) {
  struct rusage ru;
  getrusage(RUSAGE_SELF, &ru);
  return 1024.0 * (double)ru.ru_maxrss;
}

/* BENCH_QUICK=1 in the environment shrinks the problem sizes (for smoke runs). */
static inline int bench_quick(void) {
  const char *q = getenv("BENCH_QUICK");
  return q && q[0] == '1';
}

#define BENCH_CHECK(call)                                                                     \
  do {                                                                                        \
    int bench_ierr_ = (call);                                                                 \
    if (bench_ierr_) {                                                                        \
      fprintf(stderr, "%s failed: %s\n", #call, gran_last_error_message());                   \
      exit(1);                                                                                \
    }                                                                                         \
  } while (0)

#endif
