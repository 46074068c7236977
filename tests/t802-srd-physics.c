/* t802-srd-physics.c - GSRD against theory.
 *  - Standard SRD viscosity under Lees-Edwards shear (global profile-unbiased thermostat at
 *    kT = 1, a = dt = m = 1): the TOTAL stress (kinetic part: momentum flux averaged over every
 *    plane y = const; collisional part: virial of the collision momentum changes) over
 *    rho * shear rate against Eq. 1.48 (2-D) / 1.49 (3-D) + (a^2/(6 d dt)) (M - 1 + e^-M)/M
 *    (1 - cos alpha), at alpha = 60, 90, 130 in 2-D and in 3-D. Error: standard error of time
 *    blocks; tolerance 4 se + 2 %.
 *  - Poiseuille flow between no-slip walls under a body force g (global thermostat): a parabolic
 *    profile (rms residual of the block-averaged profile about its parabola), symmetric no-slip walls, and
 *    the viscosity from the curvature equal to the Lees-Edwards one (see test_poiseuille).
 *  (Haff's law of the CPU engine: the shared body sde_body_haff of tests/srd_device_body.h, run by
 *  t890 on the CPU engine and on the reference device.)
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
 * tolerance 4 se + 2 %. 2-D boxes are 8 x 8 cells: in 2-D the measured viscosity grows with the box
 * (hydrodynamic long-time tails; at alpha = 90, 4 seeds each: 0.1316 at 8^2, 0.136 at 12^2,
 * 0.137 at 16^2, 0.144 at 32^2 against 0.1306), Eq. 1.48 is the small-box value. */
static void le_viscosity(int dim, int64_t L, double alpha, double rate, int64_t nblk, int64_t blk, double *mean,
                         double *se, double *kin) {
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
  *mean = sum / nblk;
  *se = sqrt(fmax(0.0, sum2 / nblk - *mean * *mean) / (nblk - 1));
  *kin = sk / nblk;
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void viscosity_case(int dim, int64_t L, double alpha, double rate, int64_t nblk, int64_t blk) {
  double mean, se, kin;
  le_viscosity(dim, L, alpha, rate, nblk, blk, &mean, &se, &kin);
  const double n0 = 10;
  const double th = nu_theory(dim, n0, alpha), thc = nu_coll_theory(dim, n0, alpha);
  printf("viscosity %dD alpha %3g: total %.5f +- %.5f (theory %.5f, %+.2f %% = %+.1f se); kinetic %.5f (%.5f), "
         "collisional %.5f (%.5f)\n",
         dim, alpha, mean, se, th, 100 * (mean / th - 1), (mean - th) / se, kin, th - thc, mean - kin, thc);
  assert_true(se < 0.06 * th); /* the measurement resolves the theory */
  assert_true(fabs(mean - th) <= 4 * se + 0.02 * th);
}

static void test_viscosity(void **state) {
  (void)state;
  const double al[3] = {60, 90, 130};
  for (int k = 0; k < 3; ++k) viscosity_case(2, 8, al[k], 0.1, SAN ? 8 : 24, SAN ? 150 : 250);
  for (int k = 0; k < 3; ++k) viscosity_case(3, SAN ? 8 : 10, al[k], 0.05, SAN ? 8 : 12, SAN ? 100 : 200);
}

/* Poiseuille flow between no-slip walls (2-D, alpha = 90, global thermostat) under a body force
 * g along x: the time-averaged profile (gran_srd_velocity_profile, 2 slabs per cell) in nblk blocks;
 * per block a least-squares parabola v = c0 + c1 y + c2 y^2. nu = -g / (2 c2) against the
 * Lees-Edwards viscosity of a 20 x 20 box (4 combined se + 3 %) and against Eq. 1.48 + collisional
 * (4 se + 8 %); the fitted wall velocities are equal within 4 se and below 5 % of the centre
 * velocity (no slip); the rms residual of the mean profile about its parabola is below 2 % of the
 * centre velocity (chi^2 per degree of freedom against the block errors printed: 8 blocks make
 * those errors too rough for a bound; the slabs at the walls deviate most). */
static void fit_parabola(const double *v, int nb, double hbin, double c[3]) {
  double A[3][4] = {{0}};
  for (int b = 0; b < nb; ++b) {
    const double yb = (b + 0.5) * hbin, f[3] = {1, yb, yb * yb};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) A[i][j] += f[i] * f[j];
      A[i][3] += f[i] * v[b];
    }
  }
  for (int i = 0; i < 3; ++i)
    for (int r = 0; r < 3; ++r)
      if (r != i) {
        const double m = A[r][i] / A[i][i];
        for (int k = 0; k < 4; ++k) A[r][k] -= m * A[i][k];
      }
  for (int i = 0; i < 3; ++i) c[i] = A[i][3] / A[i][i];
}

static void test_poiseuille(void **state) {
  (void)state;
  gran_srd_options o;
  GRAN_ASSERT_OK(gran_srd_options_default(&o));
  o.dim = 2;
  enum { H = 20, NB = 2 * H, NBLK = 8 };
  o.cells[0] = SAN ? 8 : 32;
  o.cells[1] = H;
  o.n0 = 10;
  o.alpha_deg = 90;
  o.thermostat = 2;
  o.wall_axis = 1;
  o.wall_rule = 1;
  const double nu = nu_theory(2, o.n0, o.alpha_deg);
  const double g = 0.3 * 8 * nu / (H * H); /* centre velocity ~ 0.3 */
  o.accel[0] = g;
  o.seed = 77;
  o.threads = 1; /* small systems: no OpenMP barriers on a loaded 2-core machine */
  /* the Lees-Edwards viscosity of a box as wide as the channel (2-D: it depends on the size) */
  double le_nu = 0, le_se = 0, le_kin;
  if (!SAN) le_viscosity(2, H, 90, 0.1, 16, 250, &le_nu, &le_se, &le_kin);
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, SAN ? 300 : 3000)); /* slowest mode: H^2 / (pi^2 nu) ~ 310 steps */
  const int blk = SAN ? 50 : 1000;
  double vb[NBLK][NB], c[NBLK][3], vm[NB] = {0}, vv[NB] = {0};
  for (int k = 0; k < NBLK; ++k) {
    double sv[NB] = {0}, sn[NB] = {0}, mean[NB];
    int64_t cnt[NB];
    for (int t = 0; t < blk; ++t) {
      GRAN_ASSERT_OK(gran_srd_advance(s, 1));
      GRAN_ASSERT_OK(gran_srd_velocity_profile(s, 1, 0, NB, mean, cnt));
      for (int b = 0; b < NB; ++b) {
        sv[b] += mean[b] * (double)cnt[b];
        sn[b] += (double)cnt[b];
      }
    }
    for (int b = 0; b < NB; ++b) {
      vb[k][b] = sv[b] / sn[b];
      vm[b] += vb[k][b] / NBLK;
      vv[b] += vb[k][b] * vb[k][b] / NBLK;
    }
    fit_parabola(vb[k], NB, 0.5, c[k]);
  }
  /* block statistics of the curvature and the two wall velocities */
  double m[3] = {0}, q[3] = {0};
  for (int k = 0; k < NBLK; ++k) {
    const double x[3] = {c[k][2], c[k][0], c[k][0] + c[k][1] * H + c[k][2] * H * H};
    for (int i = 0; i < 3; ++i) {
      m[i] += x[i] / NBLK;
      q[i] += x[i] * x[i] / NBLK;
    }
  }
  double se[3], dlh = 0, dlh2 = 0;
  for (int i = 0; i < 3; ++i) se[i] = sqrt(fmax(0.0, q[i] - m[i] * m[i]) / (NBLK - 1));
  for (int k = 0; k < NBLK; ++k) {
    const double d = c[k][0] - (c[k][0] + c[k][1] * H + c[k][2] * H * H);
    dlh += d / NBLK;
    dlh2 += d * d / NBLK;
  }
  const double se_dlh = sqrt(fmax(0.0, dlh2 - dlh * dlh) / (NBLK - 1));
  const double nu_m = -g / (2 * m[0]), se_nu = nu_m * se[0] / fabs(m[0]);
  const double vc = -m[0] * H * H / 4; /* centre velocity above the walls */
  double cm[3], chi2 = 0, rms = 0;
  fit_parabola(vm, NB, 0.5, cm);
  for (int b = 0; b < NB; ++b) {
    const double yb = (b + 0.5) * 0.5, r = vm[b] - (cm[0] + cm[1] * yb + cm[2] * yb * yb);
    const double e2 = fmax(vv[b] - vm[b] * vm[b], 1e-30) / (NBLK - 1);
    chi2 += r * r / e2;
    rms += r * r / NB;
  }
  chi2 /= (NB - 3);
  printf("Poiseuille: nu = %.5f +- %.5f (Lees-Edwards %d^2 %.5f +- %.5f, Eq. 1.48 + coll %.5f), walls %.4f %.4f "
         "(+- %.4f, centre %.4f), residual about the parabola: rms %.2g of the centre velocity, chi2/dof %.2f\n",
         nu_m, se_nu, (int)H, le_nu, le_se, nu, m[1], m[2], se[1], vc, sqrt(rms) / vc, chi2);
  if (!SAN) {
    assert_true(le_se > 0);
    assert_true(fabs(nu_m - le_nu) <= 4 * sqrt(se_nu * se_nu + le_se * le_se) + 0.03 * le_nu);
    assert_true(fabs(nu_m - nu) <= 4 * se_nu + 0.08 * nu);
    assert_true(fabs(dlh) <= 4 * se_dlh);                     /* symmetric walls */
    assert_true(fabs(m[1]) < 0.05 * vc && fabs(m[2]) < 0.05 * vc); /* no slip */
    assert_true(sqrt(rms) < 0.02 * vc);                        /* parabolic */
  } else {
    assert_true(m[0] < 0); /* curved the right way */
  }
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_viscosity),
      cmocka_unit_test(test_poiseuille),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
