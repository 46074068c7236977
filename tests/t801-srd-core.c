/* t801-srd-core.c - GSRD core: conservation per step (N exact, momentum 1e-12, energy to rounding
 * for eps = 1, ledger 1e-12 for eps < 1, with every effect combination that conserves them), the
 * rotation invariants of the kernel (|u_perp| kept, angle alpha, parallel part unchanged), the
 * random axis uniform on the sphere (chi-square), theta after cooling by 1e8 against a long-double
 * two-pass sum, 1 vs 2 threads bit for bit, checkpoint/resume bit for bit, S(k) against a direct
 * O(N^2) DFT and S = 1 for uncorrelated positions, bad options rejected naming the option. */
#define _POSIX_C_SOURCE 200809L
#include <unistd.h>

#include "granary_test.h"
#include "srd/srd_kernels.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static gran_srd_options base(int dim, int64_t L) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = dim;
  o.cells[0] = o.cells[1] = o.cells[2] = L;
  o.n0 = 7.5;
  o.alpha_deg = dim == 2 ? 90 : 130;
  o.seed = 12345;
  o.sort_every = 7;
  return o;
}

static void momentum_energy(gran_srd *s, double P[3], double *E, double *vscale) {
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  long double p[3] = {0, 0, 0}, e = 0, a = 0;
  for (int64_t i = 0; i < n; ++i) {
    double w = vz ? vz[i] : 0.0;
    p[0] += vx[i];
    p[1] += vy[i];
    p[2] += w;
    e += 0.5L * ((long double)vx[i] * vx[i] + (long double)vy[i] * vy[i] + (long double)w * w);
    a += fabs(vx[i]) + fabs(vy[i]) + fabs(w);
  }
  for (int k = 0; k < 3; ++k) P[k] = (double)p[k];
  *E = (double)e;
  *vscale = (double)a;
}

/* per step: N exact, momentum to 1e-12 of sum |v|, energy to 1e-12 (eps = 1) or ledger (eps < 1) */
static void conservation_case(int dim, double eps, int thermo) {
  gran_srd_options o = base(dim, 6);
  o.eps = eps;
  o.sigma = 0.3;
  o.thermostat = thermo;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  double P0[3], E0, a0;
  momentum_energy(s, P0, &E0, &a0);
  for (int st = 0; st < 25; ++st) {
    GRAN_ASSERT_OK(gran_srd_advance(s, 1));
    double P[3], E, a;
    momentum_energy(s, P, &E, &a);
    for (int k = 0; k < 3; ++k) GRAN_ASSERT_ABS(P[k], P0[k], 1e-12 * a);
    gran_srd_obs ob;
    GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
    assert_int_equal(ob.n, (int64_t)floor(o.n0 * pow(6, dim) + 0.5));
    if (eps == 1.0 && !thermo) GRAN_ASSERT_REL(E, E0, 1e-12);
    else GRAN_ASSERT_ABS(ob.ledger_error, 0.0, 1e-12);
    if (eps < 1.0 && !thermo) assert_true(ob.e_collisions < 0.0);
  }
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  if (eps < 1.0 && !thermo) assert_true(ob.energy < 0.9 * E0); /* it did dissipate */
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  assert_null(s);
}

static void test_conservation(void **state) {
  (void)state;
  conservation_case(2, 1.0, 0);
  conservation_case(3, 1.0, 0);
  conservation_case(2, 0.7, 0);
  conservation_case(3, 0.7, 0);
  conservation_case(3, 1.0, 1);
  conservation_case(2, 1.0, 2);
  conservation_case(3, 0.7, 2);
}

/* Lees-Edwards: momentum changes only by the boundary; the ledger still closes (e_external). */
static void test_ledger_effects(void **state) {
  (void)state;
  gran_srd_options o = base(3, 6);
  o.shear_rate = 0.05;
  o.eps = 0.9;
  o.sigma = 0.3;
  o.accel[2] = -0.01;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 30));
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  GRAN_ASSERT_ABS(ob.ledger_error, 0.0, 1e-12);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  o = base(2, 8);
  o.wall_axis = 1;
  o.accel[0] = 0.001;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 30));
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  GRAN_ASSERT_ABS(ob.ledger_error, 0.0, 1e-12);
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  for (int64_t i = 0; i < n; ++i) assert_true(y[i] >= 0.0 && y[i] < 8.0 && x[i] >= 0.0 && x[i] < 8.0);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* kernel: |u_perp| kept, angle between u_perp before and after = alpha, parallel part unchanged */
static void test_rotation_invariants(void **state) {
  (void)state;
  gran_rng r;
  GRAN_ASSERT_OK(gran_rng_seed(&r, 7));
  const double alpha = 1.1, ca = cos(alpha), sa = sin(alpha);
  for (int t = 0; t < 1000; ++t) {
    srd_cell_rot cr;
    for (int k = 0; k < 3; ++k) cr.V[k] = srd_rng_normal(&r);
    cr.f = cr.g = 1.0;
    srd_draw_axis(&r, 3, cr.r);
    double v[3], u[3];
    for (int k = 0; k < 3; ++k) {
      v[k] = srd_rng_normal(&r);
      u[k] = v[k] - cr.V[k];
    }
    srd_rotate(v, &cr, ca, sa, 3, 0);
    double w[3];
    for (int k = 0; k < 3; ++k) w[k] = v[k] - cr.V[k];
    double up = 0, wp = 0;
    for (int k = 0; k < 3; ++k) {
      up += u[k] * cr.r[k];
      wp += w[k] * cr.r[k];
    }
    GRAN_ASSERT_ABS(wp, up, 1e-13);
    double a[3], b[3], na = 0, nb = 0, dot = 0;
    for (int k = 0; k < 3; ++k) {
      a[k] = u[k] - up * cr.r[k];
      b[k] = w[k] - wp * cr.r[k];
      na += a[k] * a[k];
      nb += b[k] * b[k];
      dot += a[k] * b[k];
    }
    GRAN_ASSERT_REL(sqrt(nb), sqrt(na), 1e-13);
    GRAN_ASSERT_ABS(dot / sqrt(na * nb), ca, 1e-12);
    /* 3-D with dissipation: parallel part kept, perpendicular scaled by f */
    cr.f = 0.8;
    for (int k = 0; k < 3; ++k) v[k] = cr.V[k] + u[k];
    srd_rotate(v, &cr, ca, sa, 3, 1);
    double wp2 = 0, nb2 = 0;
    for (int k = 0; k < 3; ++k) wp2 += (v[k] - cr.V[k]) * cr.r[k];
    for (int k = 0; k < 3; ++k) {
      double q = v[k] - cr.V[k] - wp2 * cr.r[k];
      nb2 += q * q;
    }
    GRAN_ASSERT_ABS(wp2, up, 1e-13);
    GRAN_ASSERT_REL(sqrt(nb2), 0.8 * sqrt(na), 1e-13);
    /* 2-D: angle +-alpha, |u| kept */
    srd_cell_rot c2 = cr;
    c2.f = 1.0;
    srd_draw_axis(&r, 2, c2.r);
    double v2[3] = {cr.V[0] + u[0], cr.V[1] + u[1], 0};
    srd_rotate(v2, &c2, ca, sa, 2, 0);
    double w0 = v2[0] - c2.V[0], w1 = v2[1] - c2.V[1];
    GRAN_ASSERT_REL(hypot(w0, w1), hypot(u[0], u[1]), 1e-13);
    double cross = u[0] * w1 - u[1] * w0;
    GRAN_ASSERT_ABS(cross / (hypot(w0, w1) * hypot(u[0], u[1])), c2.r[2] * sa, 1e-12);
  }
}

/* random axis: cos(theta) and phi each in 20 bins; chi-square with 19 dof below 45 (p ~ 1e-3) */
static void test_axis_uniform(void **state) {
  (void)state;
  gran_rng r;
  GRAN_ASSERT_OK(gran_rng_stream(99, 5, &r));
  enum { NB = 20, NS = 200000 };
  int64_t hc[NB] = {0}, hp[NB] = {0}, sign[2] = {0, 0};
  for (int i = 0; i < NS; ++i) {
    double e[3];
    srd_draw_axis(&r, 3, e);
    GRAN_ASSERT_REL(e[0] * e[0] + e[1] * e[1] + e[2] * e[2], 1.0, 1e-14);
    int b = (int)((e[2] + 1.0) * 0.5 * NB);
    hc[b < NB ? b : NB - 1]++;
    double ph = atan2(e[1], e[0]) + M_PI;
    b = (int)(ph / (2 * M_PI) * NB);
    hp[b < NB ? b : NB - 1]++;
    srd_draw_axis(&r, 2, e);
    sign[e[2] > 0]++;
  }
  double c1 = 0, c2 = 0, ex = (double)NS / NB;
  for (int b = 0; b < NB; ++b) {
    c1 += (hc[b] - ex) * (hc[b] - ex) / ex;
    c2 += (hp[b] - ex) * (hp[b] - ex) / ex;
  }
  assert_true(c1 < 45.0);
  assert_true(c2 < 45.0);
  /* 2-D sign: binomial, 4 standard errors */
  GRAN_ASSERT_SIGMA((double)sign[1], NS / 2.0, sqrt(NS / 4.0), 4);
}

/* theta from sums relative to the previous cell mean keeps its digits at theta / V^2 = 1e-8; the
 * naive one-pass sum (reference 0) does not (so the test can fail). */
static void test_theta_cooled(void **state) {
  (void)state;
  gran_rng r;
  GRAN_ASSERT_OK(gran_rng_seed(&r, 3));
  const double V[3] = {1.3, -0.7, 0.4}, sd = 1e-4; /* T / V^2 ~ 1e-8 */
  double worst = 0, worst_naive = 0;
  for (int t = 0; t < 200; ++t) {
    int n = 2 + t % 30;
    double v[40][3];
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) v[i][k] = V[k] + sd * srd_rng_normal(&r);
    /* reference: previous mean, off by a thermal fluctuation */
    double ref[3], zero[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) ref[k] = V[k] + sd * srd_rng_normal(&r);
    srd_cell_sum cs, cn;
    srd_sum_clear(&cs);
    srd_sum_clear(&cn);
    for (int i = 0; i < n; ++i) {
      srd_sum_add(&cs, v[i], ref, 3);
      srd_sum_add(&cn, v[i], zero, 3);
    }
    double Vm[3], th, thn;
    srd_cell_moments(&cs, ref, 3, Vm, &th);
    srd_cell_moments(&cn, zero, 3, Vm, &thn);
    long double m[3] = {0, 0, 0}, q = 0;
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) m[k] += v[i][k];
    for (int k = 0; k < 3; ++k) m[k] /= n;
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) q += (v[i][k] - m[k]) * (v[i][k] - m[k]);
    const double exact = (double)(q / (3.0L * n));
    worst = fmax(worst, fabs(th - exact) / exact);
    worst_naive = fmax(worst_naive, fabs(thn - exact) / exact);
  }
  printf("theta rel err: reference %.3g naive %.3g\n", worst, worst_naive);
  assert_true(worst < 1e-12);       /* rounding of the sums: ~ n eps */
  assert_true(worst_naive > 1e-9);  /* the naive sum loses ~8 digits */
}

static void run_and_get(const gran_srd_options *o, int threads, int64_t steps, double **out, int64_t *nout) {
  gran_srd_options q = *o;
  q.threads = threads;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&q, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, steps));
  int64_t n;
  double *a[6];
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &a[0], &a[1], &a[2], &a[3], &a[4], &a[5]));
  double *buf = malloc(sizeof(double) * 6 * (size_t)n);
  for (int k = 0; k < 6; ++k)
    for (int64_t i = 0; i < n; ++i) buf[k * n + i] = a[k] ? a[k][i] : 0.0;
  *out = buf;
  *nout = n;
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void test_threads(void **state) {
  (void)state;
  gran_srd_options cases[3];
  cases[0] = base(3, 8);
  cases[0].eps = 0.8;
  cases[0].sigma = 0.3;
  cases[0].thermostat = 2;
  cases[1] = base(2, 12);
  cases[1].shear_rate = 0.02;
  cases[1].thermostat = 1;
  cases[2] = base(3, 6);
  cases[2].wall_axis = 2;
  cases[2].accel[2] = -0.01;
  cases[2].vib_amp = 0.1;
  cases[2].vib_omega = 0.3;
  for (int c = 0; c < 3; ++c) {
    double *a, *b;
    int64_t na, nb;
    run_and_get(&cases[c], 1, 20, &a, &na);
    run_and_get(&cases[c], 2, 20, &b, &nb);
    assert_int_equal(na, nb);
    assert_memory_equal(a, b, sizeof(double) * 6 * (size_t)na);
    free(a);
    free(b);
  }
}

static void test_checkpoint(void **state) {
  (void)state;
  char path[256];
  snprintf(path, sizeof path, "/tmp/granary-t801-%ld.ckp", (long)getpid());
  gran_srd_options o = base(3, 6);
  o.eps = 0.9;
  o.sigma = 0.2;
  o.shear_rate = 0.01;
  gran_srd *s = NULL, *t = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 13));
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(s, path, "/srd"));
  GRAN_ASSERT_OK(gran_srd_checkpoint_read(path, "/srd", &t));
  GRAN_ASSERT_OK(gran_srd_advance(s, 17));
  GRAN_ASSERT_OK(gran_srd_advance(t, 17));
  int64_t n1, n2;
  double *a[6], *b[6];
  GRAN_ASSERT_OK(gran_srd_particles(s, &n1, &a[0], &a[1], &a[2], &a[3], &a[4], &a[5]));
  GRAN_ASSERT_OK(gran_srd_particles(t, &n2, &b[0], &b[1], &b[2], &b[3], &b[4], &b[5]));
  assert_int_equal(n1, n2);
  for (int k = 0; k < 6; ++k) assert_memory_equal(a[k], b[k], sizeof(double) * (size_t)n1);
  gran_srd_obs oa, ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &oa));
  GRAN_ASSERT_OK(gran_srd_observe(t, &ob));
  assert_memory_equal(&oa, &ob, sizeof oa);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  GRAN_ASSERT_OK(gran_srd_destroy(&t));
  GRAN_ASSERT_ERR(gran_srd_checkpoint_read("/nonexistent/x.ckp", "/srd", &t), GRAN_ERR_IO);
  FILE *f = fopen(path, "wb");
  fputs("garbage", f);
  fclose(f);
  GRAN_ASSERT_ERR(gran_srd_checkpoint_read(path, "/srd", &t), GRAN_ERR_IO);
  assert_null(t);
  /* damaged files: every one of 200 single-bit flips (spread over the file, header and trailer
   * included), a truncation and an extension is refused with GRAN_ERR_IO, never a crash or an
   * allocation the file does not justify */
  remove(path); /* a new file: the garbage above is no HDF5 file to add a group to */
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_OK(gran_srd_advance(s, 3));
  GRAN_ASSERT_OK(gran_srd_checkpoint_write(s, path, "/srd"));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  f = fopen(path, "rb");
  assert_non_null(f);
  fseek(f, 0, SEEK_END);
  const long len = ftell(f);
  fseek(f, 0, SEEK_SET);
  unsigned char *img = malloc((size_t)len);
  assert_non_null(img);
  assert_int_equal(fread(img, 1, (size_t)len, f), (size_t)len);
  fclose(f);
  char bad[300];
  snprintf(bad, sizeof bad, "%s.bad", path);
  for (int trial = 0; trial < 203; ++trial) {
    long at = trial < 200 ? (long)((double)trial / 200.0 * (double)len) : 0;
    f = fopen(bad, "wb");
    assert_non_null(f);
    if (trial < 200) {
      img[at] ^= (unsigned char)(1u << (trial % 8));
      fwrite(img, 1, (size_t)len, f);
      img[at] ^= (unsigned char)(1u << (trial % 8));
    } else if (trial == 200) {
      fwrite(img, 1, (size_t)len - 100, f); /* truncated */
    } else if (trial == 201) {
      fwrite(img, 1, (size_t)len, f); /* extended */
      fputc(0, f);
    } else { /* the binary format before HDF5: refused, saying to rerun */
      fwrite("GSRDCKP2", 1, 8, f);
      fwrite(img + 8, 1, (size_t)len - 8, f);
    }
    fclose(f);
    const int rc = gran_srd_checkpoint_read(bad, "/srd", &t);
    if (rc != GRAN_ERR_IO) fprintf(stderr, "trial %d (byte %ld): rc %d\n", trial, at, rc);
    assert_int_equal(rc, GRAN_ERR_IO);
    assert_null(t);
    if (trial == 202) {
      assert_non_null(strstr(gran_last_error_message(), "GSRDCKP2"));
      assert_non_null(strstr(gran_last_error_message(), "rerun the scene"));
    }
  }
  free(img);
  remove(bad);
  /* a write that cannot happen leaves nothing behind */
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  GRAN_ASSERT_ERR(gran_srd_checkpoint_write(s, "/nonexistent-dir/x.ckp", "/srd"), GRAN_ERR_IO);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  remove(path);
}

/* S(k) from FFTW against a direct DFT of the cell counts, shell by shell; and S ~ 1 for the
 * uniform random initial positions (Poisson counts). */
static void test_structure_factor(void **state) {
  (void)state;
  gran_srd_options o = base(2, 8);
  o.n0 = 5;
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  enum { NBIN = 6 };
  double k[NBIN], sk[NBIN];
  int64_t cnt[NBIN];
  GRAN_ASSERT_OK(gran_srd_structure_factor(s, NBIN, k, sk, cnt));
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  /* direct: counts on the 8x8 grid, O(N_cells^2) DFT over every k != 0 */
  double c[64] = {0};
  for (int64_t i = 0; i < n; ++i) c[(int)floor(x[i]) + 8 * (int)floor(y[i])] += 1.0;
  double dk[NBIN] = {0}, ds[NBIN] = {0};
  int64_t dc[NBIN] = {0};
  const double kmax = sqrt(2.0) * M_PI, w = kmax / NBIN, mean = (double)n / 64;
  for (int m1 = -3; m1 <= 4; ++m1)
    for (int m0 = -3; m0 <= 4; ++m0) {
      if (!m0 && !m1) continue;
      double re = 0, im = 0;
      for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
          double ph = -2 * M_PI * (m0 * i + m1 * j) / 8.0;
          re += (c[i + 8 * j] - mean) * cos(ph);
          im += (c[i + 8 * j] - mean) * sin(ph);
        }
      double kk = 2 * M_PI / 8 * sqrt((double)(m0 * m0 + m1 * m1));
      int b = (int)(kk / w);
      if (b >= NBIN) b = NBIN - 1;
      dk[b] += kk;
      ds[b] += (re * re + im * im) / n;
      dc[b]++;
    }
  double tot = 0;
  int64_t tc = 0;
  for (int b = 0; b < NBIN; ++b) {
    assert_int_equal(cnt[b], dc[b]);
    if (dc[b]) {
      GRAN_ASSERT_REL(k[b], dk[b] / dc[b], 1e-12);
      GRAN_ASSERT_REL(sk[b], ds[b] / dc[b], 1e-10);
    }
    tot += sk[b] * cnt[b];
    tc += cnt[b];
  }
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
  /* uncorrelated positions: each |rho_k|^2/N is ~ exponential with mean 1 - 1/N_cells... use a
   * bigger box: 64^2 cells, mean over all modes, standard error 1/sqrt(modes) */
  o = base(2, 64);
  o.n0 = 3;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  double k2[8], s2[8];
  int64_t c2[8];
  GRAN_ASSERT_OK(gran_srd_structure_factor(s, 8, k2, s2, c2));
  double sum = 0;
  int64_t m = 0;
  for (int b = 0; b < 8; ++b) {
    sum += s2[b] * c2[b];
    m += c2[b];
  }
  /* fixed N: S(k) = 1 exactly in expectation for k != 0 (multinomial counts) */
  GRAN_ASSERT_SIGMA(sum / m, 1.0, 1.0 / sqrt((double)m / 2), 4);
  for (int b = 1; b < 8; ++b) GRAN_ASSERT_SIGMA(s2[b], 1.0, 1.0 / sqrt((double)c2[b] / 2), 5);
  GRAN_ASSERT_ERR(gran_srd_structure_factor(s, 0, k2, s2, c2), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

static void bad(gran_srd_options o, const char *name) {
  gran_srd *s = NULL;
  GRAN_ASSERT_ERR(gran_srd_create(&o, &s), GRAN_ERR_ARG);
  assert_null(s);
  if (!strstr(gran_last_error_message(), name)) fail_msg("message '%s' does not name '%s'", gran_last_error_message(), name);
}

static void test_bad_options(void **state) {
  (void)state;
  gran_srd_options o = base(3, 4), q;
  q = o; q.alpha_deg = 0; bad(q, "'alpha'");
  q = o; q.alpha_deg = 181; bad(q, "'alpha'");
  q = o; q.n0 = 0; bad(q, "'n0'");
  q = o; q.dt = -1; bad(q, "'dt'");
  q = o; q.dim = 4; bad(q, "'dim'");
  q = o; q.cells[1] = 0; bad(q, "'cells[1]'");
  q = o; q.eps = 1.5; bad(q, "'eps'");
  q = o; q.T0 = 0; bad(q, "'T0'");
  q = o; q.a = NAN; bad(q, "'a'");
  q = o; q.shear_rate = 0.1; q.wall_axis = 1; bad(q, "same axis");
  q = o; q.wall_axis = 2; q.wall_rule = 5; bad(q, "'wall_rule'");
  q = o; q.vib_amp = 1; bad(q, "'vib_amp'");
  q = o; q.thermostat = 3; bad(q, "'thermostat'");
  {
    gran_srd *t = NULL; /* the global thermostat runs on a device too (t890 compares it with the CPU engine) */
    q = o;
    q.thermostat = 2;
    q.device = GRAN_SRD_DEVICE_REFERENCE;
    GRAN_ASSERT_OK(gran_srd_create(&q, &t));
    int32_t d = -1;
    GRAN_ASSERT_OK(gran_srd_get_device(t, &d));
    assert_int_equal(d, GRAN_SRD_DEVICE_REFERENCE);
    GRAN_ASSERT_OK(gran_srd_advance(t, 2));
    GRAN_ASSERT_OK(gran_srd_destroy(&t));
  }
  gran_srd *s = NULL;
  GRAN_ASSERT_ERR(gran_srd_create(NULL, &s), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_advance(NULL, 1), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_srd_destroy(NULL));
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_conservation),       cmocka_unit_test(test_ledger_effects),
      cmocka_unit_test(test_rotation_invariants), cmocka_unit_test(test_axis_uniform),
      cmocka_unit_test(test_theta_cooled),       cmocka_unit_test(test_threads),
      cmocka_unit_test(test_checkpoint),         cmocka_unit_test(test_structure_factor),
      cmocka_unit_test(test_bad_options),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
