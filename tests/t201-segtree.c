/* t201-segtree.c - sum tree: sampling frequencies (chi-square), zero-weight leaves never chosen at
 * any boundary u, updates and batches, absence of drift after 10^8 updates, a 10^6-leaf tree,
 * every error code.
 *
 * Chi-square tests use fixed seeds and significance 1e-3 (Wilson-Hilferty critical value). */
#include "granary_test.h"

/* chi-square critical value at significance 1e-3 (z = 3.0902), Wilson-Hilferty */
static double chi2_crit(int df) {
  const double z = 3.090232, a = 2.0 / (9.0 * df);
  const double c = 1.0 - a + z * sqrt(a);
  return df * c * c * c;
}

/* Neumaier's compensated sum */
static double neumaier(int64_t n, const double *x) {
  double sum = 0, c = 0;
  for (int64_t i = 0; i < n; i++) {
    const double t = sum + x[i];
    c += fabs(sum) >= fabs(x[i]) ? (sum - t) + x[i] : (x[i] - t) + sum;
    sum = t;
  }
  return sum + c;
}

/* Draw nsample indices, check that zero leaves are never chosen, and chi-square the counts of the
 * positive leaves (grouped into ngroup consecutive groups when m is large). */
static void check_frequencies(const gran_segtree *t, const double *w, int64_t nsample, int64_t ngroup,
                              uint64_t seed) {
  const int64_t m = t->m;
  const int64_t per = (m + ngroup - 1) / ngroup;
  int64_t *count = calloc((size_t)ngroup, sizeof(int64_t));
  double *p = calloc((size_t)ngroup, sizeof(double));
  double *u = malloc(sizeof(double) * 4096);
  assert_non_null(count);
  assert_non_null(p);
  assert_non_null(u);
  const double total = neumaier(m, w);
  for (int64_t i = 0; i < m; i++) p[i / per] += w[i] / total;
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, seed));
  for (int64_t done = 0; done < nsample; done += 4096) {
    const int64_t nb = nsample - done < 4096 ? nsample - done : 4096;
    GRAN_ASSERT_OK(gran_rng_uniform(&g, nb, u));
    for (int64_t k = 0; k < nb; k++) {
      int64_t idx = -1;
      GRAN_ASSERT_OK(gran_segtree_sample(t, u[k], &idx));
      assert_true(idx >= 0 && idx < m);
      if (!(w[idx] > 0)) fail_msg("zero-weight leaf " GRAN_I64_FMT " sampled at u = %.17g", idx, u[k]);
      count[idx / per]++;
    }
  }
  double chi2 = 0;
  int df = -1;
  for (int64_t k = 0; k < ngroup; k++) {
    if (p[k] == 0) {
      assert_int_equal(count[k], 0);
      continue;
    }
    const double e = p[k] * (double)nsample;
    if (e < 5) fail_msg("group " GRAN_I64_FMT " expects %.2f < 5 draws: bad test design", k, e);
    chi2 += ((double)count[k] - e) * ((double)count[k] - e) / e;
    df++;
  }
  if (df > 0 && chi2 > chi2_crit(df)) fail_msg("chi2 = %g > %g (df %d)", chi2, chi2_crit(df), df);
  free(count);
  free(p);
  free(u);
}

static void test_frequencies(void **state) {
  (void)state;
  gran_segtree t;
  /* m = 1: always leaf 0 */
  const double one = 2.5;
  GRAN_ASSERT_OK(gran_segtree_init(&t, 1, &one));
  assert_int_equal(t.base, 1);
  int64_t idx = -1;
  GRAN_ASSERT_OK(gran_segtree_sample(&t, 0.0, &idx));
  assert_int_equal(idx, 0);
  GRAN_ASSERT_OK(gran_segtree_sample(&t, nextafter(1.0, 0.0), &idx));
  assert_int_equal(idx, 0);
  check_frequencies(&t, &one, 1000, 1, 1);
  GRAN_ASSERT_OK(gran_segtree_free(&t));

  /* m = 7 (not a power of two; base 8), zeros at the ends and in the middle */
  const double w7[7] = {0.0, 1.0, 2.0, 0.0, 3.5, 0.25, 0.0};
  GRAN_ASSERT_OK(gran_segtree_init(&t, 7, w7));
  assert_int_equal(t.base, 8);
  double total = 0;
  GRAN_ASSERT_OK(gran_segtree_total(&t, &total));
  assert_true(total == 6.75);
  check_frequencies(&t, w7, 200000, 7, 2);
  GRAN_ASSERT_OK(gran_segtree_free(&t));

  /* m = 1000, random weights with every tenth one zero */
  double *w = malloc(sizeof(double) * 1000);
  assert_non_null(w);
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 3));
  GRAN_ASSERT_OK(gran_rng_uniform(&g, 1000, w));
  for (int i = 0; i < 1000; i++) w[i] = i % 10 == 0 ? 0.0 : 0.2 + w[i]; /* >= 5 expected draws each */
  GRAN_ASSERT_OK(gran_segtree_init(&t, 1000, w));
  assert_int_equal(t.base, 1024);
  check_frequencies(&t, w, 1000000, 1000, 4);
  GRAN_ASSERT_OK(gran_segtree_free(&t));
  free(w);
}

/* Sample at u = 0, u = nextafter(1,0), every prefix boundary and its neighbours: the leaf must have
 * positive weight; strictly inside an interval it must be that interval's leaf. */
static void check_boundaries(const gran_segtree *t, const double *w) {
  const int64_t m = t->m;
  double total;
  GRAN_ASSERT_OK(gran_segtree_total(t, &total));
  double prefix = 0;
  int64_t idx;
  const double ends[2] = {0.0, nextafter(1.0, 0.0)};
  for (int k = 0; k < 2; k++) {
    GRAN_ASSERT_OK(gran_segtree_sample(t, ends[k], &idx));
    if (!(w[idx] > 0)) fail_msg("zero leaf " GRAN_I64_FMT " at u = %.17g", idx, ends[k]);
  }
  for (int64_t i = 0; i < m; i++) {
    const double b = prefix / total;
    const double us[3] = {nextafter(b, 0.0), b, nextafter(b, 1.0)};
    for (int k = 0; k < 3; k++) {
      if (!(us[k] >= 0.0 && us[k] < 1.0)) continue;
      GRAN_ASSERT_OK(gran_segtree_sample(t, us[k], &idx));
      if (!(w[idx] > 0)) fail_msg("zero leaf " GRAN_I64_FMT " at u = %.17g (boundary of leaf " GRAN_I64_FMT ")",
                                  idx, us[k], i);
    }
    if (w[i] > 1e-6 * total) { /* interior point well inside leaf i */
      GRAN_ASSERT_OK(gran_segtree_sample(t, (prefix + 0.5 * w[i]) / total, &idx));
      assert_int_equal(idx, i);
    }
    prefix += w[i];
  }
}

static void test_zero_leaves_never_sampled(void **state) {
  (void)state;
  gran_segtree t;
  const double fixed[][9] = {{0, 0, 1, 0, 2, 0, 0, 3, 0},
                             {0, 0, 0, 0, 0, 0, 0, 0, 1e-300},
                             {1e-300, 0, 0, 0, 0, 0, 0, 0, 0},
                             {0.1, 0.2, 0, 0.3, 0, 0, 0, 0.7, 0},
                             {1e300, 0, 1e-300, 0, 1, 0, 0, 0, 1e-10}};
  for (size_t c = 0; c < sizeof fixed / sizeof *fixed; c++) {
    GRAN_ASSERT_OK(gran_segtree_init(&t, 9, fixed[c]));
    check_boundaries(&t, fixed[c]);
    GRAN_ASSERT_OK(gran_segtree_free(&t));
  }
  /* 2000 random configurations: sizes 1..40, 40% zeros, magnitudes 2^-40..2^40 */
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 5));
  double w[40], u[3];
  for (int c = 0; c < 2000; c++) {
    GRAN_ASSERT_OK(gran_rng_uniform(&g, 1, u));
    const int m = 1 + (int)(u[0] * 40);
    int npos = 0;
    for (int i = 0; i < m; i++) {
      GRAN_ASSERT_OK(gran_rng_uniform(&g, 3, u));
      w[i] = u[0] < 0.4 ? 0.0 : ldexp(u[1] + 0.01, (int)(u[2] * 81) - 40);
      npos += w[i] > 0;
    }
    if (npos == 0) w[m / 2] = 1.0;
    GRAN_ASSERT_OK(gran_segtree_init(&t, m, w));
    check_boundaries(&t, w);
    GRAN_ASSERT_OK(gran_segtree_free(&t));
  }
}

/* every internal node is the sum of its children, leaves beyond m are 0 */
static void assert_consistent(const gran_segtree *t) {
  for (int64_t i = 1; i < t->base; i++)
    if (t->node[i] != t->node[2 * i] + t->node[2 * i + 1])
      fail_msg("node " GRAN_I64_FMT " != sum of its children", i);
  for (int64_t i = t->m; i < t->base; i++) assert_true(t->node[t->base + i] == 0.0);
}

/* the tree is bit-identical to a fresh one built from its leaves */
static void assert_equals_fresh(const gran_segtree *t) {
  gran_segtree f;
  GRAN_ASSERT_OK(gran_segtree_init(&f, t->m, t->node + t->base));
  assert_memory_equal(f.node, t->node, sizeof(double) * 2 * (size_t)t->base);
  GRAN_ASSERT_OK(gran_segtree_free(&f));
}

static void test_updates_then_sampling(void **state) {
  (void)state;
  const int64_t m = 50;
  double w[50];
  gran_segtree t;
  GRAN_ASSERT_OK(gran_segtree_init(&t, m, NULL)); /* all zero */
  double total = -1;
  GRAN_ASSERT_OK(gran_segtree_total(&t, &total));
  assert_true(total == 0.0);
  for (int64_t i = 0; i < m; i++) {
    w[i] = (double)((i * 7) % 11); /* includes zeros */
    GRAN_ASSERT_OK(gran_segtree_set(&t, i, w[i]));
    double got;
    GRAN_ASSERT_OK(gran_segtree_get(&t, i, &got));
    assert_true(got == w[i]);
  }
  assert_int_equal(t.nupdate, m);
  assert_consistent(&t);
  assert_equals_fresh(&t);
  check_frequencies(&t, w, 200000, m, 6);
  /* zero out the heaviest leaves, raise others */
  for (int64_t i = 0; i < m; i++)
    if (w[i] >= 9) {
      w[i] = 0;
      GRAN_ASSERT_OK(gran_segtree_set(&t, i, 0.0));
    } else if (w[i] == 1) {
      w[i] = 20;
      GRAN_ASSERT_OK(gran_segtree_set(&t, i, 20.0));
    }
  assert_consistent(&t);
  check_frequencies(&t, w, 200000, m, 7);
  check_boundaries(&t, w);
  GRAN_ASSERT_OK(gran_segtree_rebuild(&t));
  assert_int_equal(t.nupdate, 0);
  GRAN_ASSERT_OK(gran_segtree_free(&t));
}

/* set_batch == the same sets one by one (sparse path and the full-rebuild path; repeated indices
 * keep their last value) */
static void test_set_batch(void **state) {
  (void)state;
  const int64_t m = 1000;
  gran_segtree a, b;
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 8));
  double *w0 = malloc(sizeof(double) * (size_t)m);
  assert_non_null(w0);
  GRAN_ASSERT_OK(gran_rng_uniform(&g, m, w0));
  GRAN_ASSERT_OK(gran_segtree_init(&a, m, w0));
  GRAN_ASSERT_OK(gran_segtree_init(&b, m, w0));
  const int64_t sizes[] = {1, 5, 40, 3000};
  for (size_t s = 0; s < sizeof sizes / sizeof *sizes; s++) {
    const int64_t n = sizes[s];
    int64_t *idx = malloc(sizeof(int64_t) * (size_t)n);
    double *w = malloc(sizeof(double) * (size_t)n), u;
    assert_non_null(idx);
    assert_non_null(w);
    for (int64_t k = 0; k < n; k++) {
      GRAN_ASSERT_OK(gran_rng_uniform(&g, 1, &u));
      idx[k] = (int64_t)(u * (double)m) % 37 * 27 % m; /* repeats on purpose */
      GRAN_ASSERT_OK(gran_rng_uniform(&g, 1, &w[k]));
      if (k % 4 == 0) w[k] = 0;
      GRAN_ASSERT_OK(gran_segtree_set(&a, idx[k], w[k]));
    }
    GRAN_ASSERT_OK(gran_segtree_set_batch(&b, n, idx, w));
    assert_memory_equal(a.node, b.node, sizeof(double) * 2 * (size_t)a.base);
    assert_int_equal(a.nupdate, b.nupdate);
    free(idx);
    free(w);
  }
  GRAN_ASSERT_OK(gran_segtree_set_batch(&b, 0, NULL, NULL)); /* nothing to do */
  assert_consistent(&b);
  GRAN_ASSERT_OK(gran_segtree_free(&a));
  GRAN_ASSERT_OK(gran_segtree_free(&b));
  free(w0);
}

/* 10^8 random updates of a 10-leaf tree (10^6 under AddressSanitizer, which slows each update
 * ~20x: the property checked is an invariant of every single update, not an accumulation that
 * needs the full count to show, and 10^6 updates still touch every leaf 10^5 times). */
#if defined(__SANITIZE_ADDRESS__)
#define NDRIFT 1000000
#else
#define NDRIFT 100000000
#endif

static void test_no_drift(void **state) {
  (void)state;
  const int64_t m = 10;
  gran_segtree t;
  GRAN_ASSERT_OK(gran_segtree_init(&t, m, NULL));
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 10));
  enum { NB = 4096 };
  uint64_t r[NB];
  double incremental = 0; /* a total maintained by adding differences, for contrast */
  for (int64_t done = 0; done < NDRIFT; done += NB) {
    GRAN_ASSERT_OK(gran_rng_u64(&g, NB, r));
    for (int k = 0; k < NB; k++) {
      const int64_t i = (int64_t)(r[k] % (uint64_t)m);
      /* weights of widely different magnitude: mantissa 1..2, exponent -30..30 */
      const double w = ldexp(1.0 + (double)(r[k] >> 40) * 0x1.0p-24, (int)((r[k] >> 8) % 61) - 30);
      incremental += w - t.node[t.base + i];
      gran_segtree_set(&t, i, w);
    }
  }
  assert_int_equal(t.nupdate, (NDRIFT + NB - 1) / NB * NB);
  assert_consistent(&t);
  assert_equals_fresh(&t);
  const double exact = neumaier(m, t.node + t.base);
  print_message("after " GRAN_I64_FMT " updates: root rel. error %.3g; an incremental total would be off by %.3g\n",
                t.nupdate, fabs(t.node[1] - exact) / exact, fabs(incremental - exact) / exact);
  GRAN_ASSERT_REL(t.node[1], exact, 1e-12);
  GRAN_ASSERT_OK(gran_segtree_free(&t));
}

static void test_million_leaves(void **state) {
  (void)state;
  const int64_t m = 1000000;
  double *w = malloc(sizeof(double) * (size_t)m);
  assert_non_null(w);
  gran_rng g;
  GRAN_ASSERT_OK(gran_rng_seed(&g, 11));
  GRAN_ASSERT_OK(gran_rng_exponential(&g, m, w));
  gran_segtree t;
  GRAN_ASSERT_OK(gran_segtree_init(&t, m, w));
  assert_int_equal(t.base, 1 << 20);
  double total;
  GRAN_ASSERT_OK(gran_segtree_total(&t, &total));
  GRAN_ASSERT_REL(total, neumaier(m, w), 1e-12); /* pairwise sum: error ~ log2(m) eps */
  check_frequencies(&t, w, 1000000, 1000, 12);
  GRAN_ASSERT_OK(gran_segtree_free(&t));
  free(w);
}

static void test_errors(void **state) {
  (void)state;
  gran_segtree t, z;
  const double w[3] = {1, 2, 3};
  double bad[3] = {1, -1, 3}, d;
  int64_t idx;
  GRAN_ASSERT_ERR(gran_segtree_init(NULL, 3, w), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_init(&t, 0, w), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'m'"));
  GRAN_ASSERT_ERR(gran_segtree_init(&t, -5, w), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_init(&t, 3, bad), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "w[1]"));
  bad[1] = NAN;
  GRAN_ASSERT_ERR(gran_segtree_init(&t, 3, bad), GRAN_ERR_ARG);
  bad[1] = INFINITY;
  GRAN_ASSERT_ERR(gran_segtree_init(&t, 3, bad), GRAN_ERR_ARG);

  /* an uninitialised (zeroed / freed) tree */
  memset(&z, 0, sizeof z);
  GRAN_ASSERT_ERR(gran_segtree_set(&z, 0, 1.0), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_segtree_get(&z, 0, &d), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_segtree_total(&z, &d), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_segtree_sample(&z, 0.5, &idx), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_segtree_rebuild(&z), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_segtree_set_batch(&z, 0, NULL, NULL), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_segtree_set(NULL, 0, 1.0), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_get(NULL, 0, &d), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_total(NULL, &d), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_sample(NULL, 0.5, &idx), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_rebuild(NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_set_batch(NULL, 0, NULL, NULL), GRAN_ERR_ARG);

  GRAN_ASSERT_OK(gran_segtree_init(&t, 3, w));
  GRAN_ASSERT_ERR(gran_segtree_set(&t, -1, 1.0), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_segtree_set(&t, 3, 1.0), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_segtree_set(&t, 0, -1.0), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_set(&t, 0, NAN), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_set(&t, 0, INFINITY), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_get(&t, 3, &d), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_segtree_get(&t, -1, &d), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_segtree_get(&t, 0, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_total(&t, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_sample(&t, 0.5, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_sample(&t, -0.1, &idx), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_sample(&t, 1.0, &idx), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "'u'"));
  GRAN_ASSERT_ERR(gran_segtree_sample(&t, NAN, &idx), GRAN_ERR_ARG);

  const int64_t ii[2] = {0, 3};
  const double ww[2] = {5, 5}, wbad[2] = {5, -5};
  const int64_t iok[2] = {0, 1};
  GRAN_ASSERT_ERR(gran_segtree_set_batch(&t, -1, iok, ww), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_set_batch(&t, 2, NULL, ww), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_set_batch(&t, 2, iok, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_segtree_set_batch(&t, 2, ii, ww), GRAN_ERR_RANGE);
  GRAN_ASSERT_ERR(gran_segtree_set_batch(&t, 2, iok, wbad), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_segtree_get(&t, 0, &d));
  assert_true(d == 1.0); /* a rejected batch changes nothing */

  /* all weights zero: nothing to sample */
  for (int i = 0; i < 3; i++) GRAN_ASSERT_OK(gran_segtree_set(&t, i, 0.0));
  GRAN_ASSERT_ERR(gran_segtree_sample(&t, 0.5, &idx), GRAN_ERR_EMPTY);
  /* a total that overflows */
  GRAN_ASSERT_OK(gran_segtree_set(&t, 0, 1e308));
  GRAN_ASSERT_OK(gran_segtree_set(&t, 1, 1e308));
  GRAN_ASSERT_ERR(gran_segtree_sample(&t, 0.5, &idx), GRAN_ERR_NUMERIC);
  /* a leaf corrupted by writing the node array directly */
  t.node[t.base + 2] = -1.0;
  GRAN_ASSERT_ERR(gran_segtree_rebuild(&t), GRAN_ERR_DOMAIN);

  GRAN_ASSERT_OK(gran_segtree_free(&t));
  assert_null(t.node);
  assert_int_equal(t.m, 0);
  GRAN_ASSERT_OK(gran_segtree_free(&t)); /* twice */
  GRAN_ASSERT_OK(gran_segtree_free(NULL));
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_frequencies),
      cmocka_unit_test(test_zero_leaves_never_sampled),
      cmocka_unit_test(test_updates_then_sampling),
      cmocka_unit_test(test_set_batch),
      cmocka_unit_test(test_no_drift),
      cmocka_unit_test(test_million_leaves),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests_name("t201-segtree", tests, NULL, NULL);
}
