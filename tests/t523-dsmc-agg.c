/* t523-dsmc-agg.c - aggregation and fragmentation in the cell selector (the DSMC outline steps
 * 10a-10d with the corrections of docs/physics.md, "Corrections to the sources") against the kinetic
 * theory and the conservation laws:
 *  - first steps from Maxwellian monomers: the fractions of collisions that merge and that shatter
 *    against gran_theory_agg_fractions (4 binomial standard errors);
 *  - n_1, n_2, n_3 at t = 40 (n_1 down to 54 %) against gran_theory_aggregation, with and without
 *    fragmentation: 4 sqrt(n_k) (counting noise) + 1.5 % (the gas leaves the Maxwellian slightly:
 *    merging removes slow pairs), T_1 within 1 %;
 *  - in every run: total mass exact, momentum to rounding, collisions = bounces + merges + breakups,
 *    energy ledger e_initial - (e_bounce + e_merge + e_break) = e_kin to 1e-12;
 *  - hard cases: e_agg huge (every collision merges), the breakup of a 1e5-mer into monomers (one
 *    growth of the particle arrays, CM energy eps_f^2 E_imp), growth to clusters of N/50 and more,
 *    a 1e6-mer that swallows 100 monomers (sizes up to 1e6 + 100; 1e5 under ASan);
 *  - bad input: a mixture that is not k-mers, matrix restitution, displacements, API misuse. */
#include "dsmc_util.h"
#include "agg_test_util.h"

#include <string.h>

enum { kM = 40 };

static gran_dsmc *make(gran_mixture *mix, const int64_t *counts, const double *T0, double volume, double dt,
                       int cells, double e_agg, double e_frag, double eps_f, uint64_t seed) {
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, seed, volume, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = dt;
  c.cells = cells;
  c.e_agg = e_agg;
  c.e_frag = e_frag;
  c.eps_f = eps_f;
  gran_dsmc *d = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, counts, T0, &o, &c, &d));
  return d;
}

static void test_first_steps(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(kM, 0.01, 0.9);
  const int64_t N = (int64_t)(100000 * dsmc_scale());
  const double Ea = 0.5, Ef = 2.0;
  double T0[kM];
  for (int k = 0; k < kM; k++) T0[k] = 1;
  gran_dsmc *d = make(mix, NULL, T0, N / 0.01, 0.5, 4, Ea, Ef, 0.7, 3);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 1.0)); /* 2 steps: about 3 % of the particles collide */
  gran_dsmc_cluster_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  const double n = (double)(st.merges + st.breakups + st.bounces);
  double fs, ff;
  GRAN_ASSERT_OK(gran_theory_agg_fractions(1, 1, 1, 1, Ea, Ef, &fs, &ff));
  GRAN_ASSERT_SIGMA(st.merges / n, fs, sqrt(fs * (1 - fs) / n), 4);
  GRAN_ASSERT_SIGMA(st.breakups / n, ff, sqrt(ff * (1 - ff) / n), 4);
  /* and the collision count of Eq. 35 at T = 1 (4 sqrt(count)) */
  const double expect = 0.5 * (double)N * 4 * sqrt(M_PI) * 0.01 * 1.0;
  GRAN_ASSERT_SIGMA(n, expect, sqrt(expect), 4);
  agg_check_conservation(d, N);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
}

static void nk_case(double Ef, uint64_t seed) {
  gran_mixture *mix = agg_kmers(kM, 0.01, 0.9);
  const int64_t N = (int64_t)(100000 * dsmc_scale());
  const double Ea = 1.0, t = 40;
  double T0[kM];
  for (int k = 0; k < kM; k++) T0[k] = 1;
  gran_dsmc *d = make(mix, NULL, T0, N / 0.01, 0.5, 4, Ea, Ef, 0.7, seed);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, t));
  double nth[kM], Tth[kM], ov[3];
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, Ea, Ef, 0.7, 1, &t, 1e-9, nth, Tth, ov));
  assert_true(ov[1] < 1e-9); /* nothing beyond 40-mers */
  int64_t cnt[kM];
  double T[kM];
  GRAN_ASSERT_OK(gran_dsmc_counts(d, cnt));
  GRAN_ASSERT_OK(gran_dsmc_temperatures(d, T));
  for (int k = 0; k < 3; k++) {
    const double expect = nth[k] * (double)N / 0.01;
    GRAN_ASSERT_SIGMA((double)cnt[k], expect, sqrt(expect) + 0.015 * expect / 4, 4);
  }
  assert_true(cnt[0] < 0.6 * N); /* well into the aggregation */
  /* T_1: 1 % plus 4 standard errors of T_1 (sqrt(2/(3 N_1)) T_1) */
  GRAN_ASSERT_SIGMA(T[0], Tth[0], sqrt(2.0 / (3.0 * (double)cnt[0])) * Tth[0] + 0.01 * Tth[0] / 4, 4);
  agg_check_conservation(d, N);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
}

static void test_nk_theory(void **state) {
  (void)state;
  nk_case(INFINITY, 1);
  nk_case(3.0, 2);
}

/* e_agg huge: every collision merges */
static void test_every_pair_sticks(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(8, 0.01, 0.9);
  const int64_t N = 20000;
  gran_dsmc *d = make(mix, NULL, NULL, N / 0.01, 0.5, 2, 1e12, INFINITY, 1, 4);
  GRAN_ASSERT_OK(gran_dsmc_advance(d, 50));
  gran_dsmc_cluster_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  assert_true(st.merges > 1000);
  assert_int_equal(st.bounces, 0);
  assert_int_equal(st.breakups, 0);
  assert_int_equal(st.nclusters, N - st.merges);
  assert_true(st.largest > 8); /* beyond the mixture's sizes: the tables grew */
  GRAN_ASSERT_REL(st.e_bounce, 0.0, 0.0);
  agg_check_conservation(d, N);
  /* the mixture's sizes 1..8 through the per-species calls; species offsets do not exist */
  int64_t cnt[8], off[9];
  GRAN_ASSERT_OK(gran_dsmc_counts(d, cnt));
  int64_t ns, sz[4096], cn[4096];
  GRAN_ASSERT_OK(gran_dsmc_size_distribution(d, 4096, &ns, sz, cn, NULL));
  assert_int_equal(sz[0], 1);
  assert_int_equal(cnt[0], cn[0]);
  GRAN_ASSERT_ERR(gran_dsmc_species_offsets(d, off), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_dsmc_size_distribution(d, 1, &ns, sz, cn, NULL), GRAN_ERR_RANGE);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
}

/* A 1e5-mer among 1000 monomers, every collision shatters (e_frag = 0): the big cluster breaks into
 * 1e5 monomers in one collision, with one growth of the particle arrays */
static void test_big_breakup(void **state) {
  (void)state;
  const int64_t K = DSMC_ASAN ? 20000 : 100000, M = K;
  double *n = calloc((size_t)M, sizeof *n), *T0 = malloc((size_t)M * sizeof *T0);
  int64_t *counts = calloc((size_t)M, sizeof *counts);
  n[0] = 0.01;
  n[M - 1] = 1e-5;
  counts[0] = 1000;
  counts[M - 1] = 1;
  for (int64_t k = 0; k < M; k++) T0[k] = 1;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, NULL, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.9));
  gran_dsmc *d = make(mix, counts, T0, 1e5, 0.5, 1, 0.0, 0.0, 0.5, 5);
  double e0;
  GRAN_ASSERT_OK(gran_dsmc_energy(d, NULL, &e0, NULL));
  const gran_particles *p;
  GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
  int64_t steps = 0;
  gran_dsmc_cluster_stats st;
  do {
    GRAN_ASSERT_OK(gran_dsmc_advance(d, 0.5 * (double)++steps));
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  } while (st.largest > 1 && steps < 200);
  assert_int_equal(st.largest, 1);
  assert_int_equal(st.nclusters, 1000 + K);
  assert_int_equal(st.merges, 0);
  /* one growth to what was needed (or to twice the old capacity), never one per fragment */
  assert_true(p->capacity <= 2 * (1000 + K));
  agg_check_conservation(d, 1000 + K);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
  free(n);
  free(T0);
  free(counts);
}

/* all-sticking growth to large clusters in one small box: sizes far beyond the mixture's */
static void test_large_clusters(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(4, 0.01, 0.9);
  const int64_t N = DSMC_ASAN ? 2000 : 10000;
  gran_dsmc *d = make(mix, NULL, NULL, N / 0.01, 0.2, 1, 1e12, INFINITY, 1, 6);
  gran_dsmc_cluster_stats st;
  double t = 0;
  do {
    t += 200;
    int s = gran_dsmc_advance(d, t);
    if (s == GRAN_ERR_DOMAIN) break; /* the largest cluster outgrew dt: a clean stop */
    GRAN_ASSERT_OK(s);
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  } while (st.nclusters > 20 && t < 1e6);
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  assert_true(st.largest >= N / 50);
  agg_check_conservation(d, N);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
}

/* a 1e6-mer among monomers that all stick to it: sizes up to 1e6 + 100 in one cluster */
static void test_million_mer(void **state) {
  (void)state;
  const int64_t K = DSMC_ASAN ? 100000 : 1000000, M = K;
  double *n = calloc((size_t)M, sizeof *n), *T0 = malloc((size_t)M * sizeof *T0);
  int64_t *counts = calloc((size_t)M, sizeof *counts);
  n[0] = 1e-3;
  n[M - 1] = 1e-5;
  counts[0] = 100;
  counts[M - 1] = 1;
  for (int64_t k = 0; k < M; k++) T0[k] = 1;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, NULL, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.9));
  gran_dsmc *d = make(mix, counts, T0, 1e5, 0.2, 1, 1e12, INFINITY, 1, 9);
  gran_dsmc_cluster_stats st;
  double t = 0;
  do {
    t += 20;
    GRAN_ASSERT_OK(gran_dsmc_advance(d, t));
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  } while (st.nclusters > 1 && t < 2e4);
  assert_int_equal(st.nclusters, 1);
  assert_int_equal(st.largest, K + 100);
  /* one cluster left: no collision can happen (a clear error, not an endless loop) */
  GRAN_ASSERT_ERR(gran_dsmc_advance_collisions(d, 1), GRAN_ERR_STATE);
  agg_check_conservation(d, K + 100);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  gran_mixture_destroy(&mix);
  free(n);
  free(T0);
  free(counts);
}

static void test_errors(void **state) {
  (void)state;
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 1, 1e5, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.dt = 0.5;
  c.e_agg = 1;
  gran_dsmc *d = NULL;
  /* not k-mers */
  double m[2] = {1, 3}, s[2] = {1, 1}, n[2] = {0.01, 0.001};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "k-mer"));
  gran_mixture_destroy(&mix);
  /* matrix restitution */
  mix = agg_kmers(2, 0.01, 0.9);
  double e[4] = {0.9, 0.8, 0.8, 0.7};
  GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(mix, e));
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_UNSUPPORTED);
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.9));
  /* displacements */
  o.observe = GRAN_OBSERVE_DISPLACEMENT;
  GRAN_ASSERT_ERR(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d), GRAN_ERR_UNSUPPORTED);
  o.observe = 0;
  /* cluster calls on an engine without aggregation */
  c.e_agg = 0;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d));
  gran_dsmc_cluster_stats st;
  int64_t ns;
  GRAN_ASSERT_ERR(gran_dsmc_get_cluster_stats(d, &st), GRAN_ERR_STATE);
  GRAN_ASSERT_ERR(gran_dsmc_size_distribution(d, 0, &ns, NULL, NULL, NULL), GRAN_ERR_STATE);
  gran_dsmc_destroy(&d);
  c.e_agg = 1;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &d));
  GRAN_ASSERT_ERR(gran_dsmc_get_cluster_stats(d, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_size_distribution(d, -1, &ns, NULL, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_size_distribution(d, 5, &ns, NULL, NULL, NULL), GRAN_ERR_ARG);
  gran_dsmc_destroy(&d);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_errors),           cmocka_unit_test(test_first_steps),
      cmocka_unit_test(test_nk_theory),        cmocka_unit_test(test_every_pair_sticks),
      cmocka_unit_test(test_big_breakup),      cmocka_unit_test(test_large_clusters),
      cmocka_unit_test(test_million_mer),
  };
  return cmocka_run_group_tests_name("t523-dsmc-agg", tests, NULL, NULL);
}
