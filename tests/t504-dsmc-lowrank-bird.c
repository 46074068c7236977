/* t504-dsmc-lowrank-bird.c - the low-rank selector and Bird's selector (and the paper variants of
 * both) simulate the same process: on a scaled-down Table I setup (N_1 = 2e4, n_k = 0.1 k^-3,
 * N_k = round(N_1 k^-3) >= 1, i.e. 34 species and 24035 particles, eps = 0.5, T_k(0) = 1,
 * t = 10) the collision count, the energy, the temperatures and MSDs of the three lightest
 * species, the total MSD and the collisions of the pairs 1-1 and 1-2 agree within noise.
 * R = 12 seeds per method (6 under ASan); the standard error of a difference of two method means
 * uses the variance pooled over the four methods (4(R-1) degrees of freedom, nearly normal):
 * tolerance 4.5 standard errors per quantity. */
#include "dsmc_util.h"

#define NQ 11
static const char *qname[NQ] = {"collisions", "E_kin", "T_1", "T_2", "T_3", "MSD_1",
                                "MSD_2", "MSD_3", "MSD_total", "coll 1-1", "coll 1-2"};

static void run_one(const gran_mixture *mix, int sel, uint64_t seed, double *q) {
  gran_dsmc_options o = dsmc_opts(sel, seed, 2e5, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS);
  double T0[34];
  for (int k = 0; k < 34; k++) T0[k] = 1.0;
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 10.0));
  double T[34], msd[34], tot, ek;
  static int64_t cc[34 * 34];
  GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
  GRAN_ASSERT_OK(gran_dsmc_msd(sim, msd, &tot));
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, NULL, NULL));
  GRAN_ASSERT_OK(gran_dsmc_collision_counts(sim, cc));
  q[0] = (double)dsmc_collisions(sim);
  q[1] = ek;
  for (int k = 0; k < 3; k++) {
    q[2 + k] = T[k];
    q[5 + k] = msd[k];
  }
  q[8] = tot;
  q[9] = (double)cc[0];
  q[10] = (double)cc[1];
  gran_dsmc_destroy(&sim);
}

static void test_same_process(void **state) {
  (void)state;
  const int R = DSMC_ASAN ? 6 : 12;
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(34, 1.0, 1.0, 0.1, 3.0, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  int64_t counts[34];
  {
    gran_dsmc_options o = dsmc_opts(0, 1, 2e5, 0);
    gran_dsmc *sim;
    GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &sim));
    GRAN_ASSERT_OK(gran_dsmc_counts(sim, counts));
    gran_dsmc_destroy(&sim);
    int64_t n = 0;
    for (int k = 0; k < 34; k++) {
      assert_true(counts[k] >= 1);
      n += counts[k];
    }
    assert_int_equal(counts[0], 20000);
    assert_int_equal(counts[33], 1); /* 2e4 / 34^3 = 0.509 */
    assert_int_equal(n, 24035); /* halves round away from 0: 2e4/4^3 = 312.5 -> 313, 2e4/20^3 = 2.5 -> 3 */
  }
  static double q[4][12][NQ];
  for (int sel = 0; sel < 4; sel++)
    for (int r = 0; r < R; r++) run_one(mix, sel, 1000 + (uint64_t)r, q[sel][r]);
  for (int i = 0; i < NQ; i++) {
    double mean[4], var = 0;
    for (int sel = 0; sel < 4; sel++) {
      mean[sel] = 0;
      for (int r = 0; r < R; r++) mean[sel] += q[sel][r][i] / R;
      for (int r = 0; r < R; r++) var += (q[sel][r][i] - mean[sel]) * (q[sel][r][i] - mean[sel]);
    }
    var /= 4.0 * (R - 1);
    const double se = sqrt(2.0 * var / R);
    print_message("%-10s lowrank %.6g bird %.6g lowrank-paper %.6g bird-paper %.6g (se of a difference %.2g)\n",
                  qname[i], mean[0], mean[1], mean[2], mean[3], se);
    for (int sel = 1; sel < 4; sel++) GRAN_ASSERT_SIGMA(mean[sel], mean[0], se, 4.5);
    /* every quantity resolved to better than 2% (3% with the ASan sample) */
    assert_true(se < (DSMC_ASAN ? 0.03 : 0.02) * fabs(mean[0]));
  }
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_same_process),
  };
  return cmocka_run_group_tests_name("t504-dsmc-lowrank-bird", tests, NULL, NULL);
}
