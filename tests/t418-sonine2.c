/* t418-sonine2.c - the second Sonine approximation (src/theory/sonine2.cpp, docs/physics-sonine.md Sec. 4):
 * one species (a2, a3 of the linear second Sonine equations; zeta = zeta_Haff (1 + 3 a2/16 + a3/64)), the rates
 * at an unequal state against docs/tools/sonine_second.py (mpmath, 30 digits), the first Sonine rates at a3 = 0,
 * the HCS property, the elastic and equal-species limits, and the refusals; the Sonine hierarchy to order nmax
 * (gran_theory_hcs_sonine_n): nmax = 2, 3 are the first and the second level, nmax = 5 against
 * docs/tools/sonine_order_n.py. */
#include "granary_test.h"

static const double SQRT_PI = 1.7724538509055160273;

static gran_mixture *make(int M, const double *m, const double *s, const double *n, double eps) {
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

/* One species: a2, a3 of docs/tools/sonine_second.py (hcs, order 2) and the cooling rate. */
static void test_monodisperse(void **state) {
  (void)state;
  const double eps[3] = {0.3, 0.5, 0.9};
  const double a2r[3] = {0.088629176185060, 0.044993978002290, -0.015661801390612};
  const double a3r[3] = {-0.059650527833367, -0.017684168615936, -0.003872456650364};
  const double m = 2.5, s = 0.7, n = 0.3, g2 = 1.3, T = 1.7;
  for (int i = 0; i < 3; i++) {
    gran_mixture *mix = make(1, &m, &s, &n, eps[i]);
    GRAN_ASSERT_OK(gran_mixture_set_g2(mix, g2));
    double T0 = 0, a2 = 0, a3 = 0, tau0 = 0;
    GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, T, &T0, &a2, &a3, &tau0));
    print_message("eps %.1f: a2 = %.12f, a3 = %.12f\n", eps[i], a2, a3);
    GRAN_ASSERT_REL(T0, T, 1e-15);
    GRAN_ASSERT_ABS(a2, a2r[i], 1e-12);
    GRAN_ASSERT_ABS(a3, a3r[i], 1e-12);
    const double haff = 2.0 / 3.0 * SQRT_PI * (1 - eps[i]) * (1 + eps[i]) * n * s * s * g2 * sqrt(T / m);
    GRAN_ASSERT_REL(1.0 / tau0, haff * (1 + 3 * a2 / 16 + a3 / 64), 1e-12);
    double z, d2, d3;
    GRAN_ASSERT_OK(gran_theory_sonine2_rates(mix, &T0, &a2, &a3, &z, &d2, &d3));
    GRAN_ASSERT_ABS(d2 * tau0, 0.0, 1e-12);
    GRAN_ASSERT_ABS(d3 * tau0, 0.0, 1e-12);
    gran_mixture_destroy(&mix);
  }
}

/* The rates at an unequal state: m = 1, 10; sigma = 1, 2; n = 1, 0.5; eps = 0.7; T = 1.3, 2.9;
 * a2 = 0.03, -0.05; a3 = 0.02, -0.01 (docs/tools/sonine_second.py rates() in mpmath at 30 digits); at a3 = 0
 * zeta and da2/dt are those of the first Sonine level (gran_theory_sonine_rates). */
static void test_rates(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  const double T[2] = {1.3, 2.9}, a2[2] = {0.03, -0.05}, a3[2] = {0.02, -0.01}, a30[2] = {0, 0};
  const double zr[2] = {2.2424676607809641, 2.9432718322666662};
  const double d2r[2] = {-0.40347077414723905, 0.40268978953106601};
  const double d3r[2] = {-0.36018162137787629, 0.15178393351334718};
  double z[2], d2[2], d3[2], z1[2], d21[2];
  GRAN_ASSERT_OK(gran_theory_sonine2_rates(mix, T, a2, a3, z, d2, d3));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(z[k], zr[k], 1e-14);
    GRAN_ASSERT_REL(d2[k], d2r[k], 1e-13);
    GRAN_ASSERT_REL(d3[k], d3r[k], 1e-13);
  }
  GRAN_ASSERT_OK(gran_theory_sonine2_rates(mix, T, a2, a30, z, d2, NULL));
  GRAN_ASSERT_OK(gran_theory_sonine_rates(mix, T, a2, z1, d21));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(z[k], z1[k], 1e-14);
    GRAN_ASSERT_REL(d2[k], d21[k], 1e-13);
  }
  /* temperatures 1e-60 times smaller (a gas cooled for long): the rates scale as sqrt(T), nothing underflows */
  const double Ts[2] = {1.3e-60, 2.9e-60};
  GRAN_ASSERT_OK(gran_theory_sonine2_rates(mix, Ts, a2, a3, z, d2, d3));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(z[k], zr[k] * 1e-30, 1e-13);
    GRAN_ASSERT_REL(d2[k], d2r[k] * 1e-30, 1e-12);
    GRAN_ASSERT_REL(d3[k], d3r[k] * 1e-30, 1e-12);
  }
  /* the matrix restitution path gives the same */
  const double E[4] = {0.7, 0.7, 0.7, 0.7};
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(mix, E));
  GRAN_ASSERT_OK(gran_theory_sonine2_rates(mix, T, a2, a3, z1, d21, NULL));
  for (int k = 0; k < 2; k++) GRAN_ASSERT_REL(z1[k], zr[k], 1e-14);
  gran_mixture_destroy(&mix);
}

/* HCS of mixtures: equal zeta_k, da2/dt = da3/dt = 0; the ratios of docs/tools/sonine_second.py. */
static void test_hcs(void **state) {
  (void)state;
  struct {
    int M;
    double m[3], s[3], n[3], eps, ratio[2];
  } c[3] = {{2, {1, 10}, {1, 2}, {1, 0.5}, 0.7, {1.799810119285, 0}},
            {2, {1, 100}, {1, 4.641588833612779}, {0.1, 0.1}, 0.5, {13.532707243808, 0}},
            {3, {1, 100, 500}, {1, 4.641588833612779, 7.937005259840998}, {0.1, 0.1, 0.1}, 0.5, {23.0095, 38.3740}}};
  for (int j = 0; j < 3; j++) {
    const int M = c[j].M;
    gran_mixture *mix = make(M, c[j].m, c[j].s, c[j].n, c[j].eps);
    double T0[3], a2[3], a3[3], tau0, z[3], d2[3], d3[3];
    GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_T1, 1.0, T0, a2, a3, &tau0));
    GRAN_ASSERT_OK(gran_theory_sonine2_rates(mix, T0, a2, a3, z, d2, d3));
    print_message("M = %d: T_k/T_1 = %.9f %.9f, a2 = %.5f %.5f %.5f, a3 = %.5f %.5f %.5f\n", M, T0[1],
                  M > 2 ? T0[2] : 0.0, a2[0], a2[1], M > 2 ? a2[2] : 0.0, a3[0], a3[1], M > 2 ? a3[2] : 0.0);
    GRAN_ASSERT_REL(T0[0], 1.0, 1e-15);
    for (int k = 0; k < M; k++) {
      GRAN_ASSERT_ABS(0.5 * z[k] * tau0, 1.0, 1e-11);
      GRAN_ASSERT_ABS(d2[k] * tau0, 0.0, 1e-10);
      GRAN_ASSERT_ABS(d3[k] * tau0, 0.0, 1e-10);
    }
    for (int k = 1; k < M; k++) GRAN_ASSERT_REL(T0[k], c[j].ratio[k - 1], j < 2 ? 1e-10 : 5e-6);
    gran_mixture_destroy(&mix);
  }
}

/* eps = 1: equipartition, a2 = a3 = 0; eps = 1 - 1e-9: a2, a3 = O(1e-9); two equal species = one species. */
static void test_limits(void **state) {
  (void)state;
  const double m[2] = {1, 7}, s[2] = {1, 1.9}, n[2] = {0.4, 0.2};
  gran_mixture *mix = make(2, m, s, n, 1.0);
  double T0[2], a2[2], a3[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 2.0, T0, a2, a3, &tau0));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(T0[k], 2.0, 1e-14);
    GRAN_ASSERT_ABS(a2[k], 0.0, 1e-14);
    GRAN_ASSERT_ABS(a3[k], 0.0, 1e-14);
  }
  assert_true(tau0 > 1e300);
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 1.0 - 1e-9));
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 2.0, T0, a2, a3, &tau0));
  for (int k = 0; k < 2; k++) {
    assert_true(fabs(a2[k]) < 1e-8 && fabs(a3[k]) < 1e-8);
    GRAN_ASSERT_REL(T0[k], 2.0, 1e-8);
  }
  gran_mixture_destroy(&mix);
  const double me[2] = {3, 3}, se[2] = {0.8, 0.8}, ne[2] = {0.1, 0.3}, n1 = 0.4;
  gran_mixture *two = make(2, me, se, ne, 0.6), *one = make(1, me, se, &n1, 0.6);
  double T1, b2, b3, t1;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(two, GRAN_HCS_NORM_MEAN, 1.0, T0, a2, a3, &tau0));
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(one, GRAN_HCS_NORM_MEAN, 1.0, &T1, &b2, &b3, &t1));
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(T0[k], T1, 1e-12);
    GRAN_ASSERT_ABS(a2[k], b2, 1e-12);
    GRAN_ASSERT_ABS(a3[k], b3, 1e-12);
  }
  GRAN_ASSERT_REL(tau0, t1, 1e-12);
  /* the HCS at a mean temperature of 1e-60: the same a2, a3 */
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(one, GRAN_HCS_NORM_MEAN, 1e-60, &T1, &a2[0], &a3[0], &tau0));
  GRAN_ASSERT_REL(T1, 1e-60, 1e-14);
  GRAN_ASSERT_ABS(a2[0], b2, 1e-12);
  GRAN_ASSERT_ABS(a3[0], b3, 1e-12);
  GRAN_ASSERT_REL(tau0, t1 * 1e30, 1e-12);
  gran_mixture_destroy(&two);
  gran_mixture_destroy(&one);
}

static void test_refusals(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5}, T[2] = {1, 2}, a2[2] = {0, 0}, bad[2] = {0, 1.0};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double T0[2], z[2];
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine2(mix, 7, 1.0, T0, NULL, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, -1.0, T0, NULL, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 1.0, NULL, NULL, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_sonine2_rates(mix, T, a2, bad, z, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a3'[1]"));
  GRAN_ASSERT_ERR(gran_theory_sonine2_rates(mix, T, a2, NULL, z, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine2(NULL, GRAN_HCS_NORM_MEAN, 1.0, T0, NULL, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 1.0, T0, NULL, NULL, NULL), GRAN_ERR_DOMAIN);
  GRAN_ASSERT_ERR(gran_theory_sonine2_rates(mix, T, a2, a2, z, NULL, NULL), GRAN_ERR_DOMAIN);
  gran_mixture_destroy(&mix);
  /* 129 species: beyond the dense solve */
  enum { MB = 129 };
  double mb[MB], sb[MB], nb[MB], Tb[MB];
  for (int k = 0; k < MB; k++) mb[k] = 1 + k, sb[k] = 1, nb[k] = 0.01;
  mix = make(MB, mb, sb, nb, 0.8);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 1.0, Tb, NULL, NULL, NULL), GRAN_ERR_DOMAIN);
  assert_non_null(strstr(gran_last_error_message(), "129 species"));
  gran_mixture_destroy(&mix);
}

/* gran_theory_hcs_sonine_n: nmax = 2 is gran_theory_hcs_approx(GRAN_THEORY_SONINE), nmax = 3 gran_theory_hcs_sonine2
 * (the same linearisation, a separate code); nmax = 5 against docs/tools/sonine_order_n.py 5 (its 4 printed digits) */
static void test_hierarchy(void **state) {
  (void)state;
  const double m[2] = {1, 100}, s[2] = {1, 4.641588833612779}, n[2] = {0.1, 0.1};
  gran_mixture *mix = make(2, m, s, n, 0.5);
  double T1[2], b2[2], t1, T2[2], c2[2], c3[2], t2, T[2], a[8], tau;
  GRAN_ASSERT_OK(gran_theory_hcs_approx(mix, GRAN_THEORY_SONINE, GRAN_HCS_NORM_T1, 1.0, T1, b2, &t1));
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 2, GRAN_HCS_NORM_T1, 1.0, T, a, &tau));
  GRAN_ASSERT_REL(T[1], T1[1], 1e-11);
  for (int k = 0; k < 2; k++) GRAN_ASSERT_ABS(a[k], b2[k], 1e-11);
  GRAN_ASSERT_REL(tau, t1, 1e-11);
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_T1, 1.0, T2, c2, c3, &t2));
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 3, GRAN_HCS_NORM_T1, 1.0, T, a, &tau));
  GRAN_ASSERT_REL(T[1], T2[1], 1e-11);
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_ABS(a[2 * k], c2[k], 1e-11);
    GRAN_ASSERT_ABS(a[2 * k + 1], c3[k], 1e-11);
  }
  GRAN_ASSERT_REL(tau, t2, 1e-11);
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 5, GRAN_HCS_NORM_T1, 1.0, T, a, &tau));
  print_message("nmax 5, binary m = 1, 100: T2/T1 = %.6f, a = %.5f %.5f %.5f %.5f | %.5f %.5f %.5f %.5f\n", T[1], a[0],
                a[1], a[2], a[3], a[4], a[5], a[6], a[7]);
  const double ar[8] = {-0.0007, -0.0312, -0.0081, -0.0129, 0.0457, -0.0137, 0.0085, -0.0120};
  GRAN_ASSERT_REL(T[1], 13.4737, 4e-6);
  for (int j = 0; j < 8; j++) GRAN_ASSERT_ABS(a[j], ar[j], 6e-5);
  gran_mixture_destroy(&mix);
  const double m1 = 1, s1 = 1, n1 = 0.1, ar1[4] = {0.0466, -0.0145, 0.0090, -0.0135};
  mix = make(1, &m1, &s1, &n1, 0.5);
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 5, GRAN_HCS_NORM_MEAN, 1.0, T, a, &tau));
  for (int j = 0; j < 4; j++) GRAN_ASSERT_ABS(a[j], ar1[j], 6e-5);
  /* eps = 1: equipartition, all a_q = 0 */
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 1.0));
  GRAN_ASSERT_OK(gran_theory_hcs_sonine_n(mix, 4, GRAN_HCS_NORM_MEAN, 2.0, T, a, &tau));
  GRAN_ASSERT_REL(T[0], 2.0, 1e-15);
  for (int j = 0; j < 3; j++) GRAN_ASSERT_ABS(a[j], 0.0, 1e-15);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine_n(mix, 1, GRAN_HCS_NORM_MEAN, 1.0, T, a, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'nmax' = 1"));
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine_n(mix, 6, GRAN_HCS_NORM_MEAN, 1.0, T, a, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine_n(mix, 4, GRAN_HCS_NORM_MEAN, 1.0, NULL, a, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine_n(mix, 4, GRAN_HCS_NORM_MEAN, 1.0, T, a, NULL), GRAN_ERR_DOMAIN);
  gran_mixture_destroy(&mix);
  enum { MB = 65 };
  double mb[MB], sb[MB], nb[MB], Tb[MB];
  for (int k = 0; k < MB; k++) mb[k] = 1 + k, sb[k] = 1, nb[k] = 0.01;
  mix = make(MB, mb, sb, nb, 0.8);
  GRAN_ASSERT_ERR(gran_theory_hcs_sonine_n(mix, 4, GRAN_HCS_NORM_MEAN, 1.0, Tb, NULL, NULL), GRAN_ERR_DOMAIN);
  assert_non_null(strstr(gran_last_error_message(), "65 species"));
  gran_mixture_destroy(&mix);
}

/* gran_theory_temperatures_sonine2: from the second Sonine HCS it stays there (T_k/T_1, a2, a3 constant, T on Haff's
 * law with the HCS tau0); from a Maxwellian start it relaxes to the HCS (ratios, a2, a3; one species: the monodisperse
 * values, then Haff's law); eps = 1: a2 = a3 = 0 and constant T at equal temperatures, energy conserved and
 * equipartition from unequal ones; eps = 1 - 1e-4: the Maxwellian trajectory to O(1 - eps). */
static void test_trajectory(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double T0[2], a2h[2], a3h[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_T1, 1.0, T0, a2h, a3h, &tau0));
  enum { NT = 5 };
  /* the times in any order (the output rows follow t) */
  const double f[NT] = {10.0, 0.0, 1.0, 100.0, 1e3};
  double t[NT], T[2 * NT], a2[2 * NT], a3[2 * NT];
  for (int j = 0; j < NT; j++) t[j] = f[j] * tau0;
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(mix, T0, a2h, a3h, NT, t, 1e-10, T, a2, a3));
  for (int j = 0; j < NT; j++) {
    const double haff = 1.0 / ((1 + f[j]) * (1 + f[j]));
    for (int k = 0; k < 2; k++) {
      GRAN_ASSERT_REL(T[2 * j + k], T0[k] * haff, 1e-8);
      GRAN_ASSERT_ABS(a2[2 * j + k], a2h[k], 1e-10);
      GRAN_ASSERT_ABS(a3[2 * j + k], a3h[k], 1e-10);
    }
    GRAN_ASSERT_REL(T[2 * j + 1] / T[2 * j], T0[1] / T0[0], 1e-9);
  }
  /* a Maxwellian start far from the HCS ratio relaxes to it (1.799810119 against 1.806 of the first level) */
  const double Ts[2] = {1.0, 5.0}, tl[2] = {3e3 * tau0, 1e4 * tau0};
  double Tl[4], b2[4], b3[4];
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(mix, Ts, NULL, NULL, 2, tl, 1e-10, Tl, b2, b3));
  print_message("Maxwellian start: T2/T1 = %.10f (HCS %.10f), a2 = %.6f %.6f, a3 = %.6f %.6f\n", Tl[3] / Tl[2],
                T0[1] / T0[0], b2[2], b2[3], b3[2], b3[3]);
  GRAN_ASSERT_REL(Tl[3] / Tl[2], T0[1] / T0[0], 1e-7);
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_ABS(b2[2 + k], a2h[k], 1e-7);
    GRAN_ASSERT_ABS(b3[2 + k], a3h[k], 1e-7);
  }
  /* and cools by Haff's law with the HCS tau0 at its temperature: T_1(t2) = T_1(t1)/(1 + (t2 - t1)/tau0(t1))^2 */
  const double tau1 = tau0 / sqrt(Tl[0]), dt = (tl[1] - tl[0]) / tau1;
  GRAN_ASSERT_REL(Tl[2], Tl[0] / ((1 + dt) * (1 + dt)), 1e-6);
  /* the first level is another trajectory: a3 = 0 moves T_2/T_1 by 0.36 % */
  double T1[2], c2[2];
  GRAN_ASSERT_OK(gran_theory_temperatures_approx(mix, GRAN_THEORY_SONINE, Ts, NULL, 1, &tl[1], 1e-10, T1, c2));
  assert_true(T1[1] / T1[0] / (Tl[3] / Tl[2]) - 1 > 3e-3);
  /* a2, a3 may be NULL */
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(mix, Ts, NULL, NULL, 2, tl, 1e-10, b2, NULL, NULL));
  for (int j = 0; j < 4; j++) GRAN_ASSERT_REL(b2[j], Tl[j], 1e-14);
  gran_mixture_destroy(&mix);

  /* one species (eps = 0.5): a2, a3 of the monodisperse second Sonine HCS after relaxation */
  const double m1 = 2.5, s1 = 0.7, n1 = 0.3;
  gran_mixture *one = make(1, &m1, &s1, &n1, 0.5);
  double Th, ah, bh, th;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(one, GRAN_HCS_NORM_MEAN, 1.0, &Th, &ah, &bh, &th));
  const double T1s = 1.0, to[2] = {1e3 * th, 1e4 * th};
  double To[2], ao[2], bo[2];
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(one, &T1s, NULL, NULL, 2, to, 1e-10, To, ao, bo));
  print_message("one species: a2 = %.12f (HCS %.12f), a3 = %.12f (HCS %.12f)\n", ao[1], ah, bo[1], bh);
  GRAN_ASSERT_ABS(ao[1], 0.044993978002290, 1e-8);
  GRAN_ASSERT_ABS(bo[1], -0.017684168615936, 1e-8);
  const double tau2 = th / sqrt(To[0]), d2 = (to[1] - to[0]) / tau2;
  GRAN_ASSERT_REL(To[1], To[0] / ((1 + d2) * (1 + d2)), 1e-6);
  gran_mixture_destroy(&one);

  /* eps = 1 */
  const double me[2] = {1, 7}, se[2] = {1, 1.9}, ne[2] = {0.4, 0.2};
  gran_mixture *el = make(2, me, se, ne, 1.0);
  const double Te[2] = {2.0, 2.0}, tt[3] = {1.0, 10.0, 1e3};
  double Tt[6], e2[6], e3[6];
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(el, Te, NULL, NULL, 3, tt, 1e-10, Tt, e2, e3));
  for (int j = 0; j < 6; j++) {
    GRAN_ASSERT_REL(Tt[j], 2.0, 1e-12);
    GRAN_ASSERT_ABS(e2[j], 0.0, 1e-14);
    GRAN_ASSERT_ABS(e3[j], 0.0, 1e-14);
  }
  /* unequal temperatures: energy conserved, equipartition and a2, a3 -> 0 (they are not 0 while T_1 != T_2) */
  const double Tu[2] = {1.0, 4.0}, E0 = ne[0] * Tu[0] + ne[1] * Tu[1], Teq = E0 / (ne[0] + ne[1]);
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(el, Tu, NULL, NULL, 3, tt, 1e-10, Tt, e2, e3));
  for (int j = 0; j < 3; j++) GRAN_ASSERT_REL(ne[0] * Tt[2 * j] + ne[1] * Tt[2 * j + 1], E0, 1e-9);
  assert_true(fabs(e2[0]) > 1e-4);
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_REL(Tt[4 + k], Teq, 1e-9);
    GRAN_ASSERT_ABS(e2[4 + k], 0.0, 1e-9);
    GRAN_ASSERT_ABS(e3[4 + k], 0.0, 1e-9);
  }
  /* eps = 1 - 1e-4: the Maxwellian trajectory to O(1 - eps) over a cooling time, a2, a3 = O(1 - eps) */
  GRAN_ASSERT_OK(gran_mixture_set_restitution(el, 1.0 - 1e-4));
  const double tc[2] = {1e3, 1e4};
  double Tc[4], Tm[4], f2[4], f3[4];
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(el, Te, NULL, NULL, 2, tc, 1e-10, Tc, f2, f3));
  GRAN_ASSERT_OK(gran_theory_temperatures(el, Te, 2, tc, 1e-10, Tm));
  print_message("eps = 1 - 1e-4: T/T_Maxwellian - 1 = %.3g, a2 = %.3g, a3 = %.3g at t = 1e4 (T/T0 = %.3f)\n",
                Tc[3] / Tm[3] - 1, f2[3], f3[3], Tc[3] / 2.0);
  assert_true(Tc[3] < 1.0); /* cooled by more than a factor 2 */
  for (int j = 0; j < 4; j++) {
    GRAN_ASSERT_REL(Tc[j], Tm[j], 1e-3);
    assert_true(fabs(f2[j]) < 1e-3 && fabs(f3[j]) < 1e-3);
  }
  gran_mixture_destroy(&el);
}

/* refusals of gran_theory_temperatures_sonine2, and the breakdown |a| >= 1 named with its species and time */
static void test_trajectory_refusals(void **state) {
  (void)state;
  const double m[2] = {1, 10}, s[2] = {1, 2}, n[2] = {1, 0.5}, T0[2] = {1, 2}, bad[2] = {0, 1.0}, t = 1.0;
  const double tn = -1.0;
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double T[2], a2[2];
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(NULL, T0, NULL, NULL, 1, &t, 1e-8, T, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, NULL, NULL, NULL, 1, &t, 1e-8, T, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, NULL, bad, 1, &t, 1e-8, T, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a30'[1]"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, bad, NULL, 1, &t, 1e-8, T, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a20'[1]"));
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, -1, &t, 1e-8, T, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, 1, &tn, 1e-8, T, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, 1, &t, 0.0, T, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, 1, &t, 1e-8, NULL, NULL, NULL), GRAN_ERR_ARG);
  /* ntimes = 0: nothing to do, nothing written */
  a2[0] = 7.0;
  GRAN_ASSERT_OK(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, 0, NULL, 1e-8, NULL, a2, NULL));
  assert_true(a2[0] == 7.0);
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(mix, T0, NULL, NULL, 1, &t, 1e-8, T, NULL, NULL), GRAN_ERR_DOMAIN);
  gran_mixture_destroy(&mix);
  /* a start far from the HCS (a2 = -0.9, a3 = 0.99, eps = 0.1): a3 passes 1 on the way (at t = 0.011) */
  const double m1 = 1, s1 = 1, n1 = 1, T1 = 1, b2 = -0.9, b3 = 0.99, tl = 100.0;
  gran_mixture *one = make(1, &m1, &s1, &n1, 0.1);
  double Tb, ab;
  GRAN_ASSERT_ERR(gran_theory_temperatures_sonine2(one, &T1, &b2, &b3, 1, &tl, 1e-8, &Tb, &ab, NULL), GRAN_ERR_DOMAIN);
  const char *msg = gran_last_error_message();
  print_message("%s\n", msg);
  assert_non_null(strstr(msg, "species 0"));
  assert_non_null(strstr(msg, "at t = "));
  gran_mixture_destroy(&one);
}

/* gran_theory_msd_sonine2: (1) from the second Sonine HCS the MSD grows as 6 D_k(0) tau0 log(1 + t/tau0) at
 * late times, D_k(0) the two-moment diffusion coefficient at the HCS (gran_theory_diffusion_approx with its a2 and
 * zeta_k = 2/tau0): the trajectory, its cooling rate and the quadrature against the closed form; (2) an elastic
 * mixture at equipartition (a2 = a3 = 0, zeta = 0 all along) gives gran_theory_msd_sonine's MSD; (3) refusals. */
static void test_msd(void **state) {
  (void)state;
  const double m[2] = {1, 4}, s[2] = {1, 1.5}, n[2] = {0.1, 0.05};
  gran_mixture *mix = make(2, m, s, n, 0.7);
  double T0[2], a2h[2], a3h[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs_sonine2(mix, GRAN_HCS_NORM_MEAN, 1.0, T0, a2h, a3h, &tau0));
  const double t[2] = {50.0 * tau0, 500.0 * tau0}, zeta[2] = {2.0 / tau0, 2.0 / tau0};
  double msd[4], tot[2], D[2];
  GRAN_ASSERT_OK(gran_theory_msd_sonine2(mix, T0, a2h, a3h, 1, 2, t, 1e-9, msd, tot));
  GRAN_ASSERT_OK(gran_theory_diffusion_approx(mix, GRAN_THEORY_SONINE, T0, a2h, zeta, D));
  const double dL = tau0 * (log1p(t[1] / tau0) - log1p(t[0] / tau0));
  for (int k = 0; k < 2; k++) {
    const double slope = (msd[2 + k] - msd[k]) / (6.0 * dL);
    print_message("second Sonine HCS, species %d: late MSD slope / 6 D(0) tau0 - 1 = %.3g\n", k + 1, slope / D[k] - 1);
    GRAN_ASSERT_REL(slope, D[k], 1e-6);
  }
  for (int j = 0; j < 2; j++)
    GRAN_ASSERT_REL(tot[j], (n[0] * msd[2 * j] + n[1] * msd[2 * j + 1]) / (n[0] + n[1]), 1e-14);
  /* a2 out of the correlation is another MSD (the partners' f_i and the weight f_k) */
  double msd0[4];
  GRAN_ASSERT_OK(gran_theory_msd_sonine2(mix, T0, a2h, a3h, 0, 2, t, 1e-9, msd0, NULL));
  print_message("a2 out of the correlation: MSD_1 / MSD_1(a2 in) - 1 = %.3g (a2 = %.4f %.4f)\n", msd0[2] / msd[2] - 1,
                a2h[0], a2h[1]);
  assert_true(fabs(msd0[2] / msd[2] - 1) > 1e-5);
  /* refusals */
  const double bad[2] = {0.0, -1.0};
  GRAN_ASSERT_ERR(gran_theory_msd_sonine2(mix, T0, NULL, bad, 1, 2, t, 1e-9, msd, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a30'[1]"));
  GRAN_ASSERT_ERR(gran_theory_msd_sonine2(mix, T0, bad, NULL, 1, 2, t, 1e-9, msd, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'a20'[1]"));
  GRAN_ASSERT_ERR(gran_theory_msd_sonine2(mix, T0, NULL, NULL, 2, 2, t, 1e-9, msd, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "correlation_a2"));
  GRAN_ASSERT_ERR(gran_theory_msd_sonine2(mix, NULL, NULL, NULL, 1, 2, t, 1e-9, msd, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_msd_sonine2(mix, T0, NULL, NULL, 1, 2, t, 1e-9, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  GRAN_ASSERT_ERR(gran_theory_msd_sonine2(mix, T0, NULL, NULL, 1, 2, t, 1e-9, msd, NULL), GRAN_ERR_DOMAIN);
  gran_mixture_destroy(&mix);
  /* eps = 1 at equipartition: the first and second levels are one MSD */
  const double me[2] = {1, 7}, se[2] = {1, 1.9}, ne[2] = {0.4, 0.2}, Te[2] = {2.0, 2.0}, te[3] = {0.1, 10.0, 1e3};
  gran_mixture *el = make(2, me, se, ne, 1.0);
  double m1[6], m2[6];
  for (int ca = 0; ca < 2; ca++) {
    GRAN_ASSERT_OK(gran_theory_msd_sonine(el, Te, NULL, ca, 3, te, 1e-9, m1, NULL));
    GRAN_ASSERT_OK(gran_theory_msd_sonine2(el, Te, NULL, NULL, ca, 3, te, 1e-9, m2, NULL));
    for (int j = 0; j < 6; j++) GRAN_ASSERT_REL(m2[j], m1[j], 1e-8);
  }
  gran_mixture_destroy(&el);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_monodisperse), cmocka_unit_test(test_rates),
                                     cmocka_unit_test(test_hcs), cmocka_unit_test(test_limits),
                                     cmocka_unit_test(test_refusals), cmocka_unit_test(test_hierarchy),
                                     cmocka_unit_test(test_trajectory), cmocka_unit_test(test_trajectory_refusals),
                                     cmocka_unit_test(test_msd)};
  return cmocka_run_group_tests_name("t418-sonine2", tests, NULL, NULL);
}
