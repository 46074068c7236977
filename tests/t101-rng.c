/* t101-rng.c - xoshiro256**: known answers against Vigna's reference code (copied below,
 * independent of the library), jumps, streams, moments and chi-square tests of every
 * distribution, exact boundaries of the uniform maps, argument errors.
 *
 * Statistical assertions use fixed seeds and K_SIGMA = 4 standard errors (two-sided false-alarm
 * probability 6e-5 per assertion for a correct generator had the seed been random); chi-square
 * tests use significance 1e-3 (critical value from the Wilson-Hilferty approximation). */
#include "granary_test.h"

#define K_SIGMA 4.0

/* ---- Vigna's reference code, literally (xoshiro256starstar.c and splitmix64.c, public domain),
 * only renamed so that it cannot collide with anything else ------------------------------------ */
static inline uint64_t ref_rotl(const uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static uint64_t s[4];

static uint64_t ref_next(void) {
  const uint64_t result = ref_rotl(s[1] * 5, 7) * 9;
  const uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = ref_rotl(s[3], 45);
  return result;
}

static void ref_jump(void) {
  static const uint64_t JUMP[] = {0x180ec6d33cfd0aba, 0xd5a61266f0c9392c, 0xa9582618e03fc9aa,
                                  0x39abdc4529b1661c};
  uint64_t s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  for (size_t i = 0; i < sizeof JUMP / sizeof *JUMP; i++)
    for (int b = 0; b < 64; b++) {
      if (JUMP[i] & UINT64_C(1) << b) {
        s0 ^= s[0];
        s1 ^= s[1];
        s2 ^= s[2];
        s3 ^= s[3];
      }
      ref_next();
    }
  s[0] = s0;
  s[1] = s1;
  s[2] = s2;
  s[3] = s3;
}

static void ref_long_jump(void) {
  static const uint64_t LONG_JUMP[] = {0x76e15d3efefdcbbf, 0xc5004e441c522fb3, 0x77710069854ee241,
                                       0x39109bb02acbe635};
  uint64_t s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  for (size_t i = 0; i < sizeof LONG_JUMP / sizeof *LONG_JUMP; i++)
    for (int b = 0; b < 64; b++) {
      if (LONG_JUMP[i] & UINT64_C(1) << b) {
        s0 ^= s[0];
        s1 ^= s[1];
        s2 ^= s[2];
        s3 ^= s[3];
      }
      ref_next();
    }
  s[0] = s0;
  s[1] = s1;
  s[2] = s2;
  s[3] = s3;
}

static uint64_t x; /* splitmix64 state */

static uint64_t ref_splitmix64(void) {
  uint64_t z = (x += 0x9e3779b97f4a7c15);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9;
  z = (z ^ (z >> 27)) * 0x94d049bb133111eb;
  return z ^ (z >> 31);
}

/* reference seeding: four splitmix64 outputs */
static void ref_seed(uint64_t seed) {
  x = seed;
  for (int i = 0; i < 4; i++) s[i] = ref_splitmix64();
}

/* ---- helpers ------------------------------------------------------------------------------- */
#define NOUT 1000

static void assert_lib_matches_ref(gran_rng *g) {
  uint64_t out[NOUT];
  GRAN_ASSERT_OK(gran_rng_u64(g, NOUT, out));
  for (int i = 0; i < NOUT; i++)
    if (out[i] != ref_next()) fail_msg("output %d differs from the reference", i);
  for (int w = 0; w < 4; w++) assert_true(g->s[w] == s[w]);
}

/* chi-square critical value at significance 1e-3 (z = 3.0902), Wilson-Hilferty */
static double chi2_crit(int df) {
  const double z = 3.090232, a = 2.0 / (9.0 * df);
  const double c = 1.0 - a + z * sqrt(a);
  return df * c * c * c;
}

/* chi-square of counts against probabilities p (sum 1) for n draws */
static double chi2_stat(int nbins, const int64_t *counts, const double *p, int64_t n) {
  double chi2 = 0;
  for (int k = 0; k < nbins; k++) {
    const double e = p[k] * (double)n;
    if (e < 5) fail_msg("bin %d expects %.2f < 5 counts: bad test design", k, e);
    chi2 += ((double)counts[k] - e) * ((double)counts[k] - e) / e;
  }
  return chi2;
}

static int imin(int a, int b) { return a < b ? a : b; }

/* mean and standard error of the mean of f over n values */
static void mean_se(const double *f, int64_t n, double *mean, double *se) {
  double m = 0, q = 0;
  for (int64_t i = 0; i < n; i++) m += f[i];
  m /= (double)n;
  for (int64_t i = 0; i < n; i++) q += (f[i] - m) * (f[i] - m);
  *mean = m;
  *se = sqrt(q / (double)(n - 1) / (double)n);
}

/* ---- known answers --------------------------------------------------------------------------- */
static void test_known_answers_state_1234(void **state) {
  (void)state;
  gran_rng g = {{1, 2, 3, 4}};
  uint64_t out[4];
  GRAN_ASSERT_OK(gran_rng_u64(&g, 4, out));
  /* published first outputs of xoshiro256** from state {1,2,3,4} */
  assert_true(out[0] == UINT64_C(11520));
  assert_true(out[1] == UINT64_C(0));
  assert_true(out[2] == UINT64_C(1509978240));
  assert_true(out[3] == UINT64_C(1215971899390074240));
  /* the same from the reference copy */
  s[0] = 1, s[1] = 2, s[2] = 3, s[3] = 4;
  for (int i = 0; i < 4; i++) assert_true(out[i] == ref_next());
  /* first outputs after jump / long_jump from {1,2,3,4} (values of the reference code, hard-coded
   * so that a shared mistake of library and copy would show; the Fortran twin checks them too) */
  gran_rng j = {{1, 2, 3, 4}}, l = {{1, 2, 3, 4}};
  GRAN_ASSERT_OK(gran_rng_jump(&j));
  GRAN_ASSERT_OK(gran_rng_u64(&j, 2, out));
  assert_true(out[0] == UINT64_C(13534147089533256664) && out[1] == UINT64_C(7126240192422241655));
  GRAN_ASSERT_OK(gran_rng_long_jump(&l));
  GRAN_ASSERT_OK(gran_rng_u64(&l, 2, out));
  assert_true(out[0] == UINT64_C(5942309088398569549) && out[1] == UINT64_C(15625447729937358436));
}

static void test_seed_is_splitmix64(void **state) {
  (void)state;
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 0));
  /* splitmix64 from x = 0: first three outputs (published test vector) */
  assert_true(g.s[0] == UINT64_C(0xe220a8397b1dcdaf));
  assert_true(g.s[1] == UINT64_C(0x6e789e6aa1b965f4));
  assert_true(g.s[2] == UINT64_C(0x06c45d188009454f));
  const uint64_t seeds[] = {0, 1, 42, UINT64_C(0xdeadbeefcafef00d), UINT64_MAX};
  for (size_t k = 0; k < sizeof seeds / sizeof *seeds; k++) {
    GRAN_ASSERT_OK(gran_rng_seed(&g, seeds[k]));
    ref_seed(seeds[k]);
    for (int w = 0; w < 4; w++) assert_true(g.s[w] == s[w]);
    assert_lib_matches_ref(&g);
  }
}

static void test_jump_and_long_jump(void **state) {
  (void)state;
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 12345));
  ref_seed(12345);
  for (int rep = 0; rep < 3; rep++) {
    GRAN_ASSERT_OK(gran_rng_jump(&g));
    ref_jump();
    assert_lib_matches_ref(&g);
  }
  for (int rep = 0; rep < 3; rep++) {
    GRAN_ASSERT_OK(gran_rng_long_jump(&g));
    ref_long_jump();
    assert_lib_matches_ref(&g);
  }
  /* and from the hand-made state {1,2,3,4} */
  gran_rng h = {{1, 2, 3, 4}};
  s[0] = 1, s[1] = 2, s[2] = 3, s[3] = 4;
  GRAN_ASSERT_OK(gran_rng_jump(&h));
  ref_jump();
  assert_lib_matches_ref(&h);
}

/* ---- streams --------------------------------------------------------------------------------- */
static void test_stream_equals_repeated_jumps(void **state) {
  (void)state;
  const uint64_t seed = 2024;
  gran_rng ref, g;
  GRAN_ASSERT_OK(gran_rng_seed(&ref, seed));
  /* stream k == seed + k jumps, for every k up to 1000: checks the polynomials of bits 0..9 */
  for (uint64_t k = 0; k <= 1000; k++) {
    GRAN_ASSERT_OK(gran_rng_stream(seed, k, &g));
    for (int w = 0; w < 4; w++)
      if (g.s[w] != ref.s[w]) fail_msg("stream %d differs from %d jumps", (int)k, (int)k);
    GRAN_ASSERT_OK(gran_rng_jump(&ref));
  }
}

static void test_streams_reproducible_and_uncorrelated(void **state) {
  (void)state;
  const uint64_t ids[] = {0, 1, 2, 3, 1000, UINT64_C(1) << 40, (UINT64_C(1) << 63) + 7, UINT64_MAX};
  const int nid = (int)(sizeof ids / sizeof *ids);
  const int64_t n = 200000;
  double *u = malloc(sizeof(double) * (size_t)(n * nid));
  assert_non_null(u);
  for (int a = 0; a < nid; a++) {
    gran_rng g, h;
    GRAN_ASSERT_OK(gran_rng_stream(77, ids[a], &g));
    GRAN_ASSERT_OK(gran_rng_stream(77, ids[a], &h));
    assert_memory_equal(&g, &h, sizeof g); /* same (seed, id): same stream */
    GRAN_ASSERT_OK(gran_rng_uniform(&g, n, u + a * n));
  }
  /* Pearson correlation between every pair of streams, and between successive values of one
   * stream: se = 1/sqrt(n) for independent uniforms */
  const double se = 1.0 / sqrt((double)n);
  for (int a = 0; a < nid; a++)
    for (int b = a; b < nid; b++) {
      const double *x1 = u + a * n, *x2 = u + b * n + (a == b ? 1 : 0);
      const int64_t m = n - (a == b ? 1 : 0);
      double c = 0;
      for (int64_t i = 0; i < m; i++) c += (x1[i] - 0.5) * (x2[i] - 0.5);
      c /= (double)m / 12.0;
      GRAN_ASSERT_SIGMA(c, 0.0, se, K_SIGMA);
      if (a != b) assert_true(x1[0] != x2[0] || x1[1] != x2[1]);
    }
  /* a different seed gives a different stream 0 */
  gran_rng g1, g2;
  GRAN_ASSERT_OK(gran_rng_stream(77, 0, &g1));
  GRAN_ASSERT_OK(gran_rng_stream(78, 0, &g2));
  assert_true(memcmp(&g1, &g2, sizeof g1) != 0);
  free(u);
}

/* ---- exact boundaries of the uniform maps ------------------------------------------------- */
/* inverse of an odd number modulo 2^64 (Newton) */
static uint64_t inv64(uint64_t a) {
  uint64_t y = a;
  for (int i = 0; i < 6; i++) y *= 2 - a * y;
  return y;
}

/* a state whose next output is `out` (the output depends on s[1] only) */
static gran_rng state_for_output(uint64_t out) {
  const uint64_t y = out * inv64(9);            /* rotl(s1*5, 7) */
  const uint64_t z = (y >> 7) | (y << 57);      /* s1*5 */
  gran_rng g = {{0x1234, z * inv64(5), 0x5678, 0x9abc}};
  return g;
}

static void test_uniform_boundaries(void **state) {
  (void)state;
  double u;
  gran_rng g = state_for_output(UINT64_MAX);
  gran_rng h = g;
  uint64_t raw;
  GRAN_ASSERT_OK(gran_rng_u64(&h, 1, &raw));
  assert_true(raw == UINT64_MAX); /* the construction works */
  h = g;
  GRAN_ASSERT_OK(gran_rng_uniform(&h, 1, &u));
  assert_true(u == 1.0 - 0x1.0p-53); /* largest value: strictly below 1 */
  h = g;
  GRAN_ASSERT_OK(gran_rng_uniform_pos(&h, 1, &u));
  assert_true(u == 1.0);
  h = g;
  GRAN_ASSERT_OK(gran_rng_exponential(&h, 1, &u));
  assert_true(u == 0.0);

  g = state_for_output(0);
  h = g;
  GRAN_ASSERT_OK(gran_rng_u64(&h, 1, &raw));
  assert_true(raw == 0);
  h = g;
  GRAN_ASSERT_OK(gran_rng_uniform(&h, 1, &u));
  assert_true(u == 0.0);
  h = g;
  GRAN_ASSERT_OK(gran_rng_uniform_pos(&h, 1, &u));
  assert_true(u == 0x1.0p-53); /* smallest value: strictly above 0 */
  h = g;
  GRAN_ASSERT_OK(gran_rng_exponential(&h, 1, &u));
  GRAN_ASSERT_REL(u, 53.0 * log(2.0), 1e-15); /* -log(2^-53): finite */

  /* and over a long run */
  const int64_t n = 1000000;
  double *v = malloc(sizeof(double) * (size_t)n);
  assert_non_null(v);
  GRAN_ASSERT_OK(gran_rng_seed(&g, 9));
  GRAN_ASSERT_OK(gran_rng_uniform(&g, n, v));
  for (int64_t i = 0; i < n; i++) assert_true(v[i] >= 0.0 && v[i] < 1.0);
  GRAN_ASSERT_OK(gran_rng_uniform_pos(&g, n, v));
  for (int64_t i = 0; i < n; i++) assert_true(v[i] > 0.0 && v[i] <= 1.0);
  free(v);
}

/* ---- moments --------------------------------------------------------------------------------- */
#define NMOM 1000000

static void test_moments_scalar(void **state) {
  (void)state;
  double *v = malloc(sizeof(double) * NMOM), *f = malloc(sizeof(double) * NMOM);
  assert_non_null(v);
  assert_non_null(f);
  gran_rng g;
  double m, se;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 101));

  /* uniform [0,1): <u> = 1/2, <(u-1/2)^2> = 1/12 */
  GRAN_ASSERT_OK(gran_rng_uniform(&g, NMOM, v));
  mean_se(v, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 0.5, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = (v[i] - 0.5) * (v[i] - 0.5);
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 1.0 / 12.0, se, K_SIGMA);

  /* uniform (0,1] */
  GRAN_ASSERT_OK(gran_rng_uniform_pos(&g, NMOM, v));
  mean_se(v, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 0.5, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = (v[i] - 0.5) * (v[i] - 0.5);
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 1.0 / 12.0, se, K_SIGMA);

  /* exponential: <x> = 1, <x^2> = 2, <x^3> = 6 */
  GRAN_ASSERT_OK(gran_rng_exponential(&g, NMOM, v));
  mean_se(v, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 1.0, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = v[i] * v[i];
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 2.0, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = v[i] * v[i] * v[i];
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 6.0, se, K_SIGMA);

  /* normal: <x> = 0, <x^2> = 1, <x^3> = 0, <x^4> = 3 */
  GRAN_ASSERT_OK(gran_rng_normal(&g, NMOM, v));
  mean_se(v, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 0.0, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = v[i] * v[i];
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 1.0, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = v[i] * v[i] * v[i];
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 0.0, se, K_SIGMA);
  for (int i = 0; i < NMOM; i++) f[i] = v[i] * v[i] * v[i] * v[i];
  mean_se(f, NMOM, &m, &se);
  GRAN_ASSERT_SIGMA(m, 3.0, se, K_SIGMA);
  free(v);
  free(f);
}

/* unit vectors in d dimensions: |e| = 1, <e_i> = 0, <e_i e_j> = delta_ij / d */
static void check_unit_vectors(int d, int64_t n, const double *e) {
  double *f = malloc(sizeof(double) * (size_t)n);
  assert_non_null(f);
  double m, se;
  for (int64_t k = 0; k < n; k++) {
    double r2 = 0;
    for (int i = 0; i < d; i++) r2 += e[d * k + i] * e[d * k + i];
    if (fabs(sqrt(r2) - 1.0) > 4e-16) fail_msg("|e| - 1 = %g for vector %d", sqrt(r2) - 1.0, (int)k);
  }
  for (int i = 0; i < d; i++) {
    for (int64_t k = 0; k < n; k++) f[k] = e[d * k + i];
    mean_se(f, n, &m, &se);
    GRAN_ASSERT_SIGMA(m, 0.0, se, K_SIGMA);
    for (int j = i; j < d; j++) {
      for (int64_t k = 0; k < n; k++) f[k] = e[d * k + i] * e[d * k + j];
      mean_se(f, n, &m, &se);
      GRAN_ASSERT_SIGMA(m, i == j ? 1.0 / d : 0.0, se, K_SIGMA);
    }
  }
  free(f);
}

static void test_unit_vectors(void **state) {
  (void)state;
  const int64_t n = 500000;
  double *e = malloc(sizeof(double) * 3 * (size_t)n);
  assert_non_null(e);
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 303));
  GRAN_ASSERT_OK(gran_rng_unit_vector3(&g, n, e));
  check_unit_vectors(3, n, e);
  /* Archimedes: e_z is uniform on [-1,1], so <e_z^4> = 1/5 */
  double m4 = 0;
  for (int64_t k = 0; k < n; k++) m4 += pow(e[3 * k + 2], 4);
  m4 /= (double)n;
  GRAN_ASSERT_SIGMA(m4, 0.2, sqrt((1.0 / 9.0 - 1.0 / 25.0) / (double)n), K_SIGMA);
  GRAN_ASSERT_OK(gran_rng_unit_vector2(&g, n, e));
  check_unit_vectors(2, n, e);
  free(e);
}

/* ---- chi-square ------------------------------------------------------------------------------ */
static void test_chi_square(void **state) {
  (void)state;
  const int64_t n = 1000000;
  double *v = malloc(sizeof(double) * (size_t)n);
  assert_non_null(v);
  int64_t counts[128];
  double p[128];
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 404));

  /* uniform: 100 equal bins */
  GRAN_ASSERT_OK(gran_rng_uniform(&g, n, v));
  memset(counts, 0, sizeof counts);
  for (int64_t i = 0; i < n; i++) counts[imin((int)(v[i] * 100), 99)]++; /* 100*(1-2^-53) may round to 100 */
  for (int k = 0; k < 100; k++) p[k] = 0.01;
  double c2 = chi2_stat(100, counts, p, n);
  if (c2 > chi2_crit(99)) fail_msg("uniform chi2 = %g > %g", c2, chi2_crit(99));

  /* exponential: 80 bins of width 0.1 on [0, 8) and a tail bin */
  GRAN_ASSERT_OK(gran_rng_exponential(&g, n, v));
  memset(counts, 0, sizeof counts);
  for (int64_t i = 0; i < n; i++) counts[v[i] >= 8.0 ? 80 : imin((int)(v[i] * 10), 79)]++;
  for (int k = 0; k < 80; k++) p[k] = exp(-0.1 * k) - exp(-0.1 * (k + 1));
  p[80] = exp(-8.0);
  c2 = chi2_stat(81, counts, p, n);
  if (c2 > chi2_crit(80)) fail_msg("exponential chi2 = %g > %g", c2, chi2_crit(80));

  /* normal: 80 bins of width 0.1 on [-4, 4) and two tail bins */
  GRAN_ASSERT_OK(gran_rng_normal(&g, n, v));
  memset(counts, 0, sizeof counts);
  for (int64_t i = 0; i < n; i++) {
    int k = v[i] < -4.0 ? 0 : v[i] >= 4.0 ? 81 : 1 + (int)floor((v[i] + 4.0) * 10);
    if (k > 81 || (k == 81 && v[i] < 4.0)) k = 80; /* rounding just below 4 */
    counts[k]++;
  }
  p[0] = p[81] = 0.5 * erfc(4.0 / sqrt(2.0));
  for (int k = 0; k < 80; k++) {
    const double a = -4.0 + 0.1 * k, b = a + 0.1;
    p[1 + k] = 0.5 * (erf(b / sqrt(2.0)) - erf(a / sqrt(2.0)));
  }
  c2 = chi2_stat(82, counts, p, n);
  if (c2 > chi2_crit(81)) fail_msg("normal chi2 = %g > %g", c2, chi2_crit(81));
  free(v);
}

/* ---- batch equals the sequence, n = 0, errors ------------------------------------------------ */
static void test_errors(void **state) {
  (void)state;
  gran_rng g;
  double d[3];
  uint64_t u[3];
  GRAN_ASSERT_ERR(gran_rng_seed(NULL, 1), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_rng_stream(1, 2, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_rng_jump(NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_rng_long_jump(NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_rng_seed(&g, 1));
  GRAN_ASSERT_ERR(gran_rng_u64(NULL, 1, u), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_rng_u64(&g, -1, u), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'n'"));
  GRAN_ASSERT_ERR(gran_rng_u64(&g, 1, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'out'"));
  int (*dfun[])(gran_rng *, int64_t, double *) = {gran_rng_uniform, gran_rng_uniform_pos, gran_rng_exponential,
                                                 gran_rng_normal, gran_rng_unit_vector3, gran_rng_unit_vector2};
  for (size_t k = 0; k < sizeof dfun / sizeof *dfun; k++) {
    GRAN_ASSERT_ERR(dfun[k](NULL, 1, d), GRAN_ERR_ARG);
    GRAN_ASSERT_ERR(dfun[k](&g, -1, d), GRAN_ERR_ARG);
    GRAN_ASSERT_ERR(dfun[k](&g, 1, NULL), GRAN_ERR_ARG);
    gran_rng before = g;
    GRAN_ASSERT_OK(dfun[k](&g, 0, NULL)); /* n = 0: nothing drawn, state unchanged */
    assert_memory_equal(&before, &g, sizeof g);
  }
  /* a failed call leaves the state alone */
  gran_rng before = g;
  GRAN_ASSERT_ERR(gran_rng_normal(&g, -5, d), GRAN_ERR_ARG);
  assert_memory_equal(&before, &g, sizeof g);
}

/* batch calls continue one sequence: 2 + 3 draws == 5 draws */
static void test_batches_continue(void **state) {
  (void)state;
  gran_rng a, b;
  double x[5], y[5];
  GRAN_ASSERT_OK(gran_rng_seed(&a, 5));
  b = a;
  GRAN_ASSERT_OK(gran_rng_normal(&a, 5, x));
  GRAN_ASSERT_OK(gran_rng_normal(&b, 2, y));
  GRAN_ASSERT_OK(gran_rng_normal(&b, 3, y + 2));
  assert_memory_equal(x, y, sizeof x);
  assert_memory_equal(&a, &b, sizeof a);
}

/* the CUDA entry point never crashes: without a GPU it says so, with one it matches the CPU */
static void test_cuda_uniform_available_or_unsupported(void **state) {
  (void)state;
  gran_rng st[3];
  double out[3 * 4], ref[4];
  for (int k = 0; k < 3; k++) GRAN_ASSERT_OK(gran_rng_stream(8, (uint64_t)k, &st[k]));
  gran_clear_error();
  const int ierr = gran_cuda_rng_uniform(st, 3, 4, out);
  if (ierr == GRAN_ERR_UNSUPPORTED) {
    assert_true(gran_last_error_message()[0] != '\0');
    return;
  }
  GRAN_ASSERT_OK(ierr);
  for (int k = 0; k < 3; k++) {
    gran_rng g = st[k];
    GRAN_ASSERT_OK(gran_rng_uniform(&g, 4, ref));
    assert_memory_equal(out + 4 * k, ref, sizeof ref);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_known_answers_state_1234),
      cmocka_unit_test(test_seed_is_splitmix64),
      cmocka_unit_test(test_jump_and_long_jump),
      cmocka_unit_test(test_stream_equals_repeated_jumps),
      cmocka_unit_test(test_streams_reproducible_and_uncorrelated),
      cmocka_unit_test(test_uniform_boundaries),
      cmocka_unit_test(test_moments_scalar),
      cmocka_unit_test(test_unit_vectors),
      cmocka_unit_test(test_chi_square),
      cmocka_unit_test(test_errors),
      cmocka_unit_test(test_batches_continue),
      cmocka_unit_test(test_cuda_uniform_available_or_unsupported),
  };
  return cmocka_run_group_tests_name("t101-rng", tests, NULL, NULL);
}
