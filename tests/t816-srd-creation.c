/* t816-srd-creation.c - the exact accumulator (src/core/exactsum.h) and the GSRD creation by
 * cells (src/srd/create.h, gran_srd_options.creation):
 *  - exact sums: 1e5 values over the whole exponent range in 20 random permutations and random
 *    groupings (merged accumulators) give the same state and bits; sums equal the exact sum
 *    correctly rounded (an __int128 fixed-point reference over a limited exponent range, and wide
 *    ranges that cancel exactly down to such a sum); the hard cases (1e308 + 1e308 - 1e308,
 *    1 + 1e-300 - 1, signed zeros, subnormals, ties, sticky bits far below, overflow, inf, NaN);
 *  - creation by cells: the cells of [0, ncell) split into P = 1, 2, 3, 4, 7 uneven ranges give,
 *    concatenated, the one-range particles bit for bit; the engine's particles are those (mean
 *    momentum removed, shear profile added) for 1 and 3 threads, in cell order;
 *  - statistics (fixed seeds, 4 se): counts sum to N, their variance n0 (1 - 1/ncell), the left
 *    half's share Binomial(N, 1/2), T = T0, positions uniform inside the cells, momentum zero to
 *    1e-12; 50 steps of a cooling gas (2-D, 32^2) give the same T from either creation;
 *  - a bad 'creation' is refused naming it; the scene key sets it. */
#include "io_test_util.h" /* first: it sets the feature macros */

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "granary_test.h"
#include "core/exactsum.h"
#include "srd/create.h"

/* ---- a test generator (splitmix64) ---- */
static uint64_t sm_state;
static uint64_t sm_next(void) {
  uint64_t z = (sm_state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
static double from_bits(uint64_t u) {
  double x;
  memcpy(&x, &u, sizeof x);
  return x;
}
static uint64_t bits_of(double x) {
  uint64_t u;
  memcpy(&u, &x, sizeof u);
  return u;
}
/* a random finite double, exponent field uniform in [e_lo, e_hi] (0: subnormal), random sign */
static double rand_double(int e_lo, int e_hi) {
  const uint64_t E = (uint64_t)(e_lo + (int)(sm_next() % (uint64_t)(e_hi - e_lo + 1)));
  const uint64_t frac = sm_next() & ((1ULL << 52) - 1);
  return from_bits((sm_next() & 1ULL) << 63 | E << 52 | frac);
}
static void shuffle(double *v, int64_t n) {
  for (int64_t i = n - 1; i > 0; --i) {
    const int64_t j = (int64_t)(sm_next() % (uint64_t)(i + 1));
    const double t = v[i];
    v[i] = v[j];
    v[j] = t;
  }
}

static double sum_of(const double *v, int64_t n) {
  gran_exactsum a;
  gran_exactsum_init_(&a);
  for (int64_t i = 0; i < n; ++i) gran_exactsum_add_(&a, v[i]);
  return gran_exactsum_value_(&a);
}

/* the sum of v in random groups (each its own accumulator) merged in random order; *st: state */
static double grouped_sum(const double *v, int64_t n, gran_exactsum *st) {
  enum { G = 37 };
  static gran_exactsum g[G];
  for (int k = 0; k < G; ++k) gran_exactsum_init_(&g[k]);
  for (int64_t i = 0; i < n; ++i) gran_exactsum_add_(&g[sm_next() % G], v[i]);
  int order[G];
  for (int k = 0; k < G; ++k) order[k] = k;
  for (int k = G - 1; k > 0; --k) {
    const int j = (int)(sm_next() % (uint64_t)(k + 1)), t = order[k];
    order[k] = order[j];
    order[j] = t;
  }
  gran_exactsum_init_(st);
  for (int k = 0; k < G; ++k) gran_exactsum_merge_(st, &g[order[k]]);
  return gran_exactsum_value_(st);
}

static void test_exact_permutations(void **state) {
  (void)state;
  enum { N = 100000 };
  double *v = malloc(N * sizeof *v);
  assert_non_null(v);
  sm_state = 11;
  for (int64_t i = 0; i < N; ++i) v[i] = rand_double(0, 2046);
  gran_exactsum ref;
  gran_exactsum_init_(&ref);
  for (int64_t i = 0; i < N; ++i) gran_exactsum_add_(&ref, v[i]);
  const uint64_t want = bits_of(gran_exactsum_value_(&ref));
  for (int r = 0; r < 20; ++r) {
    shuffle(v, N);
    assert_true(bits_of(sum_of(v, N)) == want);
    gran_exactsum st;
    assert_true(bits_of(grouped_sum(v, N, &st)) == want);
    assert_memory_equal(st.limb, ref.limb, sizeof ref.limb); /* the same exact state */
  }
  /* values and their negatives over the whole range cancel exactly: the sum is that of the rest */
  for (int64_t i = 0; i < N / 2; ++i) v[N / 2 + i] = -v[i];
  assert_true(bits_of(sum_of(v, N)) == 0); /* +0 */
  free(v);
}

/* x = m 2^(s - 100), |m| < 2^53, s in [0, 50]: the exact sum is an __int128 in units 2^-100 */
static void test_exact_rounding(void **state) {
  (void)state;
  enum { N = 100000 };
  double *v = malloc(2 * N * sizeof *v);
  assert_non_null(v);
  sm_state = 12;
  for (int rep = 0; rep < 10; ++rep) {
    __int128 t = 0;
    for (int64_t i = 0; i < N; ++i) {
      int64_t m = (int64_t)(sm_next() >> 11);
      if (rep % 2) m >>= (int)(sm_next() % 50); /* some short mantissas: ties and exact halves */
      if (sm_next() & 1) m = -m;
      const int s = (int)(sm_next() % 51);
      v[i] = ldexp((double)m, s - 100);
      t += (__int128)m * ((__int128)1 << s);
    }
    const double want = ldexp((double)t, -100); /* (double) of an __int128 rounds to nearest even */
    assert_true(bits_of(sum_of(v, N)) == bits_of(want));
    /* the same plus wide-range values and their negatives, shuffled: still the same bits */
    for (int64_t i = 0; i < N / 2; ++i) {
      v[N + 2 * i] = rand_double(1, 2046);
      v[N + 2 * i + 1] = -v[N + 2 * i];
    }
    shuffle(v, 2 * N);
    assert_true(bits_of(sum_of(v, 2 * N)) == bits_of(want));
  }
  /* subnormals: m 2^-1074 */
  {
    __int128 t = 0;
    for (int64_t i = 0; i < N; ++i) {
      const int64_t m = (int64_t)(sm_next() >> 12) * ((sm_next() & 1) ? 1 : -1);
      v[i] = ldexp((double)m, -1074);
      t += m;
    }
    assert_true(bits_of(sum_of(v, N)) == bits_of(ldexp((double)t, -1074)));
  }
  /* many equal tiny values onto 1: 1 + 1e5 x 1e-20, exact in units 2^-119 */
  {
    int e;
    const double d = 1e-20, md = frexp(d, &e); /* d = md 2^e, md in [0.5, 1) */
    const int64_t m = (int64_t)ldexp(md, 53);  /* d = m 2^(e - 53) */
    assert_int_equal(e - 53, -119);
    __int128 t = ((__int128)1 << 119) + (__int128)m * N;
    v[0] = 1.0;
    for (int64_t i = 1; i <= N; ++i) v[i] = d;
    const double want = ldexp((double)t, -119);
    assert_true(want > 1.0);
    assert_true(bits_of(sum_of(v, N + 1)) == bits_of(want));
  }
  free(v);
}

static double sum3(double a, double b, double c, int order) {
  const double v[6][3] = {{a, b, c}, {a, c, b}, {b, a, c}, {b, c, a}, {c, a, b}, {c, b, a}};
  return sum_of(v[order], 3);
}

static void test_exact_hard(void **state) {
  (void)state;
  const double tiny = 0x1p-1074, big = 1e308;
  for (int k = 0; k < 6; ++k) {
    assert_true(sum3(big, big, -big, k) == big); /* no spurious inf */
    assert_true(sum3(1.0, 1e-300, -1.0, k) == 1e-300);
    assert_true(sum3(1.0, 0x1p-53, 0x1p-1074, k) == nextafter(1.0, 2.0)); /* a sticky bit 1021 bits below */
    assert_true(sum3(DBL_MAX, 0x1p970, 0.0, k) == HUGE_VAL);                /* a tie at DBL_MAX: to even = up */
    assert_true(sum3(DBL_MAX, 0x1p969, 0.0, k) == DBL_MAX);
    assert_true(sum3(-DBL_MAX, -DBL_MAX, DBL_MAX, k) == -DBL_MAX);
    assert_true(sum3(-DBL_MAX, -DBL_MAX, 0.0, k) == -HUGE_VAL); /* a final overflow */
    assert_true(sum3(DBL_MIN, -tiny, 0.0, k) == nextafter(DBL_MIN, 0.0)); /* the largest subnormal */
    assert_true(sum3(tiny, tiny, tiny, k) == 3 * tiny);
    assert_true(isnan(sum3(HUGE_VAL, -HUGE_VAL, 1.0, k)));
    assert_true(isnan(sum3(NAN, 1.0, 2.0, k)));
    assert_true(sum3(HUGE_VAL, -DBL_MAX, -DBL_MAX, k) == HUGE_VAL);
    assert_true(sum3(-HUGE_VAL, 5.0, 1e300, k) == -HUGE_VAL);
  }
  assert_true(sum_of((const double[]){1.0, 0x1p-53}, 2) == 1.0);                    /* tie to even: down */
  assert_true(sum_of((const double[]){nextafter(1.0, 2.0), 0x1p-53}, 2) == 1.0 + 0x1p-51); /* up */
  /* signed zeros: -0 only when every input is -0 */
  const double z2[2][2] = {{0.0, -0.0}, {-0.0, 0.0}};
  for (int k = 0; k < 2; ++k) assert_true(bits_of(sum_of(z2[k], 2)) == 0);
  assert_true(bits_of(sum_of((const double[]){-0.0, -0.0}, 2)) == bits_of(-0.0));
  assert_true(bits_of(sum_of((const double[]){1.0, -1.0}, 2)) == 0);
  assert_true(bits_of(sum_of(NULL, 0)) == 0);
  /* many equal tiny values */
  gran_exactsum a;
  gran_exactsum_init_(&a);
  for (int i = 0; i < 3000000; ++i) gran_exactsum_add_(&a, tiny); /* 3e6 x the smallest subnormal */
  assert_true(gran_exactsum_value_(&a) == 3000000 * tiny);
  /* deferred carries: 2^31 + 5 adds of 2^32 - 1 units of limb 1 each (without the normalisation every
   * 2^30 adds the limb would overflow int64) */
  gran_exactsum_init_(&a);
  const double fill = ldexp((double)0xffffffffULL, -1074 + 32);
  const int64_t K = ((int64_t)1 << 31) + 5;
  for (int64_t i = 0; i < K; ++i) gran_exactsum_add_(&a, fill);
  assert_true(gran_exactsum_value_(&a) == (double)K * fill);
}

/* ---- creation by cells ---- */
static gran_srd_options cells_opts(int dim) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = dim;
  o.cells[0] = 12;
  o.cells[1] = 10;
  o.cells[2] = dim == 3 ? 7 : 1;
  o.a = 0.7;
  o.n0 = 5.3;
  o.T0 = 1.7;
  o.seed = 77;
  o.creation = GRAN_SRD_CREATE_CELLS;
  return o;
}
static int64_t ncell_of(const gran_srd_options *o) { return o->cells[0] * o->cells[1] * (o->dim == 3 ? o->cells[2] : 1); }

typedef struct {
  int64_t n, *count;
  double *p[6];
  gran_exactsum mom[3];
} cset;

static void cset_make(const gran_srd_options *o, int P, cset *c) {
  const int64_t nc = ncell_of(o);
  c->count = calloc((size_t)nc, sizeof(int64_t));
  assert_non_null(c->count);
  /* uneven ranges: boundaries at nc (k / P)^1.5 */
  int64_t b[8];
  for (int k = 0; k <= P; ++k) b[k] = (int64_t)((double)nc * pow((double)k / P, 1.5));
  b[P] = nc;
  c->n = 0;
  for (int k = 0; k < P; ++k) {
    GRAN_ASSERT_OK(gran_srd_cell_counts_(o, b[k], b[k + 1], c->count + b[k]));
    for (int64_t i = b[k]; i < b[k + 1]; ++i) c->n += c->count[i];
  }
  for (int q = 0; q < 6; ++q) {
    c->p[q] = calloc((size_t)c->n + 1, sizeof(double));
    assert_non_null(c->p[q]);
  }
  for (int k = 0; k < 3; ++k) gran_exactsum_init_(&c->mom[k]);
  int64_t off = 0;
  for (int k = 0; k < P; ++k) {
    gran_exactsum m[3];
    for (int q = 0; q < 3; ++q) gran_exactsum_init_(&m[q]);
    GRAN_ASSERT_OK(gran_srd_create_cells_(o, b[k], b[k + 1], c->count + b[k], c->p[0] + off, c->p[1] + off,
                                          c->p[2] + off, c->p[3] + off, c->p[4] + off, c->p[5] + off, m));
    for (int q = 0; q < 3; ++q) gran_exactsum_merge_(&c->mom[q], &m[q]);
    for (int64_t i = b[k]; i < b[k + 1]; ++i) off += c->count[i];
  }
}
static void cset_free(cset *c) {
  free(c->count);
  for (int q = 0; q < 6; ++q) free(c->p[q]);
}

static void test_cells_partition(void **state) {
  (void)state;
  for (int dim = 2; dim <= 3; ++dim) {
    gran_srd_options o = cells_opts(dim);
    if (dim == 2) {
      o.wall_axis = 1;
      o.sort_every = 0;
    } else {
      o.shear_rate = 0.01;
    }
    const int64_t nc = ncell_of(&o);
    cset one;
    cset_make(&o, 1, &one);
    assert_int_equal(one.n, (int64_t)floor(o.n0 * (double)nc + 0.5)); /* N exactly */
    static const int Ps[4] = {2, 3, 4, 7};
    for (int k = 0; k < 4; ++k) {
      cset c;
      cset_make(&o, Ps[k], &c);
      assert_int_equal(c.n, one.n);
      assert_memory_equal(c.count, one.count, (size_t)nc * sizeof(int64_t));
      for (int q = 0; q < 6; ++q) assert_memory_equal(c.p[q], one.p[q], (size_t)one.n * sizeof(double));
      for (int q = 0; q < 3; ++q) assert_true(gran_exactsum_value_(&c.mom[q]) == gran_exactsum_value_(&one.mom[q]));
      cset_free(&c);
    }
    /* every particle inside its cell, in cell order (binned as the engine bins: x (1 / a)) */
    const double inv_a = 1.0 / o.a;
    int64_t p = 0;
    for (int64_t c = 0; c < nc; ++c)
      for (int64_t q = 0; q < one.count[c]; ++q, ++p) {
        const int64_t ci = (int64_t)floor(one.p[0][p] * inv_a), cj = (int64_t)floor(one.p[1][p] * inv_a),
                      ck = dim == 3 ? (int64_t)floor(one.p[2][p] * inv_a) : 0;
        if (ci + o.cells[0] * (cj + o.cells[1] * ck) != c) fail_msg("particle %lld is not in its cell %lld", (long long)p, (long long)c);
      }
    /* the engine: these particles, mean momentum removed, shear added, for 1 and 3 threads */
    double m[3] = {0, 0, 0};
    for (int q = 0; q < dim; ++q) m[q] = gran_exactsum_value_(&one.mom[q]) / (double)one.n;
    const double box1 = (double)o.cells[1] * o.a;
    for (int64_t i = 0; i < one.n; ++i) {
      for (int q = 0; q < dim; ++q) one.p[3 + q][i] -= m[q];
      if (o.shear_rate != 0) one.p[3][i] = fma(o.shear_rate, one.p[1][i] - 0.5 * box1, one.p[3][i]);
    }
    for (int th = 1; th <= 3; th += 2) {
      o.threads = th;
      gran_srd *s = NULL;
      GRAN_ASSERT_OK(gran_srd_create(&o, &s));
      int64_t n;
      double *a[6];
      GRAN_ASSERT_OK(gran_srd_particles(s, &n, &a[0], &a[1], &a[2], &a[3], &a[4], &a[5]));
      assert_int_equal(n, one.n);
      for (int q = 0; q < 6; ++q) {
        if (dim == 2 && (q == 2 || q == 5)) continue;
        if (memcmp(a[q], one.p[q], (size_t)n * sizeof(double))) fail_msg("dim %d threads %d: array %d differs", dim, th, q);
      }
      GRAN_ASSERT_OK(gran_srd_destroy(&s));
    }
    cset_free(&one);
  }
}

static void test_cells_statistics(void **state) {
  (void)state;
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.cells[0] = o.cells[1] = o.cells[2] = 32;
  o.n0 = 10;
  o.T0 = 2.0;
  o.seed = 4;
  o.creation = GRAN_SRD_CREATE_CELLS;
  const int64_t nc = 32 * 32 * 32, N = 327680;
  int64_t *count = malloc((size_t)nc * sizeof *count);
  assert_non_null(count);
  GRAN_ASSERT_OK(gran_srd_cell_counts_(&o, 0, nc, count));
  int64_t tot = 0, left = 0;
  double s2 = 0;
  for (int64_t c = 0; c < nc; ++c) {
    tot += count[c];
    if (c < nc / 2) left += count[c];
    s2 += (count[c] - o.n0) * (count[c] - o.n0);
  }
  assert_int_equal(tot, N);
  /* the root's split: Binomial(N, 1/2) */
  GRAN_ASSERT_SIGMA((double)left, 0.5 * N, sqrt(0.25 * N), 4);
  /* multinomial: variance n0 (1 - 1/ncell); the sample variance's se sqrt((2 n0^2 + n0) / ncell) */
  GRAN_ASSERT_SIGMA(s2 / (double)nc, o.n0 * (1 - 1.0 / nc), sqrt((2 * o.n0 * o.n0 + o.n0) / nc), 4);
  /* the mean count of a fixed cell over seeds: n0 (se sqrt(n0 (1 - 1/nc) / seeds)) */
  {
    double m = 0;
    enum { S = 200 };
    gran_srd_options q = o;
    q.cells[0] = q.cells[1] = q.cells[2] = 4;
    for (int k = 0; k < S; ++k) {
      q.seed = 1000 + (uint64_t)k;
      int64_t c5[64];
      GRAN_ASSERT_OK(gran_srd_cell_counts_(&q, 0, 64, c5));
      m += (double)c5[37];
    }
    GRAN_ASSERT_SIGMA(m / S, q.n0, sqrt(q.n0 * (1 - 1.0 / 64) / S), 4);
  }
  free(count);
  gran_srd *s = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &s));
  int64_t n;
  double *x, *y, *z, *vx, *vy, *vz;
  GRAN_ASSERT_OK(gran_srd_particles(s, &n, &x, &y, &z, &vx, &vy, &vz));
  assert_int_equal(n, N);
  double P[3] = {0, 0, 0}, A = 0, E = 0, fx = 0, fz = 0;
  for (int64_t i = 0; i < n; ++i) {
    P[0] += vx[i];
    P[1] += vy[i];
    P[2] += vz[i];
    A += fabs(vx[i]) + fabs(vy[i]) + fabs(vz[i]);
    E += vx[i] * vx[i] + vy[i] * vy[i] + vz[i] * vz[i];
    fx += x[i] - floor(x[i]);
    fz += z[i] - floor(z[i]);
  }
  for (int k = 0; k < 3; ++k) assert_true(fabs(P[k]) <= 1e-12 * A);
  /* T = T0 (1 - 1/N) after the mean is removed; se T0 sqrt(2 / (3 N)) */
  GRAN_ASSERT_SIGMA(E / (3.0 * (double)n), o.T0 * (1 - 1.0 / n), o.T0 * sqrt(2.0 / (3.0 * n)), 4);
  /* positions uniform inside the cells: the mean offset 1/2, se sqrt(1/12 / N) */
  GRAN_ASSERT_SIGMA(fx / n, 0.5, sqrt(1.0 / 12 / n), 4);
  GRAN_ASSERT_SIGMA(fz / n, 0.5, sqrt(1.0 / 12 / n), 4);
  gran_srd_obs ob;
  GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
  GRAN_ASSERT_REL(ob.e_initial, 0.5 * E, 1e-12);
  GRAN_ASSERT_OK(gran_srd_destroy(&s));
}

/* 50 steps of a freely cooling gas (2-D, 32^2, n0 = 10, eps = 0.9): T from either creation */
static void test_cells_physics(void **state) {
  (void)state;
  enum { S = 6 };
  double T[2][S];
  for (int cr = 0; cr < 2; ++cr)
    for (int k = 0; k < S; ++k) {
      gran_srd_options o;
      GRAN_ASSERT_OK(gran_srd_options_default(&o));
      o.dim = 2;
      o.cells[0] = o.cells[1] = 32;
      o.n0 = 10;
      o.alpha_deg = 90;
      o.eps = 0.9;
      o.sigma = sqrt(0.01 / ((1 - o.eps * o.eps) * o.n0));
      o.seed = 20 + (uint64_t)k;
      o.threads = 1;
      o.creation = cr;
      gran_srd *s = NULL;
      GRAN_ASSERT_OK(gran_srd_create(&o, &s));
      GRAN_ASSERT_OK(gran_srd_advance(s, 50));
      gran_srd_obs ob;
      GRAN_ASSERT_OK(gran_srd_observe(s, &ob));
      assert_true(fabs(ob.ledger_error) < 1e-12);
      T[cr][k] = ob.temperature;
      GRAN_ASSERT_OK(gran_srd_destroy(&s));
    }
  double m[2], v[2];
  for (int cr = 0; cr < 2; ++cr) {
    m[cr] = v[cr] = 0;
    for (int k = 0; k < S; ++k) m[cr] += T[cr][k] / S;
    for (int k = 0; k < S; ++k) v[cr] += (T[cr][k] - m[cr]) * (T[cr][k] - m[cr]) / (S - 1);
  }
  assert_true(m[0] < 0.9 && m[0] > 0.3); /* the gas has cooled */
  GRAN_ASSERT_SIGMA(m[1], m[0], sqrt((v[0] + v[1]) / S), 4);
}

static void test_cells_options(void **state) {
  (void)state;
  gran_srd_options o = cells_opts(3);
  gran_srd *s = NULL;
  const int32_t bad[3] = {2, -1, 99};
  for (int k = 0; k < 3; ++k) {
    o.creation = bad[k];
    GRAN_ASSERT_ERR(gran_srd_create(&o, &s), GRAN_ERR_ARG);
    assert_non_null(strstr(gran_last_error_message(), "'creation'"));
    assert_null(s);
  }
  gran_srd_options d;
  GRAN_ASSERT_OK(gran_srd_options_default(&d));
  assert_int_equal(d.creation, GRAN_SRD_CREATE_SERIAL);
  /* serial and cells differ; each is reproducible */
  o.creation = GRAN_SRD_CREATE_SERIAL;
  gran_srd *a = NULL, *b = NULL;
  GRAN_ASSERT_OK(gran_srd_create(&o, &a));
  o.creation = GRAN_SRD_CREATE_CELLS;
  GRAN_ASSERT_OK(gran_srd_create(&o, &b));
  int64_t na, nb;
  double *xa, *xb, *u;
  GRAN_ASSERT_OK(gran_srd_particles(a, &na, &xa, &u, &u, &u, &u, &u));
  GRAN_ASSERT_OK(gran_srd_particles(b, &nb, &xb, &u, &u, &u, &u, &u));
  assert_int_equal(na, nb);
  assert_true(memcmp(xa, xb, (size_t)na * sizeof(double)) != 0);
  GRAN_ASSERT_OK(gran_srd_destroy(&a));
  GRAN_ASSERT_OK(gran_srd_destroy(&b));
  /* ranges outside the cells are refused */
  int64_t c[4];
  GRAN_ASSERT_ERR(gran_srd_cell_counts_(&o, 3, 2, c), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_srd_cell_counts_(&o, 0, ncell_of(&o) + 1, c), GRAN_ERR_ARG);
  /* the scene key: a run's checkpoint stores the creation it was made with; a bad value is refused */
  for (int k = 0; k < 3; ++k) {
    static const char *const val[3] = {"creation = \"cells\"\n", "", "creation = \"tree\"\n"};
    char name[32], text[512];
    snprintf(name, sizeof name, "run%d.ckpt", k);
    const char *ck = io_path(name);
    snprintf(name, sizeof name, "run%d.h5", k);
    const char *out = io_path(name);
    snprintf(text, sizeof text,
             "[engine]\ntype = \"srd\"\ndimension = 2\ncells = [6, 6]\nn0 = 5\nsteps = 4\nseed = 3\n%s"
             "[observables]\nevery = 2\n[output]\npath = \"%s\"\ncheckpoint_every = 1\n",
             val[k], out);
    gran_scene *sc = NULL;
    if (k == 2) {
      GRAN_ASSERT_ERR(gran_scene_parse(text, "t816.toml", &sc), GRAN_ERR_PARSE);
      assert_non_null(strstr(gran_last_error_message(), "creation"));
      continue;
    }
    GRAN_ASSERT_OK(gran_scene_parse(text, "t816.toml", &sc));
    gran_run_control ctl;
    memset(&ctl, 0, sizeof ctl);
    ctl.stop_after_checkpoints = 1;
    gran_run_result res;
    GRAN_ASSERT_OK(gran_scene_run(sc, out, ck, &ctl, &res));
    GRAN_ASSERT_OK(gran_scene_destroy(&sc));
    hid_t f = H5Fopen(ck, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(f >= 0);
    size_t nv = 0;
    double *v = io_h5_read_double(f, "/engine/options/creation", &nv);
    assert_non_null(v);
    assert_int_equal(nv, 1);
    assert_int_equal((int)v[0], k == 0 ? GRAN_SRD_CREATE_CELLS : GRAN_SRD_CREATE_SERIAL);
    free(v);
    H5Fclose(f);
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_exact_permutations), cmocka_unit_test(test_exact_rounding),
      cmocka_unit_test(test_exact_hard),         cmocka_unit_test(test_cells_partition),
      cmocka_unit_test(test_cells_statistics),   cmocka_unit_test(test_cells_physics),
      cmocka_unit_test(test_cells_options),
  };
  const int rc = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return rc;
}
