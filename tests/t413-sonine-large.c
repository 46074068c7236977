/* t413-sonine-large.c - the first Sonine HCS of many species: M = 1e4 (2000 under ASan), masses
 * m_k = 10^((k-1)/(M-1)), sigma_k = m_k^(1/3), n_k ~ m_k^-2, eps = 0.5 (bench b401 section 5):
 * finite, abs(a2_k) < 1, an HCS of the Sonine rates to 1e-10, and the same continuum as M = 500
 * (the mixture is a discretised mass distribution: T_M/T_1 and a2 at both ends agree to 1e-3). */
#include "granary_test.h"

#if defined(__SANITIZE_ADDRESS__)
#define T413_ASAN 1
#else
#define T413_ASAN 0
#endif

static void solve(int64_t M, double *ratio, double *a2first, double *a2last) {
  double *m = malloc(sizeof(double) * (size_t)M), *s = malloc(sizeof(double) * (size_t)M),
         *n = malloc(sizeof(double) * (size_t)M), *T = malloc(sizeof(double) * (size_t)M),
         *a2 = malloc(sizeof(double) * (size_t)M), *z = malloc(sizeof(double) * (size_t)M),
         *da = malloc(sizeof(double) * (size_t)M);
  assert_non_null(m);
  assert_non_null(da);
  for (int64_t k = 0; k < M; k++) {
    m[k] = pow(10.0, (double)k / (double)(M - 1));
    s[k] = cbrt(m[k]);
    n[k] = pow(m[k], -2.0) / (double)M;
  }
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  double tau0 = 0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, T, a2, &tau0));
  GRAN_ASSERT_OK(gran_theory_sonine_rates(mix, T, a2, z, da));
  double dz = 0, dd = 0;
  for (int64_t k = 0; k < M; k++) {
    assert_true(isfinite(T[k]) && T[k] > 0 && fabs(a2[k]) < 1);
    dz = fmax(dz, fabs(0.5 * z[k] * tau0 - 1));
    dd = fmax(dd, fabs(da[k] * tau0));
  }
  print_message("M = %lld: T_M/T_1 = %.6f, a2_1 = %.6f, a2_M = %.6f, defects %.1e %.1e\n", (long long)M,
                T[M - 1] / T[0], a2[0], a2[M - 1], dz, dd);
  assert_true(dz <= 1e-10 && dd <= 1e-10);
  *ratio = T[M - 1] / T[0];
  *a2first = a2[0];
  *a2last = a2[M - 1];
  gran_mixture_destroy(&mix);
  free(m), free(s), free(n), free(T), free(a2), free(z), free(da);
}

static void test_many(void **state) {
  (void)state;
  double r1, f1, l1, r2, f2, l2;
  solve(500, &r1, &f1, &l1);
  solve(T413_ASAN ? 2000 : 10000, &r2, &f2, &l2);
  GRAN_ASSERT_REL(r2, r1, 1e-3);
  GRAN_ASSERT_ABS(f2, f1, 1e-3);
  GRAN_ASSERT_ABS(l2, l1, 1e-3);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_many)};
  return cmocka_run_group_tests_name("t413-sonine-large", tests, NULL, NULL);
}
