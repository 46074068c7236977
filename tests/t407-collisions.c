/* t407-collisions.c - collision statistics of the DSMC outline: mean relative speeds (Eq. 60),
 * collision rates per species pair (Eq. 57-58, 61) and expected collision counts along the cooling. */
#include "granary_test.h"

static const double PI = 3.14159265358979323846;

static gran_mixture *make(int M, const double *m, const double *s, const double *n, double eps) {
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

/* Eq. 60 and Eq. 34 (monodisperse: 4 sqrt(T/(pi m))); per-particle collision frequency of a
 * monodisperse gas 2 rate/n = 4 sqrt(pi) n sigma^2 g2 sqrt(T/m) (docs/physics.md, "Oracles for
 * tests", and the DSMC outline Eq. 35); the total sum_{i<=j} rate_ij is TWICE the outline's Eq. 61 as
 * printed: Eqs. 57 and 58 each halve the sum over ordered pairs, so Eq. 61 reduces for one species to
 * half of Eq. 35 (a slip of the source, docs/physics.md, "Corrections to the sources"; Eq. 35 and the
 * collision frequency of "Oracles for tests" fix the factor). All 1e-14. */
static void test_rates(void **state) {
  (void)state;
  const double m = 2.0, s = 0.6, n = 0.3, T = 1.7;
  gran_mixture *mix = make(1, &m, &s, &n, 0.5);
  GRAN_ASSERT_OK(gran_mixture_set_g2(mix, 1.4));
  double g, r;
  GRAN_ASSERT_OK(gran_theory_mean_relative_speed(mix, &T, &g));
  GRAN_ASSERT_REL(g, 4 * sqrt(T / (PI * m)), 1e-15);
  GRAN_ASSERT_OK(gran_theory_collision_rates(mix, &T, &r));
  GRAN_ASSERT_REL(2 * r / n, 4 * sqrt(PI) * n * s * s * 1.4 * sqrt(T / m), 1e-14);
  gran_mixture_destroy(&mix);

  const double m3[3] = {1, 10, 50}, s3[3] = {1, 2, 3}, n3[3] = {0.1, 0.02, 0.0}, T3[3] = {0.5, 2, 7};
  mix = make(3, m3, s3, n3, 0.5);
  double G[9], R[9];
  GRAN_ASSERT_OK(gran_theory_mean_relative_speed(mix, T3, G));
  GRAN_ASSERT_OK(gran_theory_collision_rates(mix, T3, R));
  double tot = 0, eq61 = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) {
      GRAN_ASSERT_REL(G[3 * i + j], sqrt(8 / PI * (T3[i] / m3[i] + T3[j] / m3[j])), 1e-15);
      GRAN_ASSERT_REL(R[3 * i + j], R[3 * j + i], 0.0);
      if (j >= i) tot += R[3 * i + j];
      /* Eq. 61 per unit volume and time, R_i + R_j = sigma_ij, summed over ordered pairs */
      eq61 += sqrt(PI / 2) * n3[i] * n3[j] * pow(0.5 * (s3[i] + s3[j]), 2) * sqrt(T3[i] / m3[i] + T3[j] / m3[j]);
    }
  GRAN_ASSERT_REL(tot, 2 * eq61, 1e-14);
  GRAN_ASSERT_REL(R[8], 0.0, 0.0);        /* tracers do not collide with each other */
  gran_mixture_destroy(&mix);
}

/* Counts along the cooling. (a) HCS: rate_ij ~ 1/(1 + t/tau0), so
 * counts = V rate_ij(0) tau0 log(1 + t/tau0): 1e-9 at rtol 1e-10. (b) Haff in collisions per particle
 * c = 2 N_coll/N (docs/physics.md, "Oracles for tests"): ln(T/T0) = -(1 - eps^2) c/3 (a2 = 0), from
 * an equipartition start in a 1-species gas: 1e-9. (c) the MSD is linear in c: Eq. 23 =
 * 9 c/(4 pi (1+eps)^2 (n sigma^2 g2)^2) (1e-9). */
static void test_counts(void **state) {
  (void)state;
  const double m[2] = {1, 100}, s[2] = {1, cbrt(100.0)}, n[2] = {0.1, 0.001};
  gran_mixture *mix = make(2, m, s, n, 0.5);
  double T0[2], tau0, R[4], C[3 * 4];
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, T0, &tau0));
  GRAN_ASSERT_OK(gran_theory_collision_rates(mix, T0, R));
  const double V = 1e6, t[3] = {100.0, 0.0, 1.0};
  GRAN_ASSERT_OK(gran_theory_collision_counts(mix, T0, V, 3, t, 1e-10, C));
  for (int j = 0; j < 3; j++)
    for (int p = 0; p < 4; p++) GRAN_ASSERT_REL(C[4 * j + p], V * R[p] * tau0 * log1p(t[j] / tau0), 1e-9);
  gran_mixture_destroy(&mix);

  const double m1 = 1, s1 = 1, n1 = 0.1, eps = 0.8;
  double Ts = 1.0;
  mix = make(1, &m1, &s1, &n1, eps);
  const double tt[3] = {1.0, 50.0, 1e6};
  double Tt[3], c1[3], msd[3], tau;
  GRAN_ASSERT_OK(gran_theory_collision_counts(mix, &Ts, 1.0, 3, tt, 1e-10, c1));
  GRAN_ASSERT_OK(gran_theory_temperatures(mix, &Ts, 3, tt, 1e-10, Tt));
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, &Ts, &tau));
  GRAN_ASSERT_OK(gran_theory_msd_hcs(mix, &Ts, tau, 3, tt, msd, NULL));
  double D, tv;
  GRAN_ASSERT_OK(gran_theory_diffusion(mix, &Ts, &D));
  GRAN_ASSERT_OK(gran_theory_tau_v(mix, &Ts, &tv));
  for (int j = 0; j < 3; j++) {
    const double c = 2 * c1[j] / n1;
    GRAN_ASSERT_REL(log(Tt[j] / Ts), -(1 - eps * eps) * c / 3, 1e-9);
    const double eq23 = msd[j] + 6 * D * tv * (-expm1(-tau / tv * log1p(tt[j] / tau)));
    GRAN_ASSERT_REL(eq23, 9 * c / (4 * PI * pow(1 + eps, 2) * pow(n1 * s1 * s1, 2)), 1e-9);
  }
  gran_mixture_destroy(&mix);
}

static void test_bad_inputs(void **state) {
  (void)state;
  const double m[2] = {1, 2}, s[2] = {1, 1}, n[2] = {0.1, 0.1}, T[2] = {1, 1}, Tb[2] = {1, NAN};
  gran_mixture *mix = make(2, m, s, n, 0.5);
  double out[8];
  const double t[2] = {1, 2}, tb[2] = {-1, 2};
  GRAN_ASSERT_ERR(gran_theory_mean_relative_speed(mix, Tb, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_mean_relative_speed(mix, T, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_mean_relative_speed(NULL, T, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_rates(mix, Tb, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_rates(mix, T, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, T, 0.0, 2, t, 1e-8, out), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "volume"));
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, T, NAN, 2, t, 1e-8, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, T, 1.0, 2, tb, 1e-8, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, Tb, 1.0, 2, t, 1e-8, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, T, 1.0, -1, t, 1e-8, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, T, 1.0, 2, t, 0.0, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_collision_counts(mix, T, 1.0, 2, t, 1e-8, NULL), GRAN_ERR_ARG);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_rates),
      cmocka_unit_test(test_counts),
      cmocka_unit_test(test_bad_inputs),
  };
  return cmocka_run_group_tests_name("t407-collisions", tests, NULL, NULL);
}
