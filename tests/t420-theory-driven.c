/* t420-theory-driven.c - partial temperatures of a driven mixture (gran_theory_temperatures_driven):
 * Eq. 13 with a heating rate per species (white-noise thermostat) and a Maxwellian bath, against
 * closed forms (an elastic gas heats linearly; the bath rate of the DSMC outline's Eq. 76 integrated
 * here by RK4; the driven steady state xi(T*) T* = H), limits (no drive = free cooling; an elastic
 * mixture in a bath ends at T_b), and bad input. */
#include "granary_test.h"

static const double SQ2PI = 2.5066282746310002;

static gran_mixture *make(int M, const double *m, const double *s, const double *n, double eps) {
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

/* An elastic one-species gas does not cool: with heating H, T = T0 + H t exactly. */
static void test_elastic_heating(void **state) {
  (void)state;
  const double m = 2.0, s = 1.0, n = 0.1;
  gran_mixture *mix = make(1, &m, &s, &n, 1.0);
  const double T0 = 0.5, H = 0.3, t[4] = {0.0, 1.0, 10.0, 1e3};
  double T[4];
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, &T0, &H, 0.0, 1.0, 1.0, 1.0, 4, t, 1e-10, T));
  for (int j = 0; j < 4; j++) GRAN_ASSERT_REL(T[j], T0 + H * t[j], 1e-9);
  gran_mixture_destroy(&mix);
}

/* No heating and no bath: the free-cooling temperatures of gran_theory_temperatures. */
static void test_free_limit(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {0.1, 0.05};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  const double T0[2] = {1.0, 3.0}, t[3] = {0.5, 5.0, 50.0};
  double T[6], Tf[6];
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, T0, NULL, 0.0, 0.0, 0.0, 0.0, 3, t, 1e-10, T));
  GRAN_ASSERT_OK(gran_theory_temperatures(mix, T0, 3, t, 1e-10, Tf));
  for (int j = 0; j < 6; j++) GRAN_ASSERT_REL(T[j], Tf[j], 1e-8);
  gran_mixture_destroy(&mix);
}

/* One elastic species of mass m in a bath of equal particles (the outline's Eq. 76 with the bath as
 * a species at T_b): dT/dt = (4/3) sqrt(2 pi) n_b sigma^2 sqrt((T + T_b)/m) (T_b - T), integrated
 * here by RK4 (h = 1e-4); T -> T_b. */
static double bath_rate(double T, double nb, double sg, double m, double Tb) {
  return (4.0 / 3.0) * SQ2PI * nb * sg * sg * sqrt((T + Tb) / m) * (Tb - T);
}
static void test_bath_equal_masses(void **state) {
  (void)state;
  const double m = 1.0, s = 1.0, n = 0.1, nb = 0.02, Tb = 2.0, T0 = 1.0;
  gran_mixture *mix = make(1, &m, &s, &n, 1.0);
  const double t[3] = {2.0, 5.0, 10.0};
  double T[3];
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, &T0, NULL, nb, m, Tb, s, 3, t, 1e-11, T));
  double x = T0, tc = 0.0;
  const double h = 1e-4;
  for (int j = 0; j < 3; j++) {
    while (tc < t[j] - 0.5 * h) {
      const double k1 = bath_rate(x, nb, s, m, Tb), k2 = bath_rate(x + 0.5 * h * k1, nb, s, m, Tb);
      const double k3 = bath_rate(x + 0.5 * h * k2, nb, s, m, Tb), k4 = bath_rate(x + h * k3, nb, s, m, Tb);
      x += h / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4);
      tc += h;
    }
    GRAN_ASSERT_REL(T[j], x, 1e-8);
  }
  assert_true(T[0] > T0 && T[2] > T[1] && T[2] < Tb);
  /* late: the bath's temperature */
  const double tl = 1e4;
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, &T0, NULL, nb, m, Tb, s, 1, &tl, 1e-10, T));
  GRAN_ASSERT_REL(T[0], Tb, 1e-8);
  gran_mixture_destroy(&mix);
}

/* An elastic binary mixture (m = 1, 3) in a bath at T_b = 2 of another mass and size: both
 * species end at T_b (equilibrium), the light one first. */
static void test_bath_mixture_equilibrium(void **state) {
  (void)state;
  const double m[2] = {1, 3}, s[2] = {1, 1.5}, n[2] = {0.05, 0.02};
  gran_mixture *mix = make(2, m, s, n, 1.0);
  const double T0[2] = {1.0, 0.5}, t[2] = {1.0, 1e4};
  double T[4];
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, T0, NULL, 0.05, 2.0, 2.0, 0.8, 2, t, 1e-10, T));
  GRAN_ASSERT_REL(T[2], 2.0, 1e-8);
  GRAN_ASSERT_REL(T[3], 2.0, 1e-8);
  assert_true(T[0] > T0[0] && T[1] > T0[1]);
  gran_mixture_destroy(&mix);
}

/* The driven steady state of an inelastic mixture: xi_k(T*) T*_k = H_k for every species (the
 * residual through gran_theory_cooling_rates); one species: T* = (H / xi(1))^(2/3), xi ~ sqrt(T). */
static void test_steady_state(void **state) {
  (void)state;
  const double m1 = 1.0, s1 = 1.0, n1 = 0.1;
  gran_mixture *one = make(1, &m1, &s1, &n1, 0.6);
  const double T1 = 1.0;
  double xi1;
  GRAN_ASSERT_OK(gran_theory_cooling_rates(one, &T1, &xi1));
  const double H = 0.01, tl = 1e5, T0 = 4.0;
  double T;
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(one, &T0, &H, 0.0, 1.0, 1.0, 1.0, 1, &tl, 1e-10, &T));
  GRAN_ASSERT_REL(T, pow(H / xi1, 2.0 / 3.0), 1e-8);
  gran_mixture_destroy(&one);

  const double m[3] = {1, 10, 100}, s[3] = {1, 2, 4}, n[3] = {0.1, 0.01, 0.001};
  gran_mixture *mix = make(3, m, s, n, 0.8);
  const double T3[3] = {1, 1, 1}, Hk[3] = {0.02, 0.02, 0.02};
  double Ts[3], xi[3];
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, T3, Hk, 0.0, 1.0, 1.0, 1.0, 1, &tl, 1e-10, Ts));
  GRAN_ASSERT_OK(gran_theory_cooling_rates(mix, Ts, xi));
  for (int k = 0; k < 3; k++) GRAN_ASSERT_REL(xi[k] * Ts[k], Hk[k], 1e-7);
  assert_true(Ts[2] > Ts[1] && Ts[1] > Ts[0]); /* the heavy species run hotter, as in the HCS */
  gran_mixture_destroy(&mix);
}

static void test_bad_input(void **state) {
  (void)state;
  const double m = 1.0, s = 1.0, n = 0.1, T0 = 1.0, t = 1.0;
  gran_mixture *mix = make(1, &m, &s, &n, 0.9);
  double T;
  const double bad[] = {-1.0, NAN, INFINITY};
  for (int i = 0; i < 3; i++) {
    GRAN_ASSERT_ERR(gran_theory_temperatures_driven(mix, &T0, &bad[i], 0.0, 1.0, 1.0, 1.0, 1, &t, 1e-8, &T),
                    GRAN_ERR_ARG);
    assert_non_null(strstr(gran_last_error_message(), "'heating'"));
  }
  GRAN_ASSERT_ERR(gran_theory_temperatures_driven(mix, &T0, NULL, -0.1, 1.0, 1.0, 1.0, 1, &t, 1e-8, &T), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'bath_density'"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_driven(mix, &T0, NULL, 0.1, 0.0, 1.0, 1.0, 1, &t, 1e-8, &T), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'bath_mass'"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_driven(mix, &T0, NULL, 0.1, 1.0, -1.0, 1.0, 1, &t, 1e-8, &T), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'bath_T'"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_driven(mix, &T0, NULL, 0.1, 1.0, 1.0, NAN, 1, &t, 1e-8, &T), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'bath_sigma'"));
  /* the bath values are not used without a bath */
  GRAN_ASSERT_OK(gran_theory_temperatures_driven(mix, &T0, NULL, 0.0, 0.0, -1.0, NAN, 1, &t, 1e-8, &T));
  const double neg = -1.0;
  GRAN_ASSERT_ERR(gran_theory_temperatures_driven(mix, &T0, NULL, 0.0, 1.0, 1.0, 1.0, 1, &neg, 1e-8, &T), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_temperatures_driven(NULL, &T0, NULL, 0.0, 1.0, 1.0, 1.0, 1, &t, 1e-8, &T), GRAN_ERR_ARG);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_elastic_heating),         cmocka_unit_test(test_free_limit),
      cmocka_unit_test(test_bath_equal_masses),       cmocka_unit_test(test_bath_mixture_equilibrium),
      cmocka_unit_test(test_steady_state),            cmocka_unit_test(test_bad_input),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
