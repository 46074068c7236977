/* t701-analysis.c - TAMSD by FFT against the direct sum and against exact results (ballistic,
 * Brownian), Sonine a2 of Maxwellian and known non-Gaussian samples, the speed histogram against
 * the Maxwell density, errors.
 *
 * Statistical assertions: fixed seeds, K_SIGMA = 4 standard errors (stated per quantity below);
 * the chi-square test uses significance 1e-3. */
#include "granary_test.h"

#define K_SIGMA 4.0

/* random walk(s) with Gaussian steps of variance s2 per component, starting far from the origin
 * (offset) so the FFT path must cope with large absolute positions */
static double *random_walks(int64_t ntraj, int64_t nt, double s2, double offset, uint64_t seed) {
  double *r = malloc(sizeof(double) * 3 * (size_t)(ntraj * nt));
  assert_non_null(r);
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, seed));
  for (int64_t t = 0; t < ntraj; t++) {
    double pos[3] = {offset, -0.5 * offset, 0.25 * offset}, step[3];
    for (int64_t i = 0; i < nt; i++) {
      GRAN_ASSERT_OK(gran_rng_normal(&g, 3, step));
      for (int c = 0; c < 3; c++) {
        if (i > 0) pos[c] += sqrt(s2) * step[c];
        r[3 * (t * nt + i) + c] = pos[c];
      }
    }
  }
  return r;
}

static void test_fft_equals_direct(void **state) {
  (void)state;
  const int64_t nts[] = {1, 2, 3, 7, 64, 100, 1000, 1537, 4096};
  double worst = 0;
  for (size_t k = 0; k < sizeof nts / sizeof *nts; k++) {
    const int64_t nt = nts[k];
    for (int64_t ntraj = 1; ntraj <= 3; ntraj += 2) {
      double *r = random_walks(ntraj, nt, 1.0, 100.0, 700 + (uint64_t)k);
      double *a = malloc(sizeof(double) * (size_t)nt), *b = malloc(sizeof(double) * (size_t)nt);
      assert_non_null(a);
      assert_non_null(b);
      GRAN_ASSERT_OK(gran_tamsd(ntraj, nt, r, nt, a)); /* nlag = nt: every lag */
      GRAN_ASSERT_OK(gran_tamsd_direct(ntraj, nt, r, nt, b));
      assert_true(a[0] == 0.0 && b[0] == 0.0);
      for (int64_t l = 1; l < nt; l++) {
        const double rel = fabs(a[l] - b[l]) / fabs(b[l]);
        if (rel > worst) worst = rel;
        GRAN_ASSERT_REL(a[l], b[l], 1e-10);
      }
      free(r);
      free(a);
      free(b);
    }
  }
  print_message("largest relative difference FFT vs direct: %.3g\n", worst);
}

/* One plan, executed repeatedly (and with fewer lags), gives what one-shot calls give. */
static void test_plan_reuse(void **state) {
  (void)state;
  const int64_t nt = 500;
  gran_tamsd_plan *plan = NULL;
  GRAN_ASSERT_OK(gran_tamsd_plan_create(nt, &plan));
  assert_non_null(plan);
  double a[500], b[500];
  for (int rep = 0; rep < 3; rep++) {
    double *r = random_walks(4, nt, 0.3, 0.0, 710 + (uint64_t)rep);
    GRAN_ASSERT_OK(gran_tamsd_plan_execute(plan, 4, r, 37, a));
    GRAN_ASSERT_OK(gran_tamsd(4, nt, r, 37, b));
    assert_memory_equal(a, b, 37 * sizeof(double));
    free(r);
  }
  GRAN_ASSERT_OK(gran_tamsd_plan_destroy(&plan));
  assert_null(plan);
  GRAN_ASSERT_OK(gran_tamsd_plan_destroy(&plan)); /* NULL-safe */
  GRAN_ASSERT_OK(gran_tamsd_plan_destroy(NULL));
}

/* R_i = R_0 + v i dt: delta^2(L) = |v|^2 (L dt)^2 exactly */
static void test_ballistic(void **state) {
  (void)state;
  const int64_t nt = 1000;
  const double v[3] = {0.3, -1.7, 2.2}, dt = 0.01, v2 = 0.09 + 2.89 + 4.84;
  double *r = malloc(sizeof(double) * 3 * nt), *a = malloc(sizeof(double) * nt), *b = malloc(sizeof(double) * nt);
  assert_non_null(r);
  assert_non_null(a);
  assert_non_null(b);
  for (int64_t i = 0; i < nt; i++)
    for (int c = 0; c < 3; c++) r[3 * i + c] = 5.0 + v[c] * (double)i * dt;
  GRAN_ASSERT_OK(gran_tamsd(1, nt, r, nt, a));
  GRAN_ASSERT_OK(gran_tamsd_direct(1, nt, r, nt, b));
  for (int64_t l = 1; l < nt; l++) {
    const double exact = v2 * (double)(l * l) * dt * dt;
    GRAN_ASSERT_REL(b[l], exact, 1e-12); /* direct: rounding of the positions only */
    GRAN_ASSERT_REL(a[l], exact, 1e-10); /* FFT: + transform rounding */
  }
  free(r);
  free(a);
  free(b);
}

/* Brownian walk with steps N(0, 2 D dt) per component: <delta^2(L)> = 6 D L dt. The standard error
 * is the empirical one: spread of the per-trajectory TAMSDs / sqrt(ntraj). */
static void test_brownian(void **state) {
  (void)state;
  const int64_t ntraj = 200, nt = 1000;
  const double D = 0.7, dt = 0.05;
  double *r = random_walks(ntraj, nt, 2 * D * dt, 0.0, 720);
  const int64_t lags[] = {1, 10, 100, 400};
  const int64_t nlag = 401;
  double *avg = malloc(sizeof(double) * nlag), *one = malloc(sizeof(double) * nlag);
  double s1[4] = {0}, s2[4] = {0};
  assert_non_null(avg);
  assert_non_null(one);
  GRAN_ASSERT_OK(gran_tamsd(ntraj, nt, r, nlag, avg));
  gran_tamsd_plan *plan = NULL;
  GRAN_ASSERT_OK(gran_tamsd_plan_create(nt, &plan));
  for (int64_t t = 0; t < ntraj; t++) {
    GRAN_ASSERT_OK(gran_tamsd_plan_execute(plan, 1, r + 3 * nt * t, nlag, one));
    for (int k = 0; k < 4; k++) {
      s1[k] += one[lags[k]];
      s2[k] += one[lags[k]] * one[lags[k]];
    }
  }
  GRAN_ASSERT_OK(gran_tamsd_plan_destroy(&plan));
  for (int k = 0; k < 4; k++) {
    const double mean = s1[k] / ntraj, var = (s2[k] - ntraj * mean * mean) / (ntraj - 1);
    GRAN_ASSERT_REL(avg[lags[k]], mean, 1e-12); /* averaging is linear */
    GRAN_ASSERT_SIGMA(avg[lags[k]], 6.0 * D * (double)lags[k] * dt, sqrt(var / ntraj), K_SIGMA);
  }
  free(r);
  free(avg);
  free(one);
}

/* delta-method standard error of a2 = 0.6 A/B^2 - 1 from samples e_i (A = <e^2>, B = <e>) */
static double a2_se(int64_t n, const double *e) {
  double m1 = 0, m2 = 0, m3 = 0, m4 = 0;
  for (int64_t i = 0; i < n; i++) {
    m1 += e[i];
    m2 += e[i] * e[i];
    m3 += e[i] * e[i] * e[i];
    m4 += e[i] * e[i] * e[i] * e[i];
  }
  m1 /= n, m2 /= n, m3 /= n, m4 /= n;
  const double gA = 0.6 / (m1 * m1), gB = -1.2 * m2 / (m1 * m1 * m1);
  const double vA = m4 - m2 * m2, vB = m2 - m1 * m1, cAB = m3 - m2 * m1;
  return sqrt((gA * gA * vA + gB * gB * vB + 2 * gA * gB * cAB) / (double)n);
}

static void test_sonine_a2(void **state) {
  (void)state;
  const int64_t n = 1000000;
  double *v = malloc(sizeof(double) * 3 * (size_t)n), *e = malloc(sizeof(double) * (size_t)n);
  double *m = malloc(sizeof(double) * (size_t)n);
  assert_non_null(v);
  assert_non_null(e);
  assert_non_null(m);
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 730));
  double a2;

  /* Maxwellian with a mean flow: a2 = 0, se = sqrt(8/(15 n)) (delta method for chi-square(3)) */
  GRAN_ASSERT_OK(gran_rng_normal(&g, 3 * n, v));
  for (int64_t i = 0; i < n; i++) v[3 * i] += 3.0;
  GRAN_ASSERT_OK(gran_sonine_a2(n, v, NULL, &a2));
  GRAN_ASSERT_SIGMA(a2, 0.0, sqrt(8.0 / (15.0 * n)), K_SIGMA);

  /* two species, m = 1 and 4, Maxwellian at one temperature (v ~ N(0, T/m)): with the masses
   * a2 = 0; without them, a mixture of variances 1 and 1/4: (3/5)(15+15/16)/2 / ((3+3/4)/2)^2 - 1
   * = 0.36 exactly */
  for (int64_t i = 0; i < n; i++) {
    m[i] = i % 2 ? 4.0 : 1.0;
    if (i % 2)
      for (int c = 0; c < 3; c++) v[3 * i + c] *= 0.5;
  }
  for (int64_t i = 0; i < n; i++) v[3 * i] -= 3.0 * (i % 2 ? 0.5 : 1.0) - 1.0; /* common flow 1 */
  GRAN_ASSERT_OK(gran_sonine_a2(n, v, m, &a2));
  for (int64_t i = 0; i < n; i++) {
    double c2 = 0;
    for (int c = 0; c < 3; c++) c2 += (v[3 * i + c] - (c == 0)) * (v[3 * i + c] - (c == 0));
    e[i] = m[i] * c2;
  }
  GRAN_ASSERT_SIGMA(a2, 0.0, a2_se(n, e), K_SIGMA);
  GRAN_ASSERT_OK(gran_sonine_a2(n, v, NULL, &a2));
  for (int64_t i = 0; i < n; i++) e[i] /= m[i];
  GRAN_ASSERT_SIGMA(a2, 0.36, a2_se(n, e), K_SIGMA);

  /* components uniform on [-1,1]: <c^2> = 1, <c^4> = 3/5 + 6/9, a2 = (3/5)(19/15) - 1 = -0.24 */
  GRAN_ASSERT_OK(gran_rng_uniform(&g, 3 * n, v));
  for (int64_t i = 0; i < 3 * n; i++) v[i] = 2.0 * v[i] - 1.0;
  for (int64_t i = 0; i < n; i++) e[i] = v[3 * i] * v[3 * i] + v[3 * i + 1] * v[3 * i + 1] + v[3 * i + 2] * v[3 * i + 2];
  GRAN_ASSERT_OK(gran_sonine_a2(n, v, NULL, &a2));
  GRAN_ASSERT_SIGMA(a2, -0.24, a2_se(n, e), K_SIGMA);

  /* one speed, zero mean exactly (the six axis directions): a2 = 3/5 - 1 = -0.4 to rounding */
  const double axes[18] = {1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1};
  GRAN_ASSERT_OK(gran_sonine_a2(6, axes, NULL, &a2));
  GRAN_ASSERT_REL(a2, -0.4, 1e-15);
  free(v);
  free(e);
  free(m);
}

/* Maxwell speed density f(c) = 4/sqrt(pi) c^2 exp(-c^2), c = |v|/sqrt(2T/m);
 * its CDF F(c) = erf(c) - 2/sqrt(pi) c exp(-c^2) */
static double maxwell_cdf(double c) { return erf(c) - 2.0 / sqrt(3.14159265358979323846) * c * exp(-c * c); }

static void test_speed_histogram(void **state) {
  (void)state;
  const int64_t n = 1000000, nbins = 60;
  const double cmax = 3.0, T = 1.7;
  double *v = malloc(sizeof(double) * 3 * (size_t)n), hist[60];
  assert_non_null(v);
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 740));
  GRAN_ASSERT_OK(gran_rng_normal(&g, 3 * n, v));
  for (int64_t i = 0; i < 3 * n; i++) v[i] = sqrt(T) * v[i] + (i % 3 == 1 ? -2.0 : 0.0); /* m = 1, flow */
  int64_t beyond = -1;
  GRAN_ASSERT_OK(gran_speed_histogram(n, v, sqrt(2 * T), nbins, cmax, hist, &beyond));
  const double dc = cmax / nbins;
  double frac = 0, chi2 = 0;
  for (int k = 0; k < nbins; k++) {
    frac += hist[k] * dc;
    const double count = hist[k] * dc * (double)n;
    assert_true(fabs(count - round(count)) < 1e-6); /* a normalised count */
    const double e = (maxwell_cdf((k + 1) * dc) - maxwell_cdf(k * dc)) * (double)n;
    if (e < 5) fail_msg("bin %d expects %.2f < 5: bad test design", k, e);
    chi2 += (count - e) * (count - e) / e;
  }
  GRAN_ASSERT_REL(frac + (double)beyond / (double)n, 1.0, 1e-12); /* every particle counted once */
  /* tail beyond cmax: binomial, se = sqrt(p(1-p)/n) */
  const double ptail = 1.0 - maxwell_cdf(cmax);
  GRAN_ASSERT_SIGMA((double)beyond / n, ptail, sqrt(ptail * (1 - ptail) / n), K_SIGMA);
  /* chi-square, nbins + 1 cells (the tail included), df = nbins; 1e-3 critical value for df = 60 */
  chi2 += ((double)beyond - ptail * n) * ((double)beyond - ptail * n) / (ptail * n);
  const double a = 2.0 / (9.0 * nbins), crit = nbins * pow(1.0 - a + 3.090232 * sqrt(a), 3);
  if (chi2 > crit) fail_msg("speed histogram chi2 = %g > %g", chi2, crit);
  GRAN_ASSERT_OK(gran_speed_histogram(n, v, sqrt(2 * T), nbins, cmax, hist, NULL)); /* nbeyond optional */
  free(v);
}

static void test_errors(void **state) {
  (void)state;
  double r[9] = {0, 0, 0, 1, 0, 0, 2, 0, 0}, out[3], a2, hist[4];
  int64_t nb;
  gran_tamsd_plan *plan = NULL;
  GRAN_ASSERT_ERR(gran_tamsd_plan_create(0, &plan), GRAN_ERR_ARG);
  assert_null(plan);
  GRAN_ASSERT_ERR(gran_tamsd_plan_create(-3, &plan), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_plan_create(10, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_plan_create(INT64_MAX, &plan), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_tamsd_plan_create(3, &plan));
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(NULL, 1, r, 3, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(plan, 0, r, 3, out), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'ntraj'"));
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(plan, 1, NULL, 3, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(plan, 1, r, 3, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(plan, 1, r, 0, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(plan, 1, r, 4, out), GRAN_ERR_ARG); /* nlag > nsamples */
  assert_non_null(strstr(gran_last_error_message(), "'nlag'"));
  r[4] = NAN;
  GRAN_ASSERT_ERR(gran_tamsd_plan_execute(plan, 1, r, 3, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd(1, 3, r, 3, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_direct(1, 3, r, 3, out), GRAN_ERR_ARG);
  r[4] = 0;
  GRAN_ASSERT_OK(gran_tamsd_plan_execute(plan, 1, r, 3, out));
  GRAN_ASSERT_REL(out[1], 1.0, 1e-14);
  GRAN_ASSERT_REL(out[2], 4.0, 1e-14);
  GRAN_ASSERT_OK(gran_tamsd_plan_destroy(&plan));
  GRAN_ASSERT_ERR(gran_tamsd(0, 3, r, 3, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd(1, 0, r, 1, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd(1, 3, r, 5, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd(INT64_MAX / 2, 3, r, 3, out), GRAN_ERR_ARG); /* size overflow */
  GRAN_ASSERT_ERR(gran_tamsd_direct(1, 3, NULL, 3, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_direct(1, 3, r, -1, out), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_tamsd_direct(1, 3, r, 3, NULL), GRAN_ERR_ARG);

  const double v[6] = {1, 2, 3, -1, 0, 2}, same[6] = {1, 2, 3, 1, 2, 3};
  double m[2] = {1, 2};
  GRAN_ASSERT_ERR(gran_sonine_a2(0, v, NULL, &a2), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_sonine_a2(2, NULL, NULL, &a2), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_sonine_a2(2, v, NULL, NULL), GRAN_ERR_ARG);
  m[1] = 0;
  GRAN_ASSERT_ERR(gran_sonine_a2(2, v, m, &a2), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "mass[1]"));
  m[1] = NAN;
  GRAN_ASSERT_ERR(gran_sonine_a2(2, v, m, &a2), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_sonine_a2(2, same, NULL, &a2), GRAN_ERR_DOMAIN);
  GRAN_ASSERT_ERR(gran_sonine_a2(1, v, NULL, &a2), GRAN_ERR_DOMAIN); /* one particle: no spread */
  const double vbad[6] = {1, 2, INFINITY, 0, 0, 0};
  GRAN_ASSERT_ERR(gran_sonine_a2(2, vbad, NULL, &a2), GRAN_ERR_ARG);
  const double huge[6] = {1e200, 0, 0, -1e200, 0, 0};
  GRAN_ASSERT_ERR(gran_sonine_a2(2, huge, NULL, &a2), GRAN_ERR_NUMERIC);

  GRAN_ASSERT_ERR(gran_speed_histogram(0, v, 1, 4, 3, hist, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, NULL, 1, 4, 3, hist, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, v, 0, 4, 3, hist, &nb), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'scale'"));
  GRAN_ASSERT_ERR(gran_speed_histogram(2, v, NAN, 4, 3, hist, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, v, 1, 0, 3, hist, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, v, 1, 4, 0, hist, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, v, 1, 4, INFINITY, hist, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, v, 1, 4, 3, NULL, &nb), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_speed_histogram(2, vbad, 1, 4, 3, hist, &nb), GRAN_ERR_ARG);
  /* two particles at +-(1, 1, 0.5) about the mean (0, 1, 2.5): c = 1.5, bin 2 of [0,3) in 4 */
  GRAN_ASSERT_OK(gran_speed_histogram(2, v, 1, 4, 3, hist, &nb));
  assert_int_equal(nb, 0);
  assert_true(hist[0] == 0 && hist[1] == 0 && hist[3] == 0);
  GRAN_ASSERT_REL(hist[2], 1.0 / 0.75, 1e-15);
  GRAN_ASSERT_OK(gran_speed_histogram(2, v, 1, 4, 1.5, hist, &nb)); /* c == cmax: beyond */
  assert_int_equal(nb, 2);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_fft_equals_direct),
      cmocka_unit_test(test_plan_reuse),
      cmocka_unit_test(test_ballistic),
      cmocka_unit_test(test_brownian),
      cmocka_unit_test(test_sonine_a2),
      cmocka_unit_test(test_speed_histogram),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests_name("t701-analysis", tests, NULL, NULL);
}
