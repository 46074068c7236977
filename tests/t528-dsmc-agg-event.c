/* t528-dsmc-agg-event.c - aggregation and fragmentation in the event selectors (low-rank and Bird,
 * gran_dsmc_create_agg) against the cell selector, the kinetic theory and the
 * conservation laws:
 *  - the first collisions from Maxwellian monomers: fractions that merge and shatter against
 *    gran_theory_agg_fractions (4 binomial standard errors), the collision count against Eq. 35;
 *  - n_1, n_2, n_3, the number of clusters and the mean size at t = 10, 20, 40 from the low-rank,
 *    Bird and cell selectors (cell: dt = tau/28, 8^3 cells) against each other (4 standard errors
 *    of the difference, counting noise) and against gran_theory_aggregation (4 sqrt(n_k) + 1.5 %:
 *    the gas leaves the Maxwellian slightly, as in t523);
 *  - in every run: mass exact, momentum to rounding, collisions = bounces + merges + breakups,
 *    ledger to 1e-12, the sparse distribution equals the particles;
 *  - hard cases in both event selectors: every pair sticks (e_agg huge), the breakup of a 1e5-mer,
 *    a 1e6-mer swallowing 100 monomers, sizes emptied and refilled;
 *  - the binary fragment law: two pieces per breakup, in all three selectors;
 *  - checkpoints: a run split at t = 13.3 continues bit for bit;
 *  - Bird's per-size speed bounds (C_max of Eq. 49): 30-mers among monomers, Bird against low-rank,
 *    the acceptance, the bounds in a checkpoint and an edited bound refused;
 *  - bad input. */
#define _XOPEN_SOURCE 700 /* io_test_util.h: mkdtemp, nftw, strdup */
#include "dsmc_util.h"
#include "agg_test_util.h"
#include "io_test_util.h"

#include <hdf5.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

enum { kM = 40 };

/* an engine of selector sel (GRAN_SELECTOR_CELL: dt 0.5, 8 cells per side) with the processes */
static gran_dsmc *make(int sel, gran_mixture *mix, const int64_t *counts, const double *T0, double volume,
                       double e_agg, double e_frag, double eps_f, int law, uint64_t seed) {
  gran_dsmc_options o = dsmc_opts(sel, seed, volume, 0);
  gran_dsmc *d = NULL;
  if (sel == GRAN_SELECTOR_CELL) {
    gran_dsmc_cell_options c;
    GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
    c.dt = 0.5;
    c.cells = 8; /* cells of about one mean free path (27 against 22.5 at n = 0.01, N = 1e5) */
    c.e_agg = e_agg;
    c.e_frag = e_frag;
    c.eps_f = eps_f;
    c.frag_law = law;
    GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, counts, T0, &o, &c, &d));
  } else {
    gran_dsmc_agg_options a;
    GRAN_ASSERT_OK(gran_dsmc_agg_options_default(&a));
    a.e_agg = e_agg;
    a.e_frag = e_frag;
    a.eps_f = eps_f;
    a.frag_law = law;
    GRAN_ASSERT_OK(gran_dsmc_create_agg(mix, counts, T0, &o, &a, &d));
  }
  return d;
}

static const int kEvent[2] = {GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_BIRD};

static void test_first_collisions(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(kM, 0.01, 0.9);
  const int64_t N = (int64_t)(100000 * dsmc_scale());
  const double Ea = 0.5, Ef = 2.0, t = 1.0;
  double T0[kM];
  for (int k = 0; k < kM; k++) T0[k] = 1;
  double fs, ff;
  GRAN_ASSERT_OK(gran_theory_agg_fractions(1, 1, 1, 1, Ea, Ef, &fs, &ff));
  for (int q = 0; q < 2; q++) {
    gran_dsmc *d = make(kEvent[q], mix, NULL, T0, N / 0.01, Ea, Ef, 0.7, GRAN_FRAG_MONOMERS, 3 + q);
    GRAN_ASSERT_OK(gran_dsmc_advance(d, t)); /* about 3.5 % of the particles collide */
    gran_dsmc_cluster_stats st;
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    const double n = (double)(st.merges + st.breakups + st.bounces);
    GRAN_ASSERT_SIGMA(st.merges / n, fs, sqrt(fs * (1 - fs) / n), 4);
    GRAN_ASSERT_SIGMA(st.breakups / n, ff, sqrt(ff * (1 - ff) / n), 4);
    const double expect = 0.5 * (double)N * 4 * sqrt(M_PI) * 0.01 * t; /* Eq. 35 at T = 1 */
    GRAN_ASSERT_SIGMA(n, expect, sqrt(expect), 4);
    agg_check_conservation(d, N);
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  }
  gran_mixture_destroy(&mix);
}

/* n_1, n_2, n_3, clusters, mean size at three times from the three selectors and the theory */
static void test_nk_selectors(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(kM, 0.01, 0.9);
  const int64_t N = (int64_t)(100000 * dsmc_scale());
  const double Ea = 1.0, Ef = 3.0, times[3] = {10, 20, 40};
  double T0[kM];
  for (int k = 0; k < kM; k++) T0[k] = 1;
  double nth[3 * kM], ov[9];
  GRAN_ASSERT_OK(gran_theory_aggregation(mix, T0, Ea, Ef, 0.7, 3, times, 1e-9, nth, NULL, ov));
  const int sel[3] = {GRAN_SELECTOR_CELL, GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_BIRD};
  double obs[3][3][5]; /* [selector][time][n1 n2 n3 clusters mean] */
  for (int q = 0; q < 3; q++) {
    gran_dsmc *d = make(sel[q], mix, NULL, T0, N / 0.01, Ea, Ef, 0.7, GRAN_FRAG_MONOMERS, 11 + q);
    for (int it = 0; it < 3; it++) {
      GRAN_ASSERT_OK(gran_dsmc_advance(d, times[it]));
      int64_t cnt[kM];
      gran_dsmc_cluster_stats st;
      GRAN_ASSERT_OK(gran_dsmc_counts(d, cnt));
      GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
      for (int k = 0; k < 3; k++) obs[q][it][k] = (double)cnt[k];
      obs[q][it][3] = (double)st.nclusters;
      obs[q][it][4] = st.mean_size;
      /* against the theory: counting noise + 1.5 % */
      for (int k = 0; k < 3; k++) {
        const double ex = nth[it * kM + k] * (double)N / 0.01;
        GRAN_ASSERT_SIGMA(obs[q][it][k], ex, sqrt(ex) + 0.015 * ex / 4, 4);
      }
    }
    assert_true(obs[q][2][0] < 0.6 * N); /* well into the aggregation */
    agg_check_conservation(d, N);
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  }
  /* the selectors against each other: 4 standard errors of the difference of two counts (each
   * Poisson-like, sqrt(n)); clusters and the mean size from the sum of the counts */
  for (int q = 1; q < 3; q++)
    for (int it = 0; it < 3; it++) {
      for (int k = 0; k < 4; k++) {
        const double a = obs[0][it][k], b = obs[q][it][k];
        GRAN_ASSERT_SIGMA(b, a, sqrt(a + b), 4);
      }
      const double c = obs[0][it][3];
      GRAN_ASSERT_SIGMA(obs[q][it][4], obs[0][it][4], obs[0][it][4] * sqrt(2.0 * c) / c, 4);
    }
  gran_mixture_destroy(&mix);
}

/* e_agg huge: every collision merges; sizes beyond the mixture's, emptied sizes reused */
static void test_every_pair_sticks(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(8, 0.01, 0.9);
  const int64_t N = 20000;
  for (int q = 0; q < 2; q++) {
    gran_dsmc *d = make(kEvent[q], mix, NULL, NULL, N / 0.01, 1e12, INFINITY, 1, GRAN_FRAG_MONOMERS, 4);
    gran_dsmc_cluster_stats st;
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, N - 50));
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    assert_int_equal(st.merges, N - 50);
    assert_int_equal(st.bounces, 0);
    assert_int_equal(st.breakups, 0);
    assert_int_equal(st.nclusters, 50);
    assert_true(st.largest > 8 * 20); /* far beyond the mixture's sizes */
    GRAN_ASSERT_REL(st.e_bounce, 0.0, 0.0);
    agg_check_conservation(d, N);
    int64_t cnt[8], off[9];
    GRAN_ASSERT_OK(gran_dsmc_counts(d, cnt));
    GRAN_ASSERT_ERR(gran_dsmc_species_offsets(d, off), GRAN_ERR_STATE);
    /* down to one cluster: then no collision can happen (a clear error, no endless loop) */
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, 49));
    GRAN_ASSERT_ERR(gran_dsmc_advance_collisions(d, 1), GRAN_ERR_STATE);
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    assert_int_equal(st.largest, N);
    agg_check_conservation(d, N);
    double t;
    GRAN_ASSERT_OK(gran_dsmc_time(d, &t));
    GRAN_ASSERT_OK(gran_dsmc_advance(d, t + 10)); /* time runs on without collisions */
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  }
  gran_mixture_destroy(&mix);
}

/* a mixture of M sizes with counts[0] monomers and one M-mer (T = 1 each) */
static gran_dsmc *big_and_monomers(int sel, int64_t M, int64_t n1, double e_agg, double e_frag, double eps_f,
                                   uint64_t seed, gran_mixture **mixp) {
  double *n = calloc((size_t)M, sizeof *n), *T0 = malloc((size_t)M * sizeof *T0);
  int64_t *counts = calloc((size_t)M, sizeof *counts);
  n[0] = 0.01;
  n[M - 1] = 1e-5;
  counts[0] = n1;
  counts[M - 1] = 1;
  for (int64_t k = 0; k < M; k++) T0[k] = 1;
  GRAN_ASSERT_OK(gran_mixture_create(M, NULL, NULL, n, mixp));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(*mixp, 0.9));
  gran_dsmc *d = make(sel, *mixp, counts, T0, 1e5, e_agg, e_frag, eps_f, GRAN_FRAG_MONOMERS, seed);
  free(n);
  free(T0);
  free(counts);
  return d;
}

/* A 1e5-mer among 1000 monomers, every collision shatters (e_frag = 0): the big cluster breaks
 * into 1e5 monomers in one collision with one growth of the arrays */
static void test_big_breakup(void **state) {
  (void)state;
  const int64_t K = DSMC_ASAN ? 20000 : 100000;
  for (int q = 0; q < 2; q++) {
    gran_mixture *mix = NULL;
    gran_dsmc *d = big_and_monomers(kEvent[q], K, 1000, 0.0, 0.0, 0.5, 5, &mix);
    const gran_particles *p;
    GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
    gran_dsmc_cluster_stats st;
    int64_t steps = 0;
    do {
      GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, 1));
      GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    } while (st.largest > 1 && ++steps < 100000);
    assert_int_equal(st.largest, 1);
    assert_int_equal(st.nclusters, 1000 + K);
    assert_int_equal(st.merges, 0);
    GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
    assert_true(p->capacity <= 2 * (1000 + K)); /* one growth, not one per fragment */
    agg_check_conservation(d, 1000 + K);
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, 1000)); /* the monomers go on shattering into themselves */
    agg_check_conservation(d, 1000 + K);
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
    gran_mixture_destroy(&mix);
  }
}

/* a 1e6-mer that swallows 100 monomers: sizes up to 1e6 + 100 */
static void test_million_mer(void **state) {
  (void)state;
  const int64_t K = DSMC_ASAN ? 100000 : 1000000;
  for (int q = 0; q < 2; q++) {
    gran_mixture *mix = NULL;
    gran_dsmc *d = big_and_monomers(kEvent[q], K, 100, 1e12, INFINITY, 1, 9, &mix);
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, 99));
    gran_dsmc_cluster_stats st;
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    assert_int_equal(st.nclusters, 2);
    assert_true(st.largest >= K + 1);
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, 1));
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    assert_int_equal(st.nclusters, 1);
    assert_int_equal(st.largest, K + 100);
    agg_check_conservation(d, K + 100);
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
    gran_mixture_destroy(&mix);
  }
}

/* binary fragment law: a breakup makes two pieces; with e_frag = 0 and no merges the number of
 * clusters never changes; pieces of every size 1..K-1 appear */
static void test_binary_law(void **state) {
  (void)state;
  const int64_t N = DSMC_ASAN ? 2000 : 10000;
  const int sel[3] = {GRAN_SELECTOR_CELL, GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_BIRD};
  gran_mixture *mix = NULL;
  {
    double n[16] = {0};
    n[15] = 0.01; /* 16-mers only */
    GRAN_ASSERT_OK(gran_mixture_create(16, NULL, NULL, n, &mix));
    GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.9));
  }
  int64_t counts[16] = {0};
  counts[15] = N;
  double T0[16];
  for (int k = 0; k < 16; k++) T0[k] = 1;
  for (int q = 0; q < 3; q++) {
    gran_dsmc *d = make(sel[q], mix, counts, T0, N / 0.01, 0.0, 0.0, 0.8, GRAN_FRAG_BINARY, 21 + q);
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(d, N / 2));
    gran_dsmc_cluster_stats st;
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
    assert_int_equal(st.nclusters, N);
    assert_int_equal(st.merges, 0);
    assert_true(st.breakups >= N / 2);
    assert_true(st.nsizes >= 25); /* pieces of most sizes 1..31 */
    agg_check_conservation(d, 16 * N);
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  }
  gran_mixture_destroy(&mix);
}

/* the binary law against its kinetic theory (gran_theory_aggregation_law): n_1, n_2, n_3 at t = 40
 * from monomers (e_agg = 1, e_frag = 3) in the three selectors, 4 sqrt(n_k) + 1.5 % as above */
static void test_binary_theory(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(kM, 0.01, 0.9);
  const int64_t N = (int64_t)(100000 * dsmc_scale());
  const double Ea = 1.0, Ef = 3.0, t = 40;
  double T0[kM];
  for (int k = 0; k < kM; k++) T0[k] = 1;
  double nth[kM];
  GRAN_ASSERT_OK(gran_theory_aggregation_law(mix, T0, Ea, Ef, 0.7, GRAN_FRAG_BINARY, 1, &t, 1e-9, nth, NULL, NULL));
  const int sel[3] = {GRAN_SELECTOR_CELL, GRAN_SELECTOR_LOWRANK, GRAN_SELECTOR_BIRD};
  for (int q = 0; q < 3; q++) {
    gran_dsmc *d = make(sel[q], mix, NULL, T0, N / 0.01, Ea, Ef, 0.7, GRAN_FRAG_BINARY, 41 + q);
    GRAN_ASSERT_OK(gran_dsmc_advance(d, t));
    int64_t cnt[kM];
    GRAN_ASSERT_OK(gran_dsmc_counts(d, cnt));
    for (int k = 0; k < 3; k++) {
      const double ex = nth[k] * (double)N / 0.01;
      GRAN_ASSERT_SIGMA((double)cnt[k], ex, sqrt(ex) + 0.015 * ex / 4, 4);
    }
    agg_check_conservation(d, N);
    GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
  }
  gran_mixture_destroy(&mix);
}

static void compare_engines(const gran_dsmc *a, const gran_dsmc *b) {
  const gran_particles *pa, *pb;
  GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
  GRAN_ASSERT_OK(gran_dsmc_particles(b, &pb));
  assert_int_equal(pa->n, pb->n);
  assert_memory_equal(pa->v, pb->v, sizeof(double) * 3 * (size_t)pa->n);
  assert_memory_equal(pa->species, pb->species, sizeof(int32_t) * (size_t)pa->n);
  gran_dsmc_stats sa, sb;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(a, &sa));
  GRAN_ASSERT_OK(gran_dsmc_get_stats(b, &sb));
  assert_int_equal(sa.collisions, sb.collisions);
  assert_int_equal(sa.trials, sb.trials);
  assert_int_equal(sa.bound_raises, sb.bound_raises);
  assert_int_equal(sa.bound_tightenings, sb.bound_tightenings);
  assert_memory_equal(&sa.time, &sb.time, sizeof sa.time);
  gran_dsmc_cluster_stats ca, cb;
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(a, &ca));
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(b, &cb));
  assert_memory_equal(&ca, &cb, sizeof ca);
}

static void test_checkpoint(void **state) {
  (void)state;
  char path[64];
  snprintf(path, sizeof path, "t528-ckpt-%d.h5", (int)getpid());
  gran_mixture *mix = agg_kmers(kM, 0.01, 0.9);
  const int64_t N = DSMC_ASAN ? 4000 : 20000;
  const int laws[2] = {GRAN_FRAG_MONOMERS, GRAN_FRAG_BINARY};
  for (int q = 0; q < 2; q++)
    for (int lw = 0; lw < 2; lw++) {
      gran_dsmc *a = make(kEvent[q], mix, NULL, NULL, N / 0.01, 1.0, 2.0, 0.7, laws[lw], 31 + q);
      gran_dsmc *b = make(kEvent[q], mix, NULL, NULL, N / 0.01, 1.0, 2.0, 0.7, laws[lw], 31 + q);
      GRAN_ASSERT_OK(gran_dsmc_advance(a, 30));
      GRAN_ASSERT_OK(gran_dsmc_advance(b, 13.3));
      GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, path, "state"));
      gran_dsmc *c = NULL;
      GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(path, "state", mix, &c));
      compare_engines(b, c);
      GRAN_ASSERT_OK(gran_dsmc_destroy(&b));
      GRAN_ASSERT_OK(gran_dsmc_advance(c, 30));
      compare_engines(a, c);
      agg_check_conservation(c, N);
      GRAN_ASSERT_OK(gran_dsmc_destroy(&a));
      GRAN_ASSERT_OK(gran_dsmc_destroy(&c));
    }
  remove(path);
  gran_mixture_destroy(&mix);
}

/* Bird's C_max (Eq. 49) from a speed bound per size: large slow clusters among monomers no longer
 * set the bound with the monomers' speed, and the rates stay exact. Monomers with 30-mers at the
 * same temperature (the 30-mers 5.5 times slower, 3.1 times wider): merges and breakups per pair
 * kind, as counted by n_1, n_30 and the merge and breakup counters at t = 5 and 20, from Bird against
 * the low-rank selector (4 standard errors of the difference of the means over 6 seeds each, from
 * the seeds' spread); the acceptance
 * of Bird is then above 0.04 (0.052 at N_1 = 2e4; with sigma_pair,max^2 2 v_max it was 0.023); a checkpoint keeps the
 * per-size bounds, and a bound edited below a particle's speed is refused. */
static void test_bird_size_bounds(void **state) {
  (void)state;
  double dens[kM] = {0};
  dens[0] = 0.01;
  dens[29] = 0.0001;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(kM, NULL, NULL, dens, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.8));
  const int64_t n1 = DSMC_ASAN ? 4000 : 20000, n30 = n1 / 100;
  const int64_t *counts = NULL; /* n1 and n30 from the densities in the volume n1 / 0.01 */
  const int64_t mass = n1 + 30 * n30;
  double T0[kM];
  for (int k = 0; k < kM; k++) T0[k] = 1;
  const double times[2] = {5, 20};
  enum { kSeeds = 6 };
  double obs[2][kSeeds][2][4] = {{{{0}}}}; /* [selector][seed][time][n1 n30 merges breakups] */
  double trials = 0, colls = 0;
  for (int q = 0; q < 2; q++)
    for (int seed = 0; seed < kSeeds; seed++) {
      gran_dsmc *d = make(kEvent[q], mix, counts, T0, (double)n1 / 0.01, 0.5, 3.0, 0.7, GRAN_FRAG_MONOMERS,
                          100 + 10 * q + seed);
      for (int it = 0; it < 2; it++) {
        GRAN_ASSERT_OK(gran_dsmc_advance(d, times[it]));
        int64_t cnt[kM];
        gran_dsmc_cluster_stats st;
        GRAN_ASSERT_OK(gran_dsmc_counts(d, cnt));
        GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
        obs[q][seed][it][0] = (double)cnt[0];
        obs[q][seed][it][1] = (double)cnt[29];
        obs[q][seed][it][2] = (double)st.merges;
        obs[q][seed][it][3] = (double)st.breakups;
      }
      agg_check_conservation(d, mass);
      if (q == 1) {
        gran_dsmc_stats x;
        GRAN_ASSERT_OK(gran_dsmc_get_stats(d, &x));
        trials += (double)x.trials;
        colls += (double)x.collisions;
      }
      GRAN_ASSERT_OK(gran_dsmc_destroy(&d));
    }
  /* means over the seeds; the standard error of their difference from the seeds' spread (a
   * breakup of a 30-mer pair adds 60 monomers at once, so counting noise would understate it) */
  for (int it = 0; it < 2; it++)
    for (int k = 0; k < 4; k++) {
      double m[2] = {0, 0}, v[2] = {0, 0};
      for (int q = 0; q < 2; q++) {
        for (int r = 0; r < kSeeds; r++) m[q] += obs[q][r][it][k] / kSeeds;
        for (int r = 0; r < kSeeds; r++) v[q] += (obs[q][r][it][k] - m[q]) * (obs[q][r][it][k] - m[q]) / (kSeeds - 1);
      }
      if (k == 2) assert_true(m[0] > 25);                  /* merges happen */
      if (k == 3) assert_true(m[0] > 5);                   /* and breakups */
      if (k == 1) assert_true(m[0] < n30 + 0.0);          /* the 30-mers take part */
      GRAN_ASSERT_SIGMA(m[1], m[0], sqrt((v[0] + v[1]) / kSeeds) + 0.5, 4);
    }
  assert_true(colls / trials > 0.04);
  /* the checkpoint holds the bounds; an edited one is refused */
  char path[64];
  snprintf(path, sizeof path, "t528-bird-%d.h5", (int)getpid());
  gran_dsmc *b = make(GRAN_SELECTOR_BIRD, mix, counts, T0, (double)n1 / 0.01, 0.5, 3.0, 0.7, GRAN_FRAG_MONOMERS, 7);
  gran_dsmc *a = make(GRAN_SELECTOR_BIRD, mix, counts, T0, (double)n1 / 0.01, 0.5, 3.0, 0.7, GRAN_FRAG_MONOMERS, 7);
  GRAN_ASSERT_OK(gran_dsmc_advance(a, 12));
  GRAN_ASSERT_OK(gran_dsmc_advance(b, 5.5));
  GRAN_ASSERT_ERR(gran_dsmc_species_velocities(a, 0, NULL), GRAN_ERR_STATE); /* sizes, not grouped */
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, path, "state"));
  gran_dsmc *c = NULL;
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(path, "state", mix, &c));
  GRAN_ASSERT_OK(gran_dsmc_advance(c, 12));
  compare_engines(a, c);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&c));
  /* edits past the file checksum: a size's bound below its fastest particle (the monomers), and a
   * bound of 1e3 for the 29-mers (none, or a few, are present: C_max no longer covers the term a
   * 29-mer made later would need) */
  const int64_t which[2] = {0, 28};
  const double value[2] = {1e-3, 1e3};
  char edited[80];
  snprintf(edited, sizeof edited, "t528-bird-edit-%d.h5", (int)getpid());
  for (int e = 0; e < 2; e++) {
    io_edit_copy(path, edited, "state/agg_size_bound", which[e], value[e], 0);
    GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(edited, "state", mix, &c), GRAN_ERR_IO);
    if (!strstr(gran_last_error_message(), "speed bounds")) fail_msg("edit %d: %s", e, gran_last_error_message());
    assert_null(c);
  }
  remove(edited);
  remove(path);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&a));
  GRAN_ASSERT_OK(gran_dsmc_destroy(&b));
  gran_mixture_destroy(&mix);
}

static void test_errors(void **state) {
  (void)state;
  gran_mixture *mix = agg_kmers(4, 0.01, 0.9);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 1, 1e4, 0);
  gran_dsmc_agg_options a;
  GRAN_ASSERT_OK(gran_dsmc_agg_options_default(&a));
  assert_true(a.e_agg == 0 && isinf(a.e_frag) && a.eps_f == 1 && a.frag_law == GRAN_FRAG_MONOMERS);
  gran_dsmc *d = NULL;
  /* off: the plain engine, without cluster statistics */
  GRAN_ASSERT_OK(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d));
  gran_dsmc_cluster_stats st;
  GRAN_ASSERT_ERR(gran_dsmc_get_cluster_stats(d, &st), GRAN_ERR_STATE);
  gran_dsmc_destroy(&d);
  a.e_agg = 1;
  a.eps_f = 1.5;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "eps_f"));
  a.eps_f = 1;
  a.frag_law = 7;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "frag_law"));
  a.frag_law = GRAN_FRAG_BINARY;
  a.e_frag = NAN;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_ARG);
  a.e_frag = INFINITY;
  a.e_agg = -1;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_ARG);
  a.e_agg = 1;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, NULL, &d), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, NULL), GRAN_ERR_ARG);
  /* selectors and observables without aggregation */
  o.selector = GRAN_SELECTOR_LOWRANK_PAPER;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_UNSUPPORTED);
  o.selector = GRAN_SELECTOR_LOWRANK;
  o.speed_classes = 1;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_UNSUPPORTED);
  o.speed_classes = 0;
  o.selector = GRAN_SELECTOR_CELL;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_ARG);
  o.selector = GRAN_SELECTOR_BIRD;
  o.observe = GRAN_OBSERVE_DISPLACEMENT;
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(mix, NULL, NULL, &o, &a, &d), GRAN_ERR_UNSUPPORTED);
  o.observe = 0;
  /* not k-mers */
  double m[2] = {1, 3}, s[2] = {1, 1}, n[2] = {0.01, 0.001};
  gran_mixture *bad = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &bad));
  GRAN_ASSERT_ERR(gran_dsmc_create_agg(bad, NULL, NULL, &o, &a, &d), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "k-mer"));
  gran_mixture_destroy(&bad);
  assert_null(d);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_errors),          cmocka_unit_test(test_first_collisions),
      cmocka_unit_test(test_nk_selectors),    cmocka_unit_test(test_every_pair_sticks),
      cmocka_unit_test(test_big_breakup),     cmocka_unit_test(test_million_mer),
      cmocka_unit_test(test_binary_law),      cmocka_unit_test(test_binary_theory),
      cmocka_unit_test(test_checkpoint),      cmocka_unit_test(test_bird_size_bounds),
  };
  return cmocka_run_group_tests_name("t528-dsmc-agg-event", tests, NULL, NULL);
}
