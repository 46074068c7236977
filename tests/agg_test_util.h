/* agg_test_util.h - helpers shared by the aggregation tests (t522, t523, t527, t528): a mixture of
 * k-mers, the conservation checks of an aggregating engine, and the checks of the clusters
 * datasets the run driver writes. Include after dsmc_util.h or io_test_util.h. */
#ifndef GRANARY_AGG_TEST_UTIL_H
#define GRANARY_AGG_TEST_UTIL_H

#include "granary_test.h"

/* M sizes (species k-1 = k-mer, m_k = k, sigma_k = k^(1/3)), monomers at density n1, constant eps */
static inline gran_mixture *agg_kmers(int64_t M, double n1, double eps) {
  double *n = (double *)calloc((size_t)M, sizeof *n);
  n[0] = n1;
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(M, NULL, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, eps));
  free(n);
  return mix;
}

/* Mass, momentum, counters, the ledger and the sparse distribution (against the particles, for
 * sizes with at most 1000 clusters) of an aggregating engine with mass0 monomers in all. */
static inline void agg_check_conservation(const gran_dsmc *d, int64_t mass0) {
  gran_dsmc_cluster_stats st;
  gran_dsmc_stats x;
  GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(d, &st));
  GRAN_ASSERT_OK(gran_dsmc_get_stats(d, &x));
  assert_int_equal(st.mass, mass0);
  assert_int_equal(x.collisions, st.merges + st.breakups + st.bounces);
  assert_int_equal(x.nparticles, st.nclusters);
  GRAN_ASSERT_REL(st.mean_size, (double)mass0 / (double)st.nclusters, 1e-15);
  /* the particles themselves carry the mass */
  const gran_particles *p;
  GRAN_ASSERT_OK(gran_dsmc_particles(d, &p));
  assert_int_equal(p->n, st.nclusters);
  int64_t m = 0, big = 0;
  for (int64_t j = 0; j < p->n; j++) {
    m += p->species[j] + 1;
    if (p->species[j] + 1 > big) big = p->species[j] + 1;
  }
  assert_int_equal(m, mass0);
  assert_int_equal(big, st.largest);
  double e, e0, ed, P[3];
  GRAN_ASSERT_OK(gran_dsmc_energy(d, &e, &e0, &ed));
  GRAN_ASSERT_REL(ed, st.e_bounce + st.e_merge + st.e_break - st.e_heat, 1e-14);
  GRAN_ASSERT_ABS(e, e0 - ed, 1e-12 * e0);
  GRAN_ASSERT_OK(gran_dsmc_momentum(d, P));
  /* rounding against the momentum scale of the start, sqrt(2 E_0 M) (M the total mass) */
  const double scale = sqrt(2.0 * e0 * (double)mass0);
  for (int k = 0; k < 3; k++) GRAN_ASSERT_ABS(P[k], 0.0, 1e-12 * scale);
  /* the sparse size distribution holds the same clusters */
  int64_t ns = 0;
  GRAN_ASSERT_OK(gran_dsmc_size_distribution(d, 0, &ns, NULL, NULL, NULL));
  assert_int_equal(ns, st.nsizes);
  int64_t *sz = (int64_t *)malloc((size_t)ns * sizeof *sz), *cn = (int64_t *)malloc((size_t)ns * sizeof *cn);
  double *T = (double *)malloc((size_t)ns * sizeof *T);
  GRAN_ASSERT_OK(gran_dsmc_size_distribution(d, ns, &ns, sz, cn, T));
  int64_t ncl = 0, mm = 0;
  for (int64_t q = 0; q < ns; q++) {
    assert_true(cn[q] > 0 && (q == 0 || sz[q] > sz[q - 1]) && T[q] >= 0);
    ncl += cn[q];
    mm += sz[q] * cn[q];
    if (cn[q] > 1000 || ns > 1000) continue; /* the sums check the large counts */
    int64_t c = 0;
    for (int64_t j = 0; j < p->n; j++) c += p->species[j] + 1 == sz[q];
    assert_int_equal(c, cn[q]);
  }
  assert_int_equal(ncl, st.nclusters);
  assert_int_equal(mm, mass0);
  free(sz);
  free(cn);
  free(T);
}

#ifdef GRANARY_IO_TEST_UTIL_H
/* The clusters datasets of a run with three output times and M sizes (file `out`): n_1, n_2 at
 * the last time within 4 sqrt(n) + 1.5 % of clusters/n_theory (t523), merges and breakups at the
 * last time above 100, and the ledger clusters/ledger closing energy/e_dissipated and e_kin. */
static inline void agg_check_run_output(const char *out, int64_t M) {
  hid_t f = H5Fopen(out, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t nn = 0, nth = 0, ns = 0, nl = 0, ne = 0;
  hsize_t dims[4];
  assert_int_equal(io_h5_dims(f, "/clusters/n", dims), 2);
  double *n = io_h5_read_double(f, "/clusters/n", &nn);
  double *th = io_h5_read_double(f, "/clusters/n_theory", &nth);
  double *st = io_h5_read_double(f, "/clusters/stats", &ns);
  double *led = io_h5_read_double(f, "/clusters/ledger", &nl);
  double *ek = io_h5_read_double(f, "/energy/e_kin", &ne);
  double *e0 = io_h5_read_double(f, "/energy/e_initial", &ne);
  double *ed = io_h5_read_double(f, "/energy/e_dissipated", &ne);
  assert_int_equal(nn, 3 * M);
  assert_int_equal(nth, 3 * M);
  for (int k = 0; k < 2; k++)
    GRAN_ASSERT_SIGMA(n[2 * M + k], th[2 * M + k], sqrt(th[2 * M + k]) + 0.015 * th[2 * M + k] / 4, 4);
  assert_true(st[6 * 2 + 3] > 100 && st[6 * 2 + 4] > 100); /* merges and breakups happened */
  for (int i = 0; i < 3; i++) {
    GRAN_ASSERT_REL(ed[i], led[4 * i] + led[4 * i + 1] + led[4 * i + 2] - led[4 * i + 3], 1e-13);
    GRAN_ASSERT_ABS(ek[i], e0[i] - ed[i], 1e-12 * e0[i]);
  }
  free(n), free(th), free(st), free(led), free(ek), free(e0), free(ed);
  H5Fclose(f);
}

/* a scene text that must fail to parse, with a message naming `key` */
static inline void agg_expect_parse_error(const char *text, const char *key) {
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_parse(text, "bad.toml", &s), GRAN_ERR_PARSE);
  if (!strstr(gran_last_error_message(), key))
    fail_msg("message '%s' does not name '%s'", gran_last_error_message(), key);
  assert_null(s);
}
#endif

#endif
