/* t850-srd-gpu.c - the GSRD test bodies of tests/srd_device_body.h on the GPU (make test-gpu), and
 * CPU versus GPU for one scene and seed: same shift, same per-cell streams, same shared arithmetic;
 * only the order of the cell-sum additions differs (atomics), so in double the velocities agree to
 * ~1e-13 after 20 steps (tolerance 1e-9 absolute, v ~ 1) and the per-cell RNG states bit for bit;
 * with float storage the temperature agrees within its statistical noise (4 standard errors). */
#include "srd_device_body.h"

static void test_conservation_gpu(void **state) {
  (void)state;
  sdb_body_conservation(1, 3, 0, 1.0);
  sdb_body_conservation(1, 2, 0, 1.0);
  sdb_body_conservation(1, 3, 0, 0.9);
  sdb_body_conservation(1, 3, 1, 1.0); /* float storage */
  sdb_body_conservation(1, 2, 1, 1.0);
}

static double temperature(const sdb_state *st) {
  double m[3], e;
  sdb_totals(st, m, &e);
  const double n = (double)st->p.n, d = st->p.geom.dim;
  double e_flow = 0.0;
  for (int k = 0; k < d; ++k) e_flow += 0.5 * m[k] * m[k] / n;
  return 2.0 * (e - e_flow) / (d * n);
}

static void compare(int dim, double eps, int precision) {
  sdb_state c, g;
  sdb_init(&c, 0, dim, dim == 3 ? 8 : 16, 10, 130.0, eps, 0, 77);
  sdb_init(&g, 1, dim, dim == 3 ? 8 : 16, 10, 130.0, eps, precision, 77);
  sdb_run(&c, 20);
  sdb_run(&g, 20);
  const double tc = temperature(&c), tg = temperature(&g);
  if (precision == 0) {
    double dmax = 0.0;
    for (int64_t i = 0; i < c.p.n; ++i)
      for (int k = 0; k < dim; ++k) {
        const double dv = fabs(c.v[k][i] - g.v[k][i]), dx = fabs(c.x[k][i] - g.x[k][i]);
        if (dv > dmax) dmax = dv;
        if (dx > dmax) dmax = dx;
      }
    if (dmax > 1e-9) fail_msg("dim %d eps %g: CPU and GPU differ by %g", dim, eps, dmax);
    assert_memory_equal(c.cell_rng, g.cell_rng, sizeof(gran_rng) * (size_t)c.ncell);
    assert_int_equal(c.nclamp, g.nclamp);
    if (!gran_test_rel_ok(tg, tc, 1e-12)) fail_msg("T: CPU %.17g GPU %.17g", tc, tg);
  } else {
    /* standard error of the temperature estimate from N particles: T sqrt(2 / (d N)) */
    const double se = tc * sqrt(2.0 / (dim * (double)c.p.n));
    if (fabs(tg - tc) > 4.0 * se) fail_msg("float: T CPU %.9g GPU %.9g (4 se = %.3g)", tc, tg, 4 * se);
  }
  sdb_free(&c);
  sdb_free(&g);
}

static void test_cpu_vs_gpu(void **state) {
  (void)state;
  compare(3, 1.0, 0);
  compare(2, 1.0, 0);
  compare(3, 0.9, 0);
  compare(3, 1.0, 1);
  compare(3, 0.9, 1);
}

static void test_sort_keeps_state(void **state) {
  (void)state;
  sdb_state g;
  sdb_init(&g, 1, 3, 8, 10, 130.0, 1.0, 0, 5);
  double m0[3], e0, m1[3], e1;
  GRAN_ASSERT_OK(gran_cuda_srd_moments(g.dev, m0, &e0));
  GRAN_ASSERT_OK(gran_cuda_srd_sort(g.dev));
  GRAN_ASSERT_OK(gran_cuda_srd_moments(g.dev, m1, &e1));
  for (int k = 0; k < 3; ++k) assert_true(gran_test_rel_ok(m1[k], m0[k], 1e-12));
  assert_true(gran_test_rel_ok(e1, e0, 1e-12));
  sdb_run(&g, 1); /* downloads: particles now ordered by unshifted cell */
  sdb_free(&g);
}

static void test_bad_input(void **state) {
  (void)state;
  sdb_state g;
  sdb_init(&g, 1, 3, 4, 2, 90.0, 1.0, 0, 1);
  const double s_bad[3] = {1.5, 0, 0}; /* a = 1: outside [0, a) */
  GRAN_ASSERT_ERR(gran_cuda_srd_step(g.dev, &g.p.geom, s_bad, NULL, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_cuda_srd_step(NULL, &g.p.geom, s_bad, NULL, NULL), GRAN_ERR_ARG);
  gran_cuda_srd_params p = g.p;
  gran_cuda_srd *h = NULL;
  const double *xs[3] = {g.x[0], g.x[1], g.x[2]}, *vs[3] = {g.v[0], g.v[1], g.v[2]};
  p.precision = 2;
  GRAN_ASSERT_ERR(gran_cuda_srd_create(&p, xs, vs, g.cell_rng, &h), GRAN_ERR_ARG);
  p = g.p;
  p.geom.wall_axis = 1;
  GRAN_ASSERT_ERR(gran_cuda_srd_create(&p, xs, vs, g.cell_rng, &h), GRAN_ERR_UNSUPPORTED);
  p = g.p;
  p.n = (int64_t)1 << 40; /* 1e12 particles: refused before any allocation */
  gran_clear_error();
  int rc = gran_cuda_srd_create(&p, xs, vs, g.cell_rng, &h);
  assert_true(rc == GRAN_ERR_UNSUPPORTED || rc == GRAN_ERR_NOMEM);
  assert_null(h);
  sdb_free(&g);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_conservation_gpu),
      cmocka_unit_test(test_cpu_vs_gpu),
      cmocka_unit_test(test_sort_keeps_state),
      cmocka_unit_test(test_bad_input),
  };
  return cmocka_run_group_tests_name("t850-srd-gpu", tests, NULL, NULL);
}
