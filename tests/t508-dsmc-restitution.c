/* t508-dsmc-restitution.c - restitution models and pair parameters in the DSMC engine: viscoelastic
 * cooling against docs/physics.md, "Oracles for tests" and the theory module, the per-pair formula
 * path used for many species, restitution matrices, contact values g2 per pair. */
#include "dsmc_util.h"

/* Monodisperse viscoelastic gas, beta = 0.01, n = 0.1, N = 2e4 (4e3 under ASan), T(0) = 1:
 * T = T0 [1 + (3/5) B T0^(3/5) t]^(-5/3), B = 6.5536217 beta n sigma^2 m^(-3/5).
 * That law is the leading order in beta; the next order (x^2 = beta |v_n|^(1/5) ~ 1%) makes DSMC
 * cool 1.6% slower by t = 400 (measured, every selector), so the allowance is 2.5%. The theory
 * module (A7 with all 20 terms, gran_theory_temperatures) must agree to 0.5%. Statistical part:
 * T(t)/T(0) (normalised by the sampled T(0)) scatters over seeds by 1e-3 relative at N = 2e4
 * (measured; 1/sqrt(N) scaling): 4 standard errors. The law must also be told apart from a
 * constant-eps Haff law with the same initial cooling rate: at t = 400 they differ by 9.6%, more
 * than twice the tolerance. */
static void visco(int sel) {
  const int64_t N = DSMC_ASAN ? 4000 : 20000;
  const double beta = 0.01, n = 0.1;
  gran_mixture *mix = dsmc_mono(n, 1.0);
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, beta));
  gran_dsmc_options o = dsmc_opts(sel, 5, (double)N / n, 0);
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &sim)); /* T_k(0) = 1: no HCS for viscoelastic */
  double ek, e0, ed;
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
  double T0 = 2.0 * e0 / (3.0 * (double)N);
  GRAN_ASSERT_SIGMA(T0, 1.0, sqrt(2.0 / (3.0 * (double)N)), 5);
  const double B = 6.5536217 * beta * n;
  const double ts[5] = {25, 50, 100, 200, 400};
  double Tth[5];
  GRAN_ASSERT_OK(gran_theory_temperatures(mix, &T0, 5, ts, 1e-8, Tth));
  const double se = 1e-3 * sqrt(20000.0 / (double)N);
  const double tol_law = 4 * se + 0.025;
  double T = 0, law = 0;
  for (int q = 0; q < 5; q++) {
    GRAN_ASSERT_OK(gran_dsmc_advance(sim, ts[q]));
    GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
    GRAN_ASSERT_REL(e0 - ed, ek, 1e-12);
    T = 2.0 * ek / (3.0 * (double)N);
    law = T0 * pow(1.0 + 0.6 * B * pow(T0, 0.6) * ts[q], -5.0 / 3.0);
    print_message("selector %d, t = %g: T/T0 = %.5f, leading-order law %.5f (ratio %.4f), theory A7 %.5f (ratio %.4f)\n",
                  sel, ts[q], T / T0, law / T0, T / law, Tth[q] / T0, T / Tth[q]);
    GRAN_ASSERT_REL(T, law, tol_law);
    GRAN_ASSERT_REL(T, Tth[q], 4 * se + 0.005);
  }
  /* Haff with the same initial rate dT/dt = -B T0^(8/5): T = T0 / (1 + t/tau)^2, tau = 2 T0^(-3/5)/B */
  const double haff = T0 / pow(1.0 + 400.0 * B * pow(T0, 0.6) / 2.0, 2.0);
  assert_true(fabs(haff / law - 1.0) > 2 * tol_law);
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
}

static void test_viscoelastic_cooling(void **state) {
  (void)state;
  visco(GRAN_SELECTOR_LOWRANK);
  visco(GRAN_SELECTOR_BIRD);
  visco(GRAN_SELECTOR_LOWRANK_PAPER);
}

/* Many species (M = 600 > the 512 up to which pair tables are cached) with a material (A, Y, nu):
 * the hot loop evaluates beta_ik from the mixture's formula. Only species 1 is populated; its
 * cooling must follow the theory for a one-species gas with beta = beta_11 (0.5% + 4 se). */
static void test_viscoelastic_formula_path(void **state) {
  (void)state;
  const int64_t M = 600, N = DSMC_ASAN ? 3000 : 15000;
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(M, 1.0, 1.0, 0.1, 3.0, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic_material(mix, 1e-3, 1e3, 0.3));
  double beta11;
  GRAN_ASSERT_OK(gran_mixture_pair(mix, 0, 0, NULL, &beta11, NULL));
  assert_true(beta11 > 0.001 && beta11 < 0.1);
  int64_t *counts = (int64_t *)calloc((size_t)M, sizeof(int64_t));
  counts[0] = N;
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 9, (double)N / 0.1, 0);
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, counts, NULL, &o, &sim));
  gran_mixture *one = dsmc_mono(0.1, 1.0);
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(one, beta11));
  double ek, e0, ed, Tth;
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
  double T0 = 2.0 * e0 / (3.0 * (double)N), t = 300.0;
  GRAN_ASSERT_OK(gran_theory_temperatures(one, &T0, 1, &t, 1e-8, &Tth));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, t));
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
  const double T = 2.0 * ek / (3.0 * (double)N);
  print_message("M = 600, beta_11 = %.5f: T/T0 = %.5f, theory %.5f\n", beta11, T / T0, Tth / T0);
  assert_true(T / T0 < 0.9);
  GRAN_ASSERT_REL(T, Tth, 4 * sqrt(2.0 / (3.0 * (double)N)) + 0.005);
  free(counts);
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&one);
  gran_mixture_destroy(&mix);
}

/* A restitution matrix with every entry 0.7 runs the table path and must cool exactly like
 * eps = 0.7 (constant path): the same random stream and the same eps give identical
 * trajectories, so ln(E/E0) after 20 collisions per particle of a binary mixture (m = 1, 3) is
 * bit-equal for 4 seeds. A matrix with eps_12 = 0.3 must cool measurably faster (more than
 * 10 standard errors of the seed scatter). Haff in c: ln(E/E0) = -(1 - eps^2) c / 3 within 5%. */
static void test_matrix_equals_constant(void **state) {
  (void)state;
  double m[2] = {1.0, 3.0}, s[2] = {1.0, 1.3}, n[2] = {0.06, 0.04};
  double epsm[4] = {0.7, 0.7, 0.7, 0.7};
  gran_mixture *a, *b;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &a));
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &b));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(a, 0.7));
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(b, epsm));
  const int R = 4;
  const int64_t N = 5000;
  double x[3][4];
  gran_mixture *c;
  double epsc[4] = {0.7, 0.3, 0.3, 0.7};
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &c));
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(c, epsc));
  gran_mixture *mixes[3] = {a, b, c};
  for (int w = 0; w < 3; w++)
    for (int r = 0; r < R; r++) {
      gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 50 + (uint64_t)r, (double)N / 0.1, 0);
      gran_dsmc *sim;
      double T0[2] = {1.0, 1.0}, ek, e0, ed;
      GRAN_ASSERT_OK(gran_dsmc_create(mixes[w], NULL, T0, &o, &sim));
      GRAN_ASSERT_OK(gran_dsmc_advance_collisions(sim, 10 * N));
      GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
      x[w][r] = log(ek / e0);
      gran_dsmc_destroy(&sim);
    }
  double ma, sa, mc, sc;
  dsmc_mean_se(x[0], R, &ma, &sa);
  dsmc_mean_se(x[2], R, &mc, &sc);
  print_message("ln(E/E0) after c = 20: constant %.5f (se %.1e), matrix of 0.7 %.5f, eps_12 = 0.3: %.5f\n", ma, sa,
                x[1][0], mc);
  for (int r = 0; r < R; r++) assert_true(x[0][r] == x[1][r]);
  assert_true(mc < ma - 10 * sqrt(sa * sa + sc * sc));
  GRAN_ASSERT_REL(ma, -(1 - 0.49) / 3.0 * 20.0, 0.05);
  gran_mixture_destroy(&c);
  gran_mixture_destroy(&a);
  gran_mixture_destroy(&b);
}

/* Contact values per pair scale the pair rates: elastic binary mixture (equal masses and sizes),
 * g2 = [[1, 1.5], [1.5, 2]]: collisions of pair (i,k) per unit time are g2_ik times those of
 * test_pair_rates in t503. 4 standard errors from batch means. */
static void test_g2_matrix(void **state) {
  (void)state;
  double m[2] = {1.0, 1.0}, s[2] = {1.0, 1.0}, n[2] = {0.05, 0.05}, g2[4] = {1.0, 1.5, 1.5, 2.0};
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_g2_matrix(mix, g2));
  for (int sel = 0; sel < 2; sel++) {
    const double V = 1e5, tw = DSMC_ASAN ? 2.0 : 8.0;
    gran_dsmc_options o = dsmc_opts(sel, 60, V, GRAN_OBSERVE_COLLISION_COUNTS);
    gran_dsmc *sim;
    double T0[2] = {1.0, 1.0};
    GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
    int64_t N[2], cc[4], prev[4] = {0, 0, 0, 0};
    GRAN_ASSERT_OK(gran_dsmc_counts(sim, N));
    double ek, e0, ed;
    GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
    const double T = 2.0 * e0 / (3.0 * (double)(N[0] + N[1]));
    const double gbar = sqrt(16.0 * T / M_PI); /* mean relative speed, m = 1 */
    double r[4][16];
    for (int w = 0; w < 16; w++) {
      GRAN_ASSERT_OK(gran_dsmc_advance(sim, tw * (w + 1)));
      GRAN_ASSERT_OK(gran_dsmc_collision_counts(sim, cc));
      for (int q = 0; q < 4; q++) {
        const int i = q / 2, k = q % 2;
        const double pairs = i == k ? 0.5 * (double)N[i] * (double)(N[i] - 1) : (double)N[i] * (double)N[k];
        r[q][w] = (double)(cc[q] - prev[q]) / (pairs / V * M_PI * gbar * g2[q] * tw);
        prev[q] = cc[q];
      }
    }
    for (int q = 0; q < 4; q++) {
      if (q == 2) continue; /* symmetric */
      double mean, se;
      dsmc_mean_se(r[q], 16, &mean, &se);
      print_message("selector %d, pair %d-%d (g2 %.1f): collisions / theory = %.4f (se %.1e)\n", sel, q / 2 + 1,
                    q % 2 + 1, g2[q], mean, se);
      GRAN_ASSERT_SIGMA(mean, 1.0, se, 4);
      assert_true(se < 0.01);
    }
    gran_dsmc_destroy(&sim);
  }
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_viscoelastic_cooling),
      cmocka_unit_test(test_viscoelastic_formula_path),
      cmocka_unit_test(test_matrix_equals_constant),
      cmocka_unit_test(test_g2_matrix),
  };
  return cmocka_run_group_tests_name("t508-dsmc-restitution", tests, NULL, NULL);
}
