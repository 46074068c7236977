/* t403-hcs-large.c - HCS of highly polydisperse mixtures (Bodrova & Osinsky Sec. II D, Fig. 4):
 * n_k = n_1 k^-theta, m_k = k, sigma_k = k^(1/3), M up to 1e4 (structured Newton with ACA). */
#define _POSIX_C_SOURCE 200809L
#include "granary_test.h"

#include <time.h>

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Solve, then verify the defining equations independently through gran_theory_cooling_rates:
 * max_k |xi_k tau0/2 - 1| <= tol and the number-weighted mean temperature = 1 (1e-13). */
static void check_powerlaw(int64_t M, double theta, double eps, double tol) {
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, theta, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  double *T = malloc(sizeof(double) * (size_t)M), *xi = malloc(sizeof(double) * (size_t)M);
  double *n = malloc(sizeof(double) * (size_t)M);
  double tau0 = 0;
  const double t0 = now();
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T, &tau0));
  const double el = now() - t0;
  GRAN_ASSERT_OK(gran_theory_cooling_rates(mix, T, xi));
  GRAN_ASSERT_OK(gran_mixture_get(mix, NULL, NULL, n));
  double d = 0, num = 0, den = 0;
  for (int64_t k = 0; k < M; k++) {
    assert_true(isfinite(T[k]) && T[k] > 0);
    d = fmax(d, fabs(0.5 * xi[k] * tau0 - 1.0));
    num += n[k] * T[k];
    den += n[k];
  }
  print_message("M = %" PRId64 ", theta = %g, eps = %g: HCS in %.3f s, tau0 = %.10g, T_1 = %.6g, T_M = %.6g, "
                "defect %.2e\n", M, theta, eps, el, tau0, T[0], T[M - 1], d);
  if (!(d <= tol)) fail_msg("defect %g > %g", d, tol);
  GRAN_ASSERT_REL(num / den, 1.0, 1e-13);
  /* heavier species are hotter in the HCS of these mixtures (Sec. II D) */
  assert_true(T[M - 1] > T[0]);
  free(T);
  free(xi);
  free(n);
  gran_mixture_destroy(&mix);
}

/* M = 1e4 (the brief's hard case). Cooling rates are sums of 1e4 terms in which heating by hotter
 * heavy species and cooling nearly cancel for the light species: the defect floor is ~1e-12; 1e-10. */
static void test_theta2(void **state) {
  (void)state;
  check_powerlaw(10000, 2.0, 0.5, 1e-10);
}
static void test_theta3(void **state) {
  (void)state;
  check_powerlaw(10000, 3.0, 0.5, 1e-10);
}
static void test_theta4(void **state) {
  (void)state;
  check_powerlaw(10000, 4.0, 0.5, 1e-10);
}

/* Around the dense/structured switch (M = 64/65) and other restitution values. */
static void test_switch_and_eps(void **state) {
  (void)state;
  check_powerlaw(64, 2.0, 0.5, 1e-12);
  check_powerlaw(65, 2.0, 0.5, 1e-12);
  check_powerlaw(1000, 3.0, 0.0, 1e-11);
  check_powerlaw(1000, 3.0, 0.9, 1e-11);
}

/* Structured path with matrices (no coarse start, general pair loop) and tracer species:
 * M = 400 with every 7th species a tracer, eps_ij = 0.5 + 0.4 |i - j|/M. */
static void test_structured_general(void **state) {
  (void)state;
  enum { M = 400 };
  double *m = malloc(sizeof(double) * M), *n = malloc(sizeof(double) * M), *E = malloc(sizeof(double) * M * M);
  for (int k = 0; k < M; k++) {
    m[k] = k + 1.0;
    n[k] = (k % 7 == 3) ? 0.0 : 0.1 * pow(k + 1.0, -2.5);
  }
  for (int i = 0; i < M; i++)
    for (int k = 0; k < M; k++) E[i * M + k] = 0.5 + 0.4 * fabs((double)(i - k)) / M;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(mix, E));
  double T[M], xi[M], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, T, &tau0));
  GRAN_ASSERT_OK(gran_theory_cooling_rates(mix, T, xi));
  double d = 0;
  for (int k = 0; k < M; k++) d = fmax(d, fabs(0.5 * xi[k] * tau0 - 1.0));
  if (!(d <= 1e-11)) fail_msg("defect %g", d);
  GRAN_ASSERT_REL(T[0], 1.0, 1e-15);
  free(m);
  free(n);
  free(E);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_theta2),         cmocka_unit_test(test_theta3),
      cmocka_unit_test(test_theta4),         cmocka_unit_test(test_switch_and_eps),
      cmocka_unit_test(test_structured_general),
  };
  return cmocka_run_group_tests_name("t403-hcs-large", tests, NULL, NULL);
}
