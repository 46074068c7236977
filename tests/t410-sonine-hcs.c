/* t410-sonine-hcs.c - the first Sonine approximation (src/theory/sonine.cpp, docs/physics-sonine.md):
 * the HCS of one species against van Noije & Ernst's closed form, the limits eps -> 1, equal
 * species and many species, the HCS property of the solution, the trajectories T_k(t), a2_k(t)
 * converging to the HCS, and the refusals. */
#include "granary_test.h"

static const double SQRT_PI = 1.7724538509055160273;

static gran_mixture *make(int M, const double *m, const double *s, const double *n, double eps) {
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

/* van Noije & Ernst, Granular Matter 1, 57 (1998): a2 in 3-D */
static double a2_vne(double e) { return 16 * (1 - e) * (1 - 2 * e * e) / (81 - 17 * e + 30 * e * e * (1 - e)); }

/* One species: a2 = van Noije & Ernst (1e-12) and zeta = zeta_Haff (1 + 3 a2/16) (1e-12). */
static void test_monodisperse(void **state) {
  (void)state;
  const double m = 2.5, s = 0.7, n = 0.3, g2 = 1.3, T = 1.7;
  const double eps[5] = {0.0, 0.3, 0.5, 0.7, 0.9};
  for (int i = 0; i < 5; i++) {
    gran_mixture *mix = make(1, &m, &s, &n, eps[i]);
    GRAN_ASSERT_OK(gran_mixture_set_g2(mix, g2));
    double T0 = 0, a2 = 0, tau0 = 0;
    GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, T, &T0, &a2, &tau0));
    GRAN_ASSERT_REL(T0, T, 1e-15);
    GRAN_ASSERT_ABS(a2, a2_vne(eps[i]), 1e-12);
    const double om = (1 - eps[i]) * (1 + eps[i]);
    const double haff = 2.0 / 3.0 * SQRT_PI * om * n * s * s * g2 * sqrt(T / m);
    GRAN_ASSERT_REL(1.0 / tau0, haff * (1 + 3 * a2 / 16), 1e-12);
    /* the Maxwellian level of the same call: a2 = 0, gran_theory_hcs */
    double a2m = 1, tm = 0;
    GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_MAXWELLIAN, GRAN_HCS_NORM_MEAN, T, &T0, &a2m, &tm));
    GRAN_ASSERT_ABS(a2m, 0.0, 0.0);
    GRAN_ASSERT_REL(1.0 / tm, haff, 1e-14);
    gran_mixture_destroy(&mix);
  }
}

/* The solution is an HCS of the Sonine rates: zeta_k tau0/2 = 1 and da2_k/dt = 0 (relative to
 * zeta). Binary mixture, mass ratio 10, eps = 0.7: the Sonine ratio T2/T1 lies below the
 * Maxwellian one (1.80633 against 1.82686), a2 of the light species negative, of the heavy positive. */
static void test_binary_hcs(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double T[2], a2[2], tau0, TM[2], tauM, z[2], da[2];
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T, a2, &tau0));
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, TM, &tauM));
  GRAN_ASSERT_OK(gran_theory_sonine_rates(mix, T, a2, z, da));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(0.5 * z[k] * tau0, 1.0, 1e-11);
    GRAN_ASSERT_ABS(da[k] * tau0, 0.0, 1e-10);
  }
  GRAN_ASSERT_REL(T[1], 1.806332989, 1e-8);
  GRAN_ASSERT_REL(TM[1], 1.826862763, 1e-8);
  assert_true(a2[0] < -0.01 && a2[1] > 0.01);
  /* mean normalisation */
  double Tm[2];
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 2.0, Tm, NULL, NULL));
  GRAN_ASSERT_REL((n[0] * Tm[0] + n[1] * Tm[1]) / (n[0] + n[1]), 2.0, 1e-14);
  GRAN_ASSERT_REL(Tm[1] / Tm[0], T[1] / T[0], 1e-13);
  gran_mixture_destroy(&mix);
}

/* eps -> 1: a2 -> 0 like (1 - eps) and the temperatures -> the Maxwellian HCS; eps = 1: a2 = 0 and
 * equipartition. Matrix restitution with the same eps everywhere gives the constant-eps state. */
static void test_elastic_limit(void **state) {
  (void)state;
  enum { M = 3 };
  const double m[M] = {1, 4, 30}, s[M] = {1, 1.5, 3}, n[M] = {1, 0.3, 0.02};
  const double de[3] = {1e-3, 1e-6, 1e-9};
  for (int i = 0; i < 3; i++) {
    gran_mixture *mix = make(M, m, s, n, 1 - de[i]);
    double T[M], a2[M], TM[M];
    GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T, a2, NULL));
    GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_T1, 1.0, TM, NULL));
    for (int k = 0; k < M; k++) {
      GRAN_ASSERT_ABS(a2[k], 0.0, de[i]);
      GRAN_ASSERT_REL(T[k], TM[k], de[i]);
    }
    gran_mixture_destroy(&mix);
  }
  gran_mixture *mix = make(M, m, s, n, 1.0);
  double T[M], a2[M], tau0 = 0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, T, a2, &tau0));
  for (int k = 0; k < M; k++) {
    GRAN_ASSERT_ABS(a2[k], 0.0, 0.0);
    GRAN_ASSERT_REL(T[k], 1.0, 1e-15);
  }
  assert_true(isinf(tau0));
  gran_mixture_destroy(&mix);
  /* matrix path */
  double E[M * M];
  for (int j = 0; j < M * M; j++) E[j] = 0.6;
  gran_mixture *a = make(M, m, s, n, 0.6), *b = make(M, m, s, n, 1.0);
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(b, E));
  double Ta[M], Tb[M], aa[M], ab[M];
  GRAN_ASSERT_OK(gran_theory_hcs_approx(a, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Ta, aa, NULL));
  GRAN_ASSERT_OK(gran_theory_hcs_approx(b, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Tb, ab, NULL));
  for (int k = 0; k < M; k++) {
    GRAN_ASSERT_REL(Tb[k], Ta[k], 1e-12);
    GRAN_ASSERT_ABS(ab[k], aa[k], 1e-12);
  }
  gran_mixture_destroy(&a);
  gran_mixture_destroy(&b);
}

/* Three copies of one species (densities summing to n) are that species: equal T, a2 = vNE. */
static void test_equal_species(void **state) {
  (void)state;
  const double m[3] = {2, 2, 2}, s[3] = {1, 1, 1}, n[3] = {0.2, 0.5, 0.3};
  gran_mixture *mix = make(3, m, s, n, 0.5);
  double T[3], a2[3], tau0, T1, a21, tau1;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, T, a2, &tau0));
  gran_mixture_destroy(&mix);
  const double one = 1.0;
  mix = make(1, m, s, &one, 0.5);
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, &T1, &a21, &tau1));
  for (int k = 0; k < 3; k++) {
    GRAN_ASSERT_REL(T[k], 1.0, 1e-12);
    GRAN_ASSERT_ABS(a2[k], a2_vne(0.5), 1e-12);
  }
  GRAN_ASSERT_REL(tau0, tau1, 1e-12);
  gran_mixture_destroy(&mix);
}

/* Many species (power law, 1000 species, theta = 2, eps = 0.5; the low-rank Newton path): finite,
 * |a2| < 1, and an HCS of the Sonine rates (zeta_k tau0/2 = 1 to 1e-10). */
static void test_many_species(void **state) {
  (void)state;
  enum { M = 1000 };
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(M, 1, 1, 1, 2, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  static double T[M], a2[M], z[M], da[M];
  double tau0 = 0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_MEAN, 1.0, T, a2, &tau0));
  GRAN_ASSERT_OK(gran_theory_sonine_rates(mix, T, a2, z, da));
  for (int k = 0; k < M; k++) {
    assert_true(isfinite(T[k]) && T[k] > 0 && fabs(a2[k]) < 1);
    GRAN_ASSERT_REL(0.5 * z[k] * tau0, 1.0, 1e-10);
    GRAN_ASSERT_ABS(da[k] * tau0, 0.0, 1e-9);
  }
  gran_mixture_destroy(&mix);
}

/* Trajectories: from a Maxwellian start far from the HCS, T_k(t)/T_1(t) and a2_k(t) reach the
 * Sonine HCS at t = 1e4 tau0 (1e-6); the Maxwellian level equals gran_theory_temperatures. */
static void test_trajectories(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double Th[2], ah[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Th, ah, &tau0));
  const double T0[2] = {1.0, 5.0}, a20[2] = {0.1, -0.1};
  const double t[3] = {1e4 * tau0, 0.0, 10 * tau0};
  double T[6], a2[6], Tm[6], Tr[6];
  GRAN_ASSERT_OK(gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, T0, a20, 3, t, 1e-10, T, a2));
  GRAN_ASSERT_REL(T[2], 1.0, 1e-14); /* t = 0 */
  GRAN_ASSERT_REL(T[3], 5.0, 1e-14);
  GRAN_ASSERT_REL(a2[2], 0.1, 1e-14);
  GRAN_ASSERT_REL(a2[3], -0.1, 1e-14);
  GRAN_ASSERT_REL(T[1] / T[0], Th[1] / Th[0], 1e-6);
  GRAN_ASSERT_ABS(a2[0], ah[0], 1e-6);
  GRAN_ASSERT_ABS(a2[1], ah[1], 1e-6);
  GRAN_ASSERT_OK(gran_theory_temperatures_approx(mix, GRAN_THEORY_MAXWELLIAN, T0, a20, 3, t, 1e-10, Tm, a2));
  GRAN_ASSERT_OK(gran_theory_temperatures(mix, T0, 3, t, 1e-10, Tr));
  for (int j = 0; j < 6; j++) {
    GRAN_ASSERT_REL(Tm[j], Tr[j], 0.0);
    GRAN_ASSERT_ABS(a2[j], 0.0, 0.0);
  }
  gran_mixture_destroy(&mix);
  /* one species from a2 = 0: a2(t) -> vNE */
  const double one = 1.0, T1 = 1.0;
  mix = make(1, &one, &one, &one, 0.5);
  const double tl = 1e6;
  double Tt, at;
  GRAN_ASSERT_OK(gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, &T1, NULL, 1, &tl, 1e-10, &Tt, &at));
  GRAN_ASSERT_ABS(at, a2_vne(0.5), 1e-7);
  gran_mixture_destroy(&mix);
}

/* Matrix restitution with distinct eps_ij, a g2 matrix and a tracer species (n = 0; the accessor
 * pass): still an HCS of the Sonine rates, and the tracer changes nothing else (the gas equals the
 * same mixture without it). */
static void test_matrix_tracer(void **state) {
  (void)state;
  enum { M = 3 };
  const double m[M] = {1, 3, 50}, s[M] = {1, 1.4, 3.7}, n[M] = {1, 0.4, 0};
  const double E[M * M] = {0.8, 0.7, 0.9, 0.7, 0.6, 0.85, 0.9, 0.85, 0.75};
  const double G[M * M] = {1.1, 1.2, 1.0, 1.2, 1.3, 1.05, 1.0, 1.05, 1.0};
  gran_mixture *mix = make(M, m, s, n, 1.0), *gas = make(2, m, s, n, 1.0);
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(mix, E));
  GRAN_ASSERT_OK(gran_mixture_set_g2_matrix(mix, G));
  const double E2[4] = {0.8, 0.7, 0.7, 0.6}, G2[4] = {1.1, 1.2, 1.2, 1.3};
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(gas, E2));
  GRAN_ASSERT_OK(gran_mixture_set_g2_matrix(gas, G2));
  double T[M], a2[M], tau0, z[M], da[M], Tg[2], ag[2], taug;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T, a2, &tau0));
  GRAN_ASSERT_OK(gran_theory_sonine_rates(mix, T, a2, z, da));
  for (int k = 0; k < M; k++) {
    GRAN_ASSERT_REL(0.5 * z[k] * tau0, 1.0, 1e-11);
    GRAN_ASSERT_ABS(da[k] * tau0, 0.0, 1e-10);
  }
  GRAN_ASSERT_OK(gran_theory_hcs_approx(gas, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, Tg, ag, &taug));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(T[k], Tg[k], 1e-11);
    GRAN_ASSERT_ABS(a2[k], ag[k], 1e-11);
  }
  GRAN_ASSERT_REL(tau0, taug, 1e-11);
  print_message("tracer: T = %g %g %g, a2 = %g %g %g\n", T[0], T[1], T[2], a2[0], a2[1], a2[2]);
  assert_true(T[2] > T[1] && fabs(a2[2]) < 0.2); /* the heavy tracer runs hotter */
  gran_mixture_destroy(&mix);
  gran_mixture_destroy(&gas);
}

static void test_bad_inputs(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double T[2] = {1, 1}, a2[2] = {0, 0}, z[2], t = 1.0;
  GRAN_ASSERT_ERR(gran_theory_hcs_approx(mix, 2, GRAN_HCS_NORM_T1, 1.0, T, a2, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "approximation"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_approx(mix, -1, T, a2, 1, &t, 1e-8, T, a2), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "approximation"));
  GRAN_ASSERT_ERR(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, 7, 1.0, T, a2, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "norm"));
  GRAN_ASSERT_ERR(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 0.0, T, a2, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "value"));
  GRAN_ASSERT_ERR(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, NULL, a2, NULL),
                  GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "T0"));
  const double bad[2] = {0.0, 1.0};
  GRAN_ASSERT_ERR(gran_theory_sonine_rates(mix, T, bad, z, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a2'[1]"));
  const double nan2[2] = {NAN, 0.0};
  GRAN_ASSERT_ERR(gran_theory_sonine_rates(mix, T, nan2, z, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a2'[0]"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, T, bad, 1, &t, 1e-8, T, a2),
                  GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "a20"));
  const double Tneg[2] = {1.0, -1.0};
  GRAN_ASSERT_ERR(gran_theory_sonine_rates(mix, Tneg, a2, z, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "T"));
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  GRAN_ASSERT_ERR(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T, a2, NULL),
                  GRAN_ERR_DOMAIN);
  assert_non_null(strstr(gran_last_error_message(), "viscoelastic"));
  GRAN_ASSERT_OK(gran_theory_sonine_rates(mix, T, a2, z, NULL)); /* rates: t417 */
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_monodisperse),   cmocka_unit_test(test_binary_hcs),   cmocka_unit_test(test_elastic_limit),
      cmocka_unit_test(test_equal_species),  cmocka_unit_test(test_many_species), cmocka_unit_test(test_trajectories),
      cmocka_unit_test(test_matrix_tracer),  cmocka_unit_test(test_bad_inputs),
  };
  return cmocka_run_group_tests_name("t410-sonine-hcs", tests, NULL, NULL);
}
