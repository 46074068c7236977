/* granary_test.h - CMocka glue shared by the C tests.
 * GRAN_ASSERT_OK(call)            the call returns GRAN_SUCCESS (else prints the library message)
 * GRAN_ASSERT_ERR(call, code)     the call returns exactly `code` and leaves a non-empty message
 * GRAN_ASSERT_REL(a, b, rtol)     |a - b| <= rtol * |b| (b == 0: |a| <= rtol), GSL gsl_test_rel style
 * GRAN_ASSERT_ABS(a, b, atol)     |a - b| <= atol
 * GRAN_ASSERT_SIGMA(x, mean, se, k)  |x - mean| <= k * se: statistical tests state k (standard errors)
 * gran_test_source_dir()          the repository root (env GRAN_SOURCE_DIR, default ".") */
#ifndef GRANARY_TEST_H
#define GRANARY_TEST_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "granary.h"

#define GRAN_ASSERT_OK(call)                                                                    \
  do {                                                                                          \
    int gran_t_ierr_ = (call);                                                                  \
    if (gran_t_ierr_ != GRAN_SUCCESS)                                                           \
      fail_msg("%s returned %d (%s): %s", #call, gran_t_ierr_, gran_strerror(gran_t_ierr_),     \
               gran_last_error_message());                                                      \
  } while (0)

#define GRAN_ASSERT_ERR(call, code)                                                             \
  do {                                                                                          \
    gran_clear_error();                                                                         \
    int gran_t_ierr_ = (call);                                                                  \
    if (gran_t_ierr_ != (code))                                                                 \
      fail_msg("%s returned %d (%s), expected %s", #call, gran_t_ierr_,                         \
               gran_strerror(gran_t_ierr_), gran_strerror(code));                               \
    if (gran_last_error_message()[0] == '\0') fail_msg("%s left no error message", #call);      \
  } while (0)

static inline int gran_test_rel_ok(double a, double b, double rtol) {
  if (isnan(a) || isnan(b)) return 0;
  if (b == 0.0) return fabs(a) <= rtol;
  return fabs(a - b) <= rtol * fabs(b);
}

#define GRAN_ASSERT_REL(a, b, rtol)                                                             \
  do {                                                                                          \
    double gran_a_ = (a), gran_b_ = (b);                                                        \
    if (!gran_test_rel_ok(gran_a_, gran_b_, (rtol)))                                            \
      fail_msg("%s = %.17g vs %s = %.17g: relative error %.3g > %.3g", #a, gran_a_, #b, gran_b_,\
               gran_b_ != 0 ? fabs(gran_a_ - gran_b_) / fabs(gran_b_) : fabs(gran_a_),        \
               (double)(rtol));                                                                 \
  } while (0)

#define GRAN_ASSERT_ABS(a, b, atol)                                                             \
  do {                                                                                          \
    double gran_a_ = (a), gran_b_ = (b);                                                        \
    if (!(fabs(gran_a_ - gran_b_) <= (atol)))                                                   \
      fail_msg("%s = %.17g vs %s = %.17g: |difference| %.3g > %.3g", #a, gran_a_, #b, gran_b_,  \
               fabs(gran_a_ - gran_b_), (double)(atol));                                        \
  } while (0)

#define GRAN_ASSERT_SIGMA(x, mean, se, k)                                                       \
  do {                                                                                          \
    double gran_x_ = (x), gran_m_ = (mean), gran_s_ = (se);                                     \
    if (!(fabs(gran_x_ - gran_m_) <= (k) * gran_s_))                                            \
      fail_msg("%s = %.10g vs %.10g: %.2f standard errors (se %.3g) > %g", #x, gran_x_,         \
               gran_m_, fabs(gran_x_ - gran_m_) / gran_s_, gran_s_, (double)(k));               \
  } while (0)

static inline const char *gran_test_source_dir(void) {
  const char *d = getenv("GRAN_SOURCE_DIR");
  return d ? d : ".";
}

#endif
