/* t502-dsmc-api.c - DSMC engine: argument checking (exact codes, named arguments), initial state,
 * counts, memory of effects that are off, exact bookkeeping (chunked advance, trajectories). */
#include "dsmc_util.h"

static void test_options_default(void **state) {
  (void)state;
  gran_dsmc_options o;
  GRAN_ASSERT_OK(gran_dsmc_options_default(&o));
  assert_int_equal(o.selector, GRAN_SELECTOR_LOWRANK);
  assert_int_equal(o.observe, 0);
  assert_true(o.volume == 0 && o.t_start == 0 && o.bound_refresh == 0 && o.traj_per_species == 0);
  GRAN_ASSERT_ERR(gran_dsmc_options_default(NULL), GRAN_ERR_ARG);
}

static void expect_msg(const char *word) {
  if (!strstr(gran_last_error_message(), word))
    fail_msg("message '%s' does not name '%s'", gran_last_error_message(), word);
}

static void test_bad_arguments(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(0.1, 0.5);
  gran_dsmc *sim = (gran_dsmc *)0x1;
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 1, 1000.0, 0);
  int64_t counts[1] = {100};
  double T0[1] = {1.0};

  GRAN_ASSERT_ERR(gran_dsmc_create(NULL, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("mix");
  assert_null(sim); /* *sim is NULLed first */
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, NULL, &sim), GRAN_ERR_ARG);
  expect_msg("opt");
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, NULL), GRAN_ERR_ARG);
  expect_msg("sim");

  counts[0] = -3;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("counts[0]");
  counts[0] = 100;
  T0[0] = NAN;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("T0[0]");
  T0[0] = -1;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("T0[0]");
  T0[0] = 1;

  o.selector = 7;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("selector");
  o.selector = -1;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("selector");
  o.selector = GRAN_SELECTOR_LOWRANK;

  o.observe = 64;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("observe");
  o.observe = 0;

  o.volume = 0;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, NULL, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("volume");
  o.volume = -5;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, NULL, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("volume");
  o.volume = NAN;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("volume");
  o.volume = 1000;

  o.t_start = INFINITY;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("t_start");
  o.t_start = 0;
  o.bound_refresh = -1;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("bound_refresh");
  o.bound_refresh = 0;

  o.observe = GRAN_OBSERVE_TRAJECTORIES;
  o.traj_per_species = 1;
  o.traj_samples = 10;
  o.traj_dt = 0;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("traj_dt");
  o.traj_dt = 1;
  o.traj_samples = 0;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("traj_samples");
  o.traj_samples = 10;
  o.traj_per_species = -2;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, counts, T0, &o, &sim), GRAN_ERR_ARG);
  expect_msg("traj_per_species");
  o.observe = 0;
  o.traj_per_species = 0;

  /* eps > 1 is refused by the mixture API, before any engine exists */
  GRAN_ASSERT_ERR(gran_mixture_set_restitution(mix, 1.5), GRAN_ERR_ARG);

  /* a good engine, then bad calls on it */
  GRAN_ASSERT_OK(gran_dsmc_create(mix, counts, T0, &o, &sim));
  GRAN_ASSERT_ERR(gran_dsmc_advance(sim, NAN), GRAN_ERR_ARG);
  expect_msg("t_end");
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 1.0));
  GRAN_ASSERT_ERR(gran_dsmc_advance(sim, 0.5), GRAN_ERR_ARG);
  expect_msg("t_end");
  GRAN_ASSERT_ERR(gran_dsmc_advance_collisions(sim, -1), GRAN_ERR_ARG);
  expect_msg("ncollisions");
  GRAN_ASSERT_ERR(gran_dsmc_advance(NULL, 1.0), GRAN_ERR_ARG);
  expect_msg("sim");
  double msd;
  GRAN_ASSERT_ERR(gran_dsmc_msd(sim, &msd, NULL), GRAN_ERR_STATE);
  expect_msg("GRAN_OBSERVE_DISPLACEMENT");
  int64_t cc;
  GRAN_ASSERT_ERR(gran_dsmc_collision_counts(sim, &cc), GRAN_ERR_STATE);
  expect_msg("GRAN_OBSERVE_COLLISION_COUNTS");
  int64_t nt;
  GRAN_ASSERT_ERR(gran_dsmc_trajectories(sim, &nt, NULL, NULL, NULL), GRAN_ERR_STATE);
  expect_msg("GRAN_OBSERVE_TRAJECTORIES");
  GRAN_ASSERT_ERR(gran_dsmc_temperatures(sim, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_momentum(sim, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_get_stats(sim, NULL), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_time(NULL, &msd), GRAN_ERR_ARG);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&sim));
  assert_null(sim);
  GRAN_ASSERT_OK(gran_dsmc_destroy(&sim)); /* NULL-safe */
  GRAN_ASSERT_OK(gran_dsmc_destroy(NULL));
  gran_mixture_destroy(&mix);
}

/* Table I counts: N_k = round(n_k V) with n_k = 0.1 k^-3, V = N_1 / 0.1 = 1e4 (N_1 = 1000):
 * 1000, 125, 37, 16, 8, 5, 3, 2, 1, 1, 1 (0.751), 1 (0.579), 0 (0.455). The 13th species is empty
 * and must cost nothing and break nothing. */
static void test_counts_rounding_and_empty_species(void **state) {
  (void)state;
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(13, 1.0, 1.0, 0.1, 3.0, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  const int64_t expect[13] = {1000, 125, 37, 16, 8, 5, 3, 2, 1, 1, 1, 1, 0};
  for (int sel = 0; sel < 4; sel++) {
    gran_dsmc_options o = dsmc_opts(sel, 3, 1e4, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS);
    gran_dsmc *sim;
    double T0[13];
    for (int k = 0; k < 13; k++) T0[k] = 1.0;
    GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
    int64_t c[13], off[14];
    GRAN_ASSERT_OK(gran_dsmc_counts(sim, c));
    GRAN_ASSERT_OK(gran_dsmc_species_offsets(sim, off));
    int64_t n = 0;
    for (int k = 0; k < 13; k++) {
      assert_int_equal(c[k], expect[k]);
      assert_int_equal(off[k], n);
      n += c[k];
    }
    assert_int_equal(off[13], n);
    const gran_particles *p;
    GRAN_ASSERT_OK(gran_dsmc_particles(sim, &p));
    assert_int_equal(p->n, n);
    for (int k = 0; k < 13; k++)
      for (int64_t j = off[k]; j < off[k + 1]; j++) assert_int_equal(p->species[j], k);
    GRAN_ASSERT_OK(gran_dsmc_advance(sim, 20.0));
    double T[13], msd[13], tot, a2[13];
    GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
    GRAN_ASSERT_OK(gran_dsmc_msd(sim, msd, &tot));
    GRAN_ASSERT_OK(gran_dsmc_sonine_a2(sim, a2));
    assert_true(isnan(T[12]) && isnan(msd[12]) && isnan(a2[12])); /* empty species: NaN */
    for (int k = 0; k < 12; k++) assert_true(isfinite(T[k]) && T[k] > 0 && isfinite(msd[k]));
    int64_t cc[13 * 13], sum = 0;
    GRAN_ASSERT_OK(gran_dsmc_collision_counts(sim, cc));
    for (int i = 0; i < 13; i++) {
      assert_int_equal(cc[i * 13 + 12], 0);
      for (int k = i; k < 13; k++) {
        assert_int_equal(cc[i * 13 + k], cc[k * 13 + i]);
        sum += cc[i * 13 + k];
      }
    }
    assert_int_equal(sum, dsmc_collisions(sim));
    assert_true(sum > 2000); /* about 4 collisions per particle by t = 20 */
    gran_dsmc_destroy(&sim);
  }
  gran_mixture_destroy(&mix);
}

/* Initial state: Maxwellian at T0 per species (T_k within 5 standard errors sqrt(2/(3 N_k)) T_k),
 * zero total momentum to rounding, HCS temperatures of the theory module when T0 is NULL. */
static void test_initial_state(void **state) {
  (void)state;
  double m[2] = {1.0, 4.0}, s[2] = {1.0, 1.0}, n[2] = {0.05, 0.05};
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.5));
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 11, 4e5, 0);
  gran_dsmc *sim;
  double T0[2] = {2.0, 0.5}, T[2], P[3], e0, ek, ed;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, T0, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
  for (int k = 0; k < 2; k++) GRAN_ASSERT_SIGMA(T[k], T0[k], T0[k] * sqrt(2.0 / (3.0 * 2e4)), 5);
  GRAN_ASSERT_OK(gran_dsmc_momentum(sim, P));
  GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
  const double pscale = sqrt(2.0 * ek * 8.0 * 2e4); /* sqrt(2 E sum m) */
  for (int d = 0; d < 3; d++) GRAN_ASSERT_ABS(P[d], 0.0, 1e-13 * pscale);
  assert_true(ek == e0 && ed == 0.0);
  double t;
  GRAN_ASSERT_OK(gran_dsmc_time(sim, &t));
  assert_true(t == 0.0);
  gran_dsmc_destroy(&sim);

  double Th[2], tau0;
  GRAN_ASSERT_OK(gran_theory_hcs(mix, GRAN_HCS_NORM_MEAN, 1.0, Th, &tau0));
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_temperatures(sim, T));
  for (int k = 0; k < 2; k++) GRAN_ASSERT_SIGMA(T[k], Th[k], Th[k] * sqrt(2.0 / (3.0 * 2e4)), 5);
  assert_true(fabs(Th[0] / Th[1] - 1.0) > 0.05); /* the HCS is not equipartition here */
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
}

/* Effects that are off have no memory: without GRAN_OBSERVE_DISPLACEMENT no r / t_last arrays
 * (28 bytes per particle: v + species), with it 60 bytes. */
static void test_memory_of_effects(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(0.1, 0.9);
  int64_t counts[1] = {5000};
  for (int obs = 0; obs <= 1; obs++) {
    gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 1, 0, obs ? GRAN_OBSERVE_DISPLACEMENT : 0);
    gran_dsmc *sim;
    GRAN_ASSERT_OK(gran_dsmc_create(mix, counts, NULL, &o, &sim));
    const gran_particles *p;
    GRAN_ASSERT_OK(gran_dsmc_particles(sim, &p));
    int64_t bytes;
    GRAN_ASSERT_OK(gran_particles_memory(p, &bytes));
    if (obs) {
      assert_non_null(p->r);
      assert_non_null(p->t_last);
      assert_int_equal(bytes, 60 * 5000);
    } else {
      assert_null(p->r);
      assert_null(p->t_last);
      assert_int_equal(bytes, 28 * 5000);
    }
    assert_null(p->x);
    assert_null(p->mass);
    gran_dsmc_stats st;
    GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
    assert_int_equal(st.nparticles, 5000);
    GRAN_ASSERT_REL(st.volume, 5000 / 0.1, 1e-15); /* counts given, volume 0: V = N / n */
    gran_dsmc_destroy(&sim);
  }
  gran_mixture_destroy(&mix);
}

/* The state after advance(t2) does not depend on how the interval was cut into calls (the pending
 * trial is part of the state), and advance_collisions(n) adds exactly n collisions. */
static void test_chunking_is_exact(void **state) {
  (void)state;
  double m[2] = {1.0, 3.0}, s[2] = {1.0, 1.4}, n[2] = {0.08, 0.02};
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create(2, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.7));
  for (int q = 0; q < 8; q++) {
    const int sel = q % 4, disp = q / 4; /* both time keepings: with and without displacements */
    gran_dsmc_options o = dsmc_opts(sel, 5, 2e4, disp ? GRAN_OBSERVE_DISPLACEMENT : 0);
    o.bound_refresh = 500;
    gran_dsmc *a, *b;
    GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &a));
    GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &b));
    GRAN_ASSERT_OK(gran_dsmc_advance(a, 30.0));
    for (int q = 1; q <= 300; q++) GRAN_ASSERT_OK(gran_dsmc_advance(b, 0.1 * q));
    GRAN_ASSERT_OK(gran_dsmc_advance(b, 30.0));
    const gran_particles *pa, *pb;
    GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
    GRAN_ASSERT_OK(gran_dsmc_particles(b, &pb));
    assert_memory_equal(pa->v, pb->v, sizeof(double) * 3 * (size_t)pa->n);
    if (disp) {
      assert_memory_equal(pa->r, pb->r, sizeof(double) * 3 * (size_t)pa->n);
      assert_memory_equal(pa->t_last, pb->t_last, sizeof(double) * (size_t)pa->n);
    }
    gran_dsmc_stats sa, sb;
    GRAN_ASSERT_OK(gran_dsmc_get_stats(a, &sa));
    GRAN_ASSERT_OK(gran_dsmc_get_stats(b, &sb));
    assert_int_equal(sa.collisions, sb.collisions);
    assert_int_equal(sa.trials, sb.trials);
    assert_true(sa.bound_tightenings > 5);
    const int64_t c0 = sa.collisions;
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(a, 12345));
    assert_int_equal(dsmc_collisions(a), c0 + 12345);
    double ta;
    GRAN_ASSERT_OK(gran_dsmc_time(a, &ta));
    assert_true(ta > 30.0);
    gran_dsmc_destroy(&a);
    gran_dsmc_destroy(&b);
  }
  gran_mixture_destroy(&mix);
}

/* Trajectories: sample 0 is 0, the sample at the current grid time equals the lazily evaluated
 * displacement r + v (t - t_last) of the tracer, samples not reached are NaN; tracers are the
 * first traj_per_species particles of each species (fewer when the species is smaller). */
static void test_trajectories(void **state) {
  (void)state;
  double m[3] = {1.0, 2.0, 5.0}, s[3] = {1.0, 1.2, 1.7}, n[3] = {0.1, 0.0003, 0.01};
  gran_mixture *mix;
  GRAN_ASSERT_OK(gran_mixture_create(3, m, s, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.8));
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 9, 1e4, GRAN_OBSERVE_TRAJECTORIES);
  o.traj_per_species = 4;
  o.traj_dt = 0.25;
  o.traj_samples = 41;
  o.t_start = 1.0;
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &sim)); /* counts 1000, 3, 100 */
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 1.0 + 0.25 * 20));       /* exactly grid time 20 */
  int64_t nt, ns, off[4];
  const double *xyz;
  const int32_t *sp;
  GRAN_ASSERT_OK(gran_dsmc_trajectories(sim, &nt, &ns, &xyz, &sp));
  assert_int_equal(nt, 4 + 3 + 4);
  assert_int_equal(ns, 41);
  GRAN_ASSERT_OK(gran_dsmc_species_offsets(sim, off));
  const gran_particles *p;
  GRAN_ASSERT_OK(gran_dsmc_particles(sim, &p));
  assert_non_null(p->r); /* trajectories imply displacement tracking */
  double t;
  GRAN_ASSERT_OK(gran_dsmc_time(sim, &t));
  int q = 0;
  for (int k = 0; k < 3; k++) {
    const int64_t ntk = k == 1 ? 3 : 4;
    for (int64_t i = 0; i < ntk; i++, q++) {
      assert_int_equal(sp[q], k);
      const int64_t j = off[k] + i;
      for (int d = 0; d < 3; d++) {
        assert_true(xyz[(q * ns + 0) * 3 + d] == 0.0);
        const double expect = p->r[3 * j + d] + p->v[3 * j + d] * (t - p->t_last[j]);
        /* equal up to rounding (the library may fuse the multiply-add) */
        const double scale = fabs(p->r[3 * j + d]) + fabs(p->v[3 * j + d] * (t - p->t_last[j]));
        GRAN_ASSERT_ABS(xyz[(q * ns + 20) * 3 + d], expect, 4e-16 * scale);
        assert_true(isnan(xyz[(q * ns + 21) * 3 + d]));
      }
      /* the tracer moved: its displacement at sample 20 is not zero */
      assert_true(fabs(xyz[(q * ns + 20) * 3]) > 0);
    }
  }
  /* MSD at this time from the same lazily evaluated displacements */
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 100.0)); /* past the grid: every sample filled */
  GRAN_ASSERT_OK(gran_dsmc_trajectories(sim, &nt, &ns, &xyz, &sp));
  for (int64_t i = 0; i < nt * ns * 3; i++) assert_true(isfinite(xyz[i]));
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
}

/* Degenerate systems: one particle (time passes, no collision possible), all particles at rest
 * (rate 0), species with zero count. */
static void test_degenerate(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(0.1, 0.5);
  int64_t one[1] = {1};
  for (int sel = 0; sel < 4; sel++) {
    gran_dsmc_options o = dsmc_opts(sel, 1, 10.0, 0);
    gran_dsmc *sim;
    GRAN_ASSERT_OK(gran_dsmc_create(mix, one, NULL, &o, &sim));
    GRAN_ASSERT_OK(gran_dsmc_advance(sim, 50.0));
    assert_int_equal(dsmc_collisions(sim), 0);
    GRAN_ASSERT_ERR(gran_dsmc_advance_collisions(sim, 1), GRAN_ERR_STATE);
    gran_dsmc_destroy(&sim);
    int64_t many[1] = {100};
    double T0[1] = {0.0};
    GRAN_ASSERT_OK(gran_dsmc_create(mix, many, T0, &o, &sim));
    GRAN_ASSERT_OK(gran_dsmc_advance(sim, 50.0));
    assert_int_equal(dsmc_collisions(sim), 0);
    GRAN_ASSERT_ERR(gran_dsmc_advance_collisions(sim, 1), GRAN_ERR_STATE);
    expect_msg("rate");
    gran_dsmc_destroy(&sim);
  }
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_options_default),
      cmocka_unit_test(test_bad_arguments),
      cmocka_unit_test(test_counts_rounding_and_empty_species),
      cmocka_unit_test(test_initial_state),
      cmocka_unit_test(test_memory_of_effects),
      cmocka_unit_test(test_chunking_is_exact),
      cmocka_unit_test(test_trajectories),
      cmocka_unit_test(test_degenerate),
  };
  return cmocka_run_group_tests_name("t502-dsmc-api", tests, NULL, NULL);
}
