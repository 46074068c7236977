/* t612-srd-a2.c - Sonine a2 of the GSRD gas (gran_srd_observe; Zantop 2017, Fig. 3.15).
 *  - Estimator: a2 = (d/(d+2)) <c^4>/<c^2>^2 - 1 of the thermal velocities v - V_cell, corrected for
 *    the cell-mean subtraction. Checked in 2-D and 3-D, at n0 = 3 (many cells of 2-4 particles,
 *    where the correction is large) and n0 = 20, against samples of known a2:
 *      Maxwellian (the engine's initial state)            a2 = 0,
 *      independent uniform components on [-1, 1]          a2 = -1.2 / (d + 2)  (-0.3, -0.24),
 *      independent Laplace components                     a2 = 3 / (d + 2)     (0.75, 0.6),
 *    (components of excess kurtosis k give a2 = k / (d + 2)). Error: standard error of the mean
 *    over R seeds, tolerance 4 se; the se is also required to be below a stated bound, so that
 *    the test cannot pass by noise. The former estimator (no correction, N for N_in) gave +0.018
 *    for a Maxwellian at n0 = 5 and -0.14 for the uniform 3-D sample at n0 = 3: >> 4 se.
 *  - Physics (thesis parameters, Sec. 3.5: n0 = 25, T0 = 100, dt = 0.01, alpha = 10, so dt sqrt(T0)
 *    = 0.1 a; box reduced to 8^3): a2 averaged over t = 1.5 .. 5 (150-500 steps, the thesis' minima)
 *    is negative for eps_eff(t0) = 0.980 and lower than for 0.900 (thesis: "minima are lower for
 *    higher eps_eff(t0)"), each by more than 4 se of R seeds.
 * Sizes are reduced under the sanitizers. */
#include "granary_test.h"

#if defined(__SANITIZE_ADDRESS__)
#define SAN 1
#else
#define SAN 0
#endif

/* splitmix64: the test's own sample generator (independent of the engine's streams) */
static uint64_t sm_next(uint64_t *s) {
  uint64_t z = (*s += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static double sm_uniform(uint64_t *s) { return ((double)(sm_next(s) >> 11) + 0.5) * 0x1.0p-53; } /* (0, 1) */

enum { MAXWELL = 0, UNIFORM = 1, LAPLACE = 2 };

static double sample_a2(int dim, double n0, int64_t L, int kind, uint64_t seed) {
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = dim;
  o.cells[0] = o.cells[1] = o.cells[2] = L;
  o.n0 = n0;
  o.seed = seed;
  o.threads = 1;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  if (kind != MAXWELL) {
    int64_t n;
    double *x, *y, *z, *v[3];
    GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &v[0], &v[1], &v[2]));
    uint64_t r = seed * 7919 + 17;
    for (int k = 0; k < dim; ++k)
      for (int64_t i = 0; i < n; ++i) {
        const double u = sm_uniform(&r);
        v[k][i] = kind == UNIFORM ? 2 * u - 1 : (u < 0.5 ? log(2 * u) : -log(2 - 2 * u));
      }
  }
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  return ob.a2;
}

static void mean_se(const double *x, int n, double *m, double *se) {
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) s += x[i];
  *m = s / n;
  for (int i = 0; i < n; ++i) s2 += (x[i] - *m) * (x[i] - *m);
  *se = sqrt(s2 / (n - 1) / n);
}

static void estimator_case(int dim, double n0, int kind) {
  const int R = SAN ? 6 : 12;
  const int64_t L = dim == 3 ? (SAN ? 12 : 16) : (SAN ? 48 : 96);
  const double N = n0 * (double)(dim == 3 ? L * L * L : L * L);
  const double expect = kind == MAXWELL ? 0.0 : (kind == UNIFORM ? -1.2 : 3.0) / (dim + 2.0);
  double a2[12], m, se;
  for (int r = 0; r < R; ++r) a2[r] = sample_a2(dim, n0, L, kind, 1000 + 31 * (uint64_t)r + (uint64_t)(10 * n0) + (uint64_t)kind);
  mean_se(a2, R, &m, &se);
  /* se bound: the delta-method se of one Gaussian sample, sqrt(8/(15 N)) (3-D), sqrt(1/N) (2-D),
   * times 3 for the cell-mean correction (x2 at n0 = 3) and 15 for the Laplace tails (its 8th
   * moment), over sqrt(R) */
  const double se1 = (dim == 3 ? sqrt(8.0 / 15.0) : 1.0) / sqrt(N) * (kind == LAPLACE ? 15.0 : 3.0);
  print_message("a2 d=%d n0=%g %-7s: %+.5f +- %.5f (expected %+.5f; %d seeds, N = %.0f)\n", dim, n0,
                kind == MAXWELL ? "Maxwell" : kind == UNIFORM ? "uniform" : "Laplace", m, se, expect, R, N);
  assert_true(se < se1 / sqrt((double)R));
  GRAN_ASSERT_SIGMA(m, expect, se, 4.0);
}

static void test_estimator_maxwell(void **state) {
  (void)state;
  for (int dim = 2; dim <= 3; ++dim) {
    estimator_case(dim, 3.0, MAXWELL);
    estimator_case(dim, 20.0, MAXWELL);
  }
}

static void test_estimator_uniform(void **state) {
  (void)state;
  for (int dim = 2; dim <= 3; ++dim) {
    estimator_case(dim, 3.0, UNIFORM);
    estimator_case(dim, 20.0, UNIFORM);
  }
}

static void test_estimator_laplace(void **state) {
  (void)state;
  for (int dim = 2; dim <= 3; ++dim) estimator_case(dim, 3.0, LAPLACE);
}

/* thesis parameters: n0 = 25, T0 = 100, dt = 0.01, eps from eps_eff(t0) = 1 - 2.5 (1 - eps^2) */
static double cooling_a2(double eff0, uint64_t seed) {
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 3;
  o.cells[0] = o.cells[1] = o.cells[2] = SAN ? 6 : 8;
  o.n0 = 25;
  o.T0 = 100;
  o.dt = 0.01;
  o.alpha_deg = 10;
  o.sigma = 1;
  o.eps = sqrt(1 - (1 - eff0) / 2.5);
  o.seed = seed;
  o.threads = 1;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 150));
  double sum = 0;
  int k = 0;
  for (; k < 8; ++k) { /* t = 1.5 .. 5.0 in steps of 0.5 */
    gran_srd_obs ob;
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    assert_true(ob.clamped == 0);
    sum += ob.a2;
    GRAN_ASSERT_OK(gran_srd_advance(s, 50));
  }
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  return sum / k;
}

static void test_order_of_minima(void **state) {
  (void)state;
  const int R = SAN ? 4 : 6;
  double lo[6], hi[6], d[6], mlo, slo, mhi, shi, md, sd;
  for (int r = 0; r < R; ++r) {
    lo[r] = cooling_a2(0.900, 315 + (uint64_t)r);
    hi[r] = cooling_a2(0.980, 315 + (uint64_t)r);
    d[r] = hi[r] - lo[r];
  }
  mean_se(lo, R, &mlo, &slo);
  mean_se(hi, R, &mhi, &shi);
  mean_se(d, R, &md, &sd);
  print_message("<a2>(t = 1.5..5): eps_eff(t0) = 0.900: %+.4f +- %.4f, 0.980: %+.4f +- %.4f, "
                "difference %+.4f +- %.4f (%d seeds)\n", mlo, slo, mhi, shi, md, sd, R);
  assert_true(mhi < -4 * shi);
  assert_true(md < -4 * sd);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_estimator_maxwell),
      cmocka_unit_test(test_estimator_uniform),
      cmocka_unit_test(test_estimator_laplace),
      cmocka_unit_test(test_order_of_minima),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
