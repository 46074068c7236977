/* t408-aggregation.c - temperature-dependent Smoluchowski kinetics (src/theory/aggregation.cpp):
 * Maxwellian stick/shatter fractions (closed forms and Monte Carlo), the E_agg = 0, E_frag = inf
 * limit against the mixture theory (gran_theory_temperatures), the constant-kernel solution
 * n_k = n0 tau^(k-1)/(1+tau)^(k+1), mass conservation to 1e-12 with truncation, first-step rates,
 * 1e4 sizes, and bad inputs. */
#include "granary_test.h"

static const double PI = 3.14159265358979323846;

/* Closed forms (docs/physics.md, "Aggregation and fragmentation: fractions and energy carried"):
 * P(E < W) = 1 - (1 + q) e^-q, P(E_n > W) = e^-w (w >= q); overlapping thresholds
 * (E_frag < E_agg): (1 + q - w) e^-q. 1e-14. */
static void test_fractions_closed(void **state) {
  (void)state;
  double fs, ff;
  const double mi = 1, mj = 3, Ti = 0.7, Tj = 2.0, Tij = (mj * Ti + mi * Tj) / (mi + mj);
  GRAN_ASSERT_OK(gran_theory_agg_fractions(mi, mj, Ti, Tj, 0.5, 4.0, &fs, &ff));
  double q = 0.5 / Tij, w = 4.0 / Tij;
  GRAN_ASSERT_REL(fs, 1 - (1 + q) * exp(-q), 1e-14);
  GRAN_ASSERT_REL(ff, exp(-w), 1e-14);
  GRAN_ASSERT_OK(gran_theory_agg_fractions(mi, mj, Ti, Tj, 3.0, 1.0, &fs, &ff));
  q = 3.0 / Tij;
  w = 1.0 / Tij;
  GRAN_ASSERT_REL(fs, 1 - (1 + q) * exp(-q), 1e-14);
  GRAN_ASSERT_REL(ff, (1 + q - w) * exp(-q), 1e-14);
  /* small q: series branch, q^2/2 (1 - 2q/3 + ...) */
  GRAN_ASSERT_OK(gran_theory_agg_fractions(1, 1, 1, 1, 1e-6, INFINITY, &fs, &ff));
  GRAN_ASSERT_REL(fs, 0.5e-12 * (1 - 2e-6 / 3), 1e-11);
  GRAN_ASSERT_REL(ff, 0.0, 0.0);
  GRAN_ASSERT_OK(gran_theory_agg_fractions(1, 1, 1, 1, 0, 0, &fs, &ff));
  GRAN_ASSERT_REL(fs, 0.0, 0.0);
  GRAN_ASSERT_REL(ff, 1.0, 1e-15);
}

/* Monte Carlo: Maxwellian v_i, v_j, e uniform, weight |g.e| (collision flux); fractions of the
 * weight with E < E_agg and with E_n > E_frag, E >= E_agg; overlapping thresholds. 4 standard errors
 * (ratio estimator), 4e5 samples, fixed seed. */
static void test_fractions_mc(void **state) {
  (void)state;
  const double mi = 1, mj = 4, Ti = 1.0, Tj = 2.5, Ea = 1.5, Ef = 0.8;
  const double mu = mi * mj / (mi + mj);
  double fs, ff;
  GRAN_ASSERT_OK(gran_theory_agg_fractions(mi, mj, Ti, Tj, Ea, Ef, &fs, &ff));
  gran_rng rng;
  GRAN_ASSERT_OK(gran_rng_seed(&rng, 408));
  enum { N = 400000 };
  static double z[6], e[3];
  double sw = 0, ss = 0, sf = 0, ss2 = 0, sf2 = 0, sw2s = 0, sw2f = 0;
  double *w = malloc(N * sizeof *w);
  char *cls = malloc(N);
  for (int s = 0; s < N; s++) {
    GRAN_ASSERT_OK(gran_rng_normal(&rng, 6, z));
    GRAN_ASSERT_OK(gran_rng_unit_vector3(&rng, 1, e));
    double g[3], g2 = 0, ge = 0;
    for (int c = 0; c < 3; c++) {
      g[c] = z[c] * sqrt(Ti / mi) - z[3 + c] * sqrt(Tj / mj);
      g2 += g[c] * g[c];
      ge += g[c] * e[c];
    }
    const double E = 0.5 * mu * g2, En = 0.5 * mu * ge * ge;
    w[s] = fabs(ge);
    cls[s] = E < Ea ? 1 : (En > Ef ? 2 : 0);
    sw += w[s];
    if (cls[s] == 1) ss += w[s];
    if (cls[s] == 2) sf += w[s];
  }
  const double ps = ss / sw, pf = sf / sw;
  for (int s = 0; s < N; s++) {
    const double is = cls[s] == 1, jf = cls[s] == 2;
    sw2s += w[s] * w[s] * (is - ps) * (is - ps);
    sw2f += w[s] * w[s] * (jf - pf) * (jf - pf);
  }
  (void)ss2;
  (void)sf2;
  GRAN_ASSERT_SIGMA(ps, fs, sqrt(sw2s) / sw, 4);
  GRAN_ASSERT_SIGMA(pf, ff, sqrt(sw2f) / sw, 4);
  free(w);
  free(cls);
}

static gran_mixture *kmers(int M, const double *n, double eps) {
  double m[64], s[64];
  for (int k = 0; k < M; k++) {
    m[k] = k + 1;
    s[k] = cbrt(k + 1.0);
  }
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  return mix;
}

/* E_agg = 0, E_frag = inf: densities stay, T_k(t) = the mixture theory (Eq. 13) to 1e-7
 * (both ODE solutions at rtol 1e-10). Unequal initial temperatures of sizes 1, 2, 3. */
static void test_mixture_limit(void **state) {
  (void)state;
  const double n[3] = {0.1, 0.03, 0.01}, T0[3] = {1.0, 3.0, 0.5};
  gran_mixture *mix = kmers(3, n, 0.8);
  double t[3] = {0.5, 3.0, 20.0}, nn[9], T[9], Tm[9], ov[9];
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, 0.0, INFINITY, 0.5, 3, t, 1e-10, nn, T, ov));
  GRAN_ASSERT_OK(gran_theory_temperatures(mix, T0, 3, t, 1e-10, Tm));
  for (int q = 0; q < 3; q++)
    for (int k = 0; k < 3; k++) {
      GRAN_ASSERT_REL(nn[3 * q + k], n[k], 1e-14);
      GRAN_ASSERT_REL(T[3 * q + k], Tm[3 * q + k], 1e-7);
    }
  GRAN_ASSERT_REL(ov[8], 0.0, 0.0);
  gran_mixture_destroy(&mix);
}

/* Constant kernel from monomers: n_k = n0 tau^(k-1)/(1+tau)^(k+1), tau = n0 K t/2; kmax = 400
 * (truncated mass at tau = 3 is ~(3/4)^400 ~ 1e-50 of the total); k <= 40: 1e-7; mass 1e-12. */
static void test_constant_kernel(void **state) {
  (void)state;
  enum { KM = 400 };
  static double n0[KM], n[3 * KM];
  const double N0 = 0.2, K = 1.5;
  n0[0] = N0;
  const double t[3] = {0.0, 2.0 / (N0 * K), 6.0 / (N0 * K)};
  double ov[9];
  GRAN_ASSERT_OK(gran_theory_smoluchowski_constant(KM, K, n0, 3, t, 1e-11, n, ov));
  for (int q = 0; q < 3; q++) {
    const double tau = N0 * K * t[q] / 2;
    double mass = 0;
    for (int k = 0; k < KM; k++) mass += (k + 1) * n[q * KM + k];
    GRAN_ASSERT_REL(mass + ov[3 * q + 1], N0, 1e-12);
    for (int k = 0; k < 40; k++)
      GRAN_ASSERT_REL(n[q * KM + k], N0 * pow(tau, k) / pow(1 + tau, k + 2), 1e-7);
  }
}

/* 1e4 sizes, constant kernel, tau = 1: every size up to 1e4 is a state variable; overflow mass is
 * exactly what the truncation removed; mass closes to 1e-12. Then kmax = 20 at tau = 3: a visible
 * overflow (the stated truncation), mass still closes to 1e-12. */
static void test_large_and_truncated(void **state) {
  (void)state;
  enum { KM = 10000 };
  double *n0 = calloc(KM, sizeof *n0), *n = calloc(KM, sizeof *n), ov[3];
  n0[0] = 1.0;
  const double t = 2.0;
  GRAN_ASSERT_OK(gran_theory_smoluchowski_constant(KM, 1.0, n0, 1, &t, 1e-10, n, ov));
  double mass = 0;
  for (int k = 0; k < KM; k++) mass += (k + 1) * n[k];
  GRAN_ASSERT_REL(mass + ov[1], 1.0, 1e-12);
  GRAN_ASSERT_REL(n[9], pow(1.0, 9) / pow(2.0, 11), 1e-7);
  const double t3 = 6.0;
  GRAN_ASSERT_OK(gran_theory_smoluchowski_constant(20, 1.0, n0, 1, &t3, 1e-10, n, ov));
  mass = 0;
  for (int k = 0; k < 20; k++) mass += (k + 1) * n[k];
  printf("kmax 20, tau 3: overflow mass fraction %.6g\n", ov[1]);
  assert_true(ov[1] > 0.01);
  GRAN_ASSERT_REL(mass + ov[1], 1.0, 1e-12);
  free(n0);
  free(n);
}

/* Ballistic kernels with sticking and fragmentation (E_frag > E_agg, and overlapping), 12 sizes
 * with overflow: mass sum k n_k + overflow closes to 1e-12 at every time; T_k finite and > 0. */
static void test_mass_ballistic(void **state) {
  (void)state;
  double n[12] = {0.2};
  gran_mixture *mix = kmers(12, n, 0.7);
  double T0[12];
  for (int k = 0; k < 12; k++) T0[k] = 1.0;
  const double t[4] = {1, 10, 50, 200};
  double nn[48], T[48], ov[12];
  const double cases[2][2] = {{1.5, 6.0}, {4.0, 2.0}};
  for (int c = 0; c < 2; c++) {
    GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, cases[c][0], cases[c][1], 0.6, 4, t, 1e-9, nn, T, ov));
    for (int q = 0; q < 4; q++) {
      double mass = 0;
      for (int k = 0; k < 12; k++) {
        mass += (k + 1) * nn[12 * q + k];
        assert_true(isfinite(T[12 * q + k]) && T[12 * q + k] >= 0);
      }
      GRAN_ASSERT_REL(mass + ov[3 * q + 1], 0.2, 1e-12);
    }
    assert_true(nn[1] > 0 && T[0] > 0);
  }
  gran_mixture_destroy(&mix);
}

/* First steps: monomers only, dn_1/dt = -n_1^2 K_11 P_stick (a shattering monomer pair gives two
 * monomers); K_11 = pi sigma^2 <|g|>, <|g|> = 4 sqrt(T/(pi m)). Over t = 1e-4 collision times:
 * relative error of the slope O(t nu) ~ 1e-4; tolerance 1e-3. The dimer energy per dimer is
 * E[CM energy | stick] = 3T/2 (equal temperatures, no V-g correlation): T_2(0+) = T. */
static void test_first_rates(void **state) {
  (void)state;
  double n[2] = {0.1, 0.0};
  gran_mixture *mix = kmers(2, n, 0.9);
  const double T0[2] = {2.0, 0.0}, Ea = 1.0, Ef = 5.0;
  double fs, ff;
  GRAN_ASSERT_OK(gran_theory_agg_fractions(1, 1, 2, 2, Ea, Ef, &fs, &ff));
  const double K = PI * 4 * sqrt(2.0 / PI), rate = 0.5 * 0.01 * K * fs;
  const double t = 1e-4 / (0.1 * K);
  double nn[2], T[2];
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, Ea, Ef, 0.5, 1, &t, 1e-12, nn, T, NULL));
  GRAN_ASSERT_REL((0.1 - nn[0]) / t, 2 * rate, 1e-3);
  GRAN_ASSERT_REL(nn[1] / t, rate, 1e-3);
  GRAN_ASSERT_REL(T[1], 2.0, 1e-3);
  /* hard case: E_agg huge, every collision sticks: dn_1/dt = -n_1^2 K_11 */
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, 1e12, INFINITY, 0.5, 1, &t, 1e-12, nn, T, NULL));
  GRAN_ASSERT_REL((0.1 - nn[0]) / t, 0.01 * K, 1e-3);
  gran_mixture_destroy(&mix);
}

static void test_bad_inputs(void **state) {
  (void)state;
  double fs, ff, out[4], T0[2] = {1, 1}, t = 1;
  GRAN_ASSERT_ERR(gran_theory_agg_fractions(0, 1, 1, 1, 1, 1, &fs, &ff), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_agg_fractions(1, 1, 0, 0, 1, 1, &fs, &ff), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_agg_fractions(1, 1, 1, 1, -1, 1, &fs, &ff), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_agg_fractions(1, 1, 1, 1, 1, NAN, &fs, &ff), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_agg_fractions(1, 1, 1, 1, 1, 1, NULL, &ff), GRAN_ERR_ARG);
  double n[2] = {0.1, 0.1};
  gran_mixture *mix = kmers(2, n, 0.9);
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0, -1, 1, 0.5, 1, &t, 1e-8, out, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0, 1, 1, 1.5, 1, &t, 1e-8, out, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0, 1, 1, 0.5, 1, &t, 1e-8, NULL, NULL, NULL), GRAN_ERR_ARG);
  double tb[2] = {2, 1};
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0, 1, 1, 0.5, 2, tb, 1e-8, out, NULL, NULL), GRAN_ERR_ARG);
  double T0z[2] = {0, 1};
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0z, 1, 1, 0.5, 1, &t, 1e-8, out, NULL, NULL), GRAN_ERR_ARG);
  gran_mixture_destroy(&mix);
  const double m[2] = {1, 3}, s[2] = {1, 1};
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0, 1, 1, 0.5, 1, &t, 1e-8, out, NULL, NULL), GRAN_ERR_DOMAIN);
  gran_mixture_destroy(&mix);
  const double m2[2] = {1, 2};
  GRAN_ASSERT_OK(gran_mixture_create(2, m2, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.1));
  GRAN_ASSERT_ERR(gran_theory_aggregation(mix, T0, 1, 1, 0.5, 1, &t, 1e-8, out, NULL, NULL), GRAN_ERR_UNSUPPORTED);
  gran_mixture_destroy(&mix);
  GRAN_ASSERT_ERR(gran_theory_smoluchowski_constant(0, 1, n, 1, &t, 1e-8, out, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_theory_smoluchowski_constant(2, -1, n, 1, &t, 1e-8, out, NULL), GRAN_ERR_ARG);
  double nz[2] = {0, 0};
  GRAN_ASSERT_ERR(gran_theory_smoluchowski_constant(2, 1, nz, 1, &t, 1e-8, out, NULL), GRAN_ERR_ARG);
}

/* mass sum k n_k + overflow and energy sum (3/2) n_k T_k + overflow at nt times against mass0, E0 */
static void check_closure(const double *nn, const double *T, const double *ov, int M, int nt, double mass0, double E0) {
  for (int q = 0; q < nt; q++) {
    double E = ov[3 * q + 2], mass = ov[3 * q + 1];
    for (int k = 0; k < M; k++) {
      E += 1.5 * nn[M * q + k] * T[M * q + k];
      mass += (k + 1) * nn[M * q + k];
    }
    GRAN_ASSERT_REL(E, E0, 1e-12);
    GRAN_ASSERT_REL(mass, mass0, 1e-12);
  }
}

/* Energy bookkeeping: elastic bounces (eps = 1) and fragmentation that keeps the impact energy
 * (eps_f = 1), no sticking: sum_k (3/2) n_k T_k + overflow energy is a linear invariant of the
 * right-hand side (merged/fragment energies are the exact conditional averages): 1e-12. Mass too.
 * For both fragment laws (monomers, binary); a bad law is refused. */
static void test_energy_closure(void **state) {
  (void)state;
  double n[8] = {0.05, 0.02, 0.01, 0.005};
  gran_mixture *mix = kmers(8, n, 1.0);
  const double T0[8] = {1.0, 2.0, 0.5, 3.0, 1, 1, 1, 1};
  const double t[3] = {1, 10, 100};
  double nn[24], T[24], ov[9], E0 = 0;
  for (int k = 0; k < 4; k++) E0 += 1.5 * n[k] * T0[k];
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, 0.0, 1.0, 1.0, 3, t, 1e-9, nn, T, ov));
  check_closure(nn, T, ov, 8, 3, 0.05 + 0.04 + 0.03 + 0.02, E0);
  assert_true(nn[16] > 0.06); /* shattering made monomers */
  /* the binary law (gran_theory_aggregation_law) keeps them too */
  GRAN_ASSERT_OK(gran_theory_aggregation_law(mix, T0, 0.0, 1.0, 1.0, GRAN_FRAG_BINARY, 3, t, 1e-9, nn, T, ov));
  check_closure(nn, T, ov, 8, 3, 0.05 + 0.04 + 0.03 + 0.02, E0);
  assert_true(ov[3 * 2 + 1] > 0); /* pieces beyond 8 went to the overflow */
  GRAN_ASSERT_ERR(gran_theory_aggregation_law(mix, T0, 0.0, 1.0, 1.0, 5, 3, t, 1e-9, nn, T, ov), GRAN_ERR_ARG);
  gran_mixture_destroy(&mix);
}

/* The binary fragment law (gran_theory_aggregation_law): first steps from 4-mers that all shatter (E_frag = 0): each
 * size s = 1..7 gains 2/7 piece per breakup (dn_s/dt = 2 R/7, R = n_4^2 K_44/2, s != 4) with
 * T_s(0+) = T s/8 + (4/3) eps_f^2 T (8 - s)/8 (CM motion of the piece and its share (8-s)/8 of
 * eps_f^2 mu g^2/2, <mu g^2/2> = 2T among collisions); 1e-3 over t = 1e-4 collision times; a
 * dimer's binary breakup is the monomer law's. */
static void test_binary_law(void **state) {
  (void)state;
  /* first steps from 4-mers (mass and energy closure: test_energy_closure) */
  double n4[8] = {0, 0, 0, 0.1};
  gran_mixture *mix = kmers(8, n4, 0.9);
  const double Tq = 2.0, epsf = 0.6, T8[8] = {Tq, Tq, Tq, Tq, Tq, Tq, Tq, Tq};
  const double sg = 2 * cbrt(4.0) / 2, K44 = PI * sg * sg * sqrt(8 * (2 * Tq / 4) / PI), R = 0.5 * 0.01 * K44;
  const double ts = 1e-4 / (0.1 * K44);
  double n1[8], T1[8];
  GRAN_ASSERT_OK(gran_theory_aggregation_law(mix, T8, 0.0, 0.0, epsf, GRAN_FRAG_BINARY, 1, &ts, 1e-12, n1, T1, NULL));
  for (int s = 1; s <= 7; s++) {
    if (s == 4) continue;
    GRAN_ASSERT_REL(n1[s - 1] / ts, 2 * R / 7, 1e-3);
    GRAN_ASSERT_REL(T1[s - 1], Tq * s / 8.0 + (4.0 / 3.0) * epsf * epsf * Tq * (8 - s) / 8.0, 1e-3);
  }
  GRAN_ASSERT_REL((0.1 - n1[3]) / ts, 2 * R - 2 * R / 7, 1e-3);
  gran_mixture_destroy(&mix);
  /* dimers from monomers: the binary law is the monomer law */
  double nm[4] = {0.1}, a[8], b[8];
  mix = kmers(4, nm, 0.8);
  const double Tm[4] = {1, 1, 1, 1}, tm[2] = {5, 50};
  GRAN_ASSERT_OK(gran_theory_aggregation_law(mix, Tm, 0.0, 1.0, 0.5, GRAN_FRAG_BINARY, 2, tm, 1e-10, a, NULL, NULL));
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, Tm, 0.0, 1.0, 0.5, 2, tm, 1e-10, b, NULL, NULL));
  for (int k = 0; k < 8; k++) GRAN_ASSERT_REL(a[k], b[k], 1e-14);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fractions_closed), cmocka_unit_test(test_fractions_mc),
      cmocka_unit_test(test_mixture_limit),    cmocka_unit_test(test_constant_kernel),
      cmocka_unit_test(test_large_and_truncated), cmocka_unit_test(test_mass_ballistic),
      cmocka_unit_test(test_first_rates),      cmocka_unit_test(test_energy_closure),      cmocka_unit_test(test_bad_inputs),
      cmocka_unit_test(test_binary_law),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
