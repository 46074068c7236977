/* t511-dsmc-classes.c - speed classes (opt.speed_classes = 1): the low-rank selector
 * over (species, speed class) leaves with fixed capacities. (Its statistics against `lowrank_paper`
 * on the three systems of b501: t510; rates per pair, Haff's law and the MSD with classes: t503;
 * bit-for-bit restarts: t506.)
 * Here: the class invariants seen from outside (every particle of the view, counts, the ledger
 * closes, momentum conserved, tracers and viscoelastic restitution with classes), the option's
 * checks, the view by identity with trajectories, damaged class state in a checkpoint. */
#include "io_test_util.h" /* first: it sets the feature-test macros */
#include "dsmc_util.h"

#include <hdf5.h>
#include <inttypes.h>
#include <unistd.h>
#include <zlib.h>

/* A gas of two species and a tracer species (all large enough for classes), displacements and
 * pair counts on: the ledger closes, counts and the view are consistent, particles moved between
 * classes, tracer-tracer pairs never collide, the gas's momentum stays 0. Then viscoelastic. */
static void test_invariants(void **state) {
  (void)state;
  double m[3] = {1.0, 2.0, 5.0}, sg[3] = {1.0, 1.2, 1.5}, n[3] = {0.1, 0.01, 0.0};
  int64_t counts[3] = {3000, 600, 400};
  for (int visco = 0; visco < 2; visco++) {
    gran_mixture *mix;
    GRAN_ASSERT_OK(gran_mixture_create(3, m, sg, n, &mix));
    if (visco)
      GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.05));
    else
      GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.7));
    gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 11 + (uint64_t)visco, 0,
                                    GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS);
    o.speed_classes = 1;
    o.bound_refresh = 1500;
    double T0[3] = {1.0, 1.0, 4.0};
    gran_dsmc *sim;
    GRAN_ASSERT_OK(gran_dsmc_create(mix, counts, T0, &o, &sim));
    GRAN_ASSERT_OK(gran_dsmc_advance_collisions(sim, 60000));
    gran_dsmc_stats st;
    GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
    assert_int_equal(st.collisions, 60000);
    assert_true(st.class_moves > 10000);
    assert_true(st.acceptance > 0.3); /* one bound per species: about 0.2 */
    double ek, e0, ed;
    GRAN_ASSERT_OK(gran_dsmc_energy(sim, &ek, &e0, &ed));
    GRAN_ASSERT_REL(e0 - ed, ek, 1e-12);
    int64_t cc[9], got[3], off[4];
    GRAN_ASSERT_OK(gran_dsmc_collision_counts(sim, cc));
    assert_int_equal(cc[8], 0); /* tracer-tracer */
    int64_t tot = 0;
    for (int i = 0; i < 3; i++)
      for (int k = i; k < 3; k++) tot += cc[i * 3 + k];
    assert_int_equal(tot, 60000);
    GRAN_ASSERT_OK(gran_dsmc_counts(sim, got));
    GRAN_ASSERT_OK(gran_dsmc_species_offsets(sim, off));
    const gran_particles *p;
    GRAN_ASSERT_OK(gran_dsmc_particles(sim, &p));
    assert_int_equal(p->n, 4000);
    double P[3] = {0, 0, 0}, e = 0, msd = 0;
    for (int k = 0; k < 3; k++) {
      assert_int_equal(got[k], counts[k]);
      for (int64_t j = off[k]; j < off[k + 1]; j++) {
        assert_int_equal(p->species[j], k);
        const double *v = p->v + 3 * j;
        e += 0.5 * m[k] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (k < 2)
          for (int d = 0; d < 3; d++) P[d] += m[k] * v[d];
      }
    }
    GRAN_ASSERT_REL(e, ek, 1e-12); /* the view holds every particle once */
    /* gran_dsmc_species_velocities: each species' block of the view, from the slots (no view) */
    for (int k = 0; k < 3; k++) {
      double *vk = malloc(sizeof(double) * 3 * (size_t)counts[k]);
      GRAN_ASSERT_OK(gran_dsmc_species_velocities(sim, k, vk));
      assert_memory_equal(vk, p->v + 3 * off[k], sizeof(double) * 3 * (size_t)counts[k]);
      free(vk);
    }
    GRAN_ASSERT_ERR(gran_dsmc_species_velocities(sim, 3, P), GRAN_ERR_ARG);
    assert_non_null(strstr(gran_last_error_message(), "'k'"));
    GRAN_ASSERT_ERR(gran_dsmc_species_velocities(sim, 0, NULL), GRAN_ERR_ARG);
    for (int d = 0; d < 3; d++) GRAN_ASSERT_ABS(P[d], 0.0, 1e-10 * sqrt(e));
    GRAN_ASSERT_OK(gran_dsmc_msd(sim, NULL, &msd));
    assert_true(msd > 0 && isfinite(msd));
    gran_dsmc_destroy(&sim);
    gran_mixture_destroy(&mix);
  }
}

/* The option: 0 or 1 (else GRAN_ERR_ARG naming it); Bird ignores it; with trajectories the view
 * is by identity: sample s of tracked particle q equals r + v (t - t_start) of its view entry. */
static void test_option_and_identity(void **state) {
  (void)state;
  gran_mixture *mix = dsmc_mono(0.1, 0.8);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 5, 2e4, 0);
  gran_dsmc *sim = NULL;
  o.speed_classes = 2;
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, NULL, NULL, &o, &sim), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "speed_classes"));
  assert_null(sim);
  o.speed_classes = 1;
  o.selector = GRAN_SELECTOR_BIRD; /* Bird has no speed classes: refused, not silently ignored */
  GRAN_ASSERT_ERR(gran_dsmc_create(mix, NULL, NULL, &o, &sim), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "speed_classes"));
  assert_null(sim);
  o.selector = GRAN_SELECTOR_LOWRANK;
  o.observe = GRAN_OBSERVE_TRAJECTORIES;
  o.traj_per_species = 50;
  o.traj_dt = 0.25;
  o.traj_samples = 21;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 5.0)); /* the last sample time */
  gran_dsmc_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
  assert_true(st.class_moves > 1000);
  int64_t nt, ns;
  const double *xyz;
  GRAN_ASSERT_OK(gran_dsmc_trajectories(sim, &nt, &ns, &xyz, NULL));
  assert_int_equal(nt, 50);
  const gran_particles *p;
  GRAN_ASSERT_OK(gran_dsmc_particles(sim, &p));
  for (int64_t q = 0; q < nt; q++)
    for (int d = 0; d < 3; d++) {
      const double x = xyz[(q * ns + ns - 1) * 3 + d], y = p->r[3 * q + d] + p->v[3 * q + d] * 5.0;
      GRAN_ASSERT_ABS(x, y, 1e-12 * (1 + fabs(y)));
    }
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
}

/* The scene key `[engine] speed_classes` (true, false or "auto"; default "auto" =
 * GRAN_SPEED_CLASSES_AUTO) sets the option; another value is refused
 * naming the key. */
static void test_scene_key(void **state) {
  (void)state;
  const char *base = "[mixture]\ndensity = [0.1]\n[restitution]\neps = 0.8\n[engine]\ncounts = [1000]\nt_end = 10\n";
  char txt[512];
  gran_scene *sc;
  gran_dsmc_options o;
  GRAN_ASSERT_OK(gran_scene_parse(base, "a.toml", &sc));
  GRAN_ASSERT_OK(gran_scene_dsmc_options(sc, &o, NULL, NULL));
  assert_int_equal(o.speed_classes, GRAN_SPEED_CLASSES_AUTO);
  gran_scene_destroy(&sc);
  snprintf(txt, sizeof txt, "%sspeed_classes = true\n", base);
  GRAN_ASSERT_OK(gran_scene_parse(txt, "b.toml", &sc));
  GRAN_ASSERT_OK(gran_scene_dsmc_options(sc, &o, NULL, NULL));
  assert_int_equal(o.speed_classes, 1);
  gran_mixture *mix;
  gran_dsmc *sim;
  GRAN_ASSERT_OK(gran_scene_mixture(sc, &mix));
  GRAN_ASSERT_OK(gran_scene_dsmc(sc, mix, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 2.0));
  gran_dsmc_stats st;
  GRAN_ASSERT_OK(gran_dsmc_get_stats(sim, &st));
  assert_true(st.class_moves > 0);
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&sc);
  snprintf(txt, sizeof txt, "%sspeed_classes = 2\n", base);
  sc = NULL;
  assert_int_not_equal(gran_scene_parse(txt, "c.toml", &sc), GRAN_SUCCESS);
  assert_non_null(strstr(gran_last_error_message(), "speed_classes"));
  assert_null(sc);
}

/* A damaged class state (an edit made through HDF5 with granary's file checksum recomputed, as
 * t606 does for the other datasets) is refused naming what is wrong, never used. */
/* copy `ck` to `ed`, set dataset[index] = value (int64 or double), expect the read to fail naming `why` */
static void edit_and_expect(const char *ck, const char *ed, const gran_mixture *mix, const char *dataset,
                            int64_t index, double value, int is_int, const char *why) {
  io_edit_copy(ck, ed, dataset, index, value, is_int);
  gran_dsmc *sim = (gran_dsmc *)0x1;
  const int st = gran_dsmc_checkpoint_read(ed, "/engine", mix, &sim);
  if (st == GRAN_SUCCESS || !strstr(gran_last_error_message(), why))
    fail_msg("edit of %s[%" PRId64 "] = %g: status %d, message '%s' (expected '%s')", dataset, index, value, st,
             gran_last_error_message(), why);
  assert_null(sim);
}

static void test_damaged_class_state(void **state) {
  (void)state;
  char ck[64], ed[64];
  snprintf(ck, sizeof ck, "/tmp/granary-t511-%d.h5", (int)getpid());
  snprintf(ed, sizeof ed, "/tmp/granary-t511-%d-ed.h5", (int)getpid());
  gran_mixture *mix = dsmc_mono(0.1, 0.7);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 9, 5e3, 0);
  o.speed_classes = 1;
  gran_dsmc *sim, *back;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &sim));
  GRAN_ASSERT_OK(gran_dsmc_advance(sim, 3.0));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(sim, ck, "/engine"));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(ck, "/engine", mix, &back)); /* intact: reads */
  gran_dsmc_destroy(&back);
  /* leaf 0 (start, cap, n): more particles than slots; a start that leaves a gap */
  edit_and_expect(ck, ed, mix, "/engine/class_leaf_int", 2, 1e6, 1, "class slots");
  edit_and_expect(ck, ed, mix, "/engine/class_leaf_int", 3, 1, 1, "class slots");
  /* leaf 3 (b, b2, lo2): a bound below its occupants; a bound that is not sqrt(b2) */
  edit_and_expect(ck, ed, mix, "/engine/class_leaf_real", 10, 1e-12, 0, "class bounds");
  edit_and_expect(ck, ed, mix, "/engine/class_leaf_real", 9, 0.5, 0, "class bounds");
  /* the tree of raises: a node that is not the sum of its children */
  edit_and_expect(ck, ed, mix, "/engine/class_ud", 1, 12345.0, 0, "class raise tree");
  /* the alias bound of a leaf above its class bound */
  edit_and_expect(ck, ed, mix, "/engine/class_ub", 0, 1e300, 0, "class alias bounds");
  /* a slot velocity of a particle */
  edit_and_expect(ck, ed, mix, "/engine/class_v", 0, NAN, 0, "class bounds");
  remove(ck);
  remove(ed);
  gran_dsmc_destroy(&sim);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_invariants),
      cmocka_unit_test(test_option_and_identity),
      cmocka_unit_test(test_scene_key),
      cmocka_unit_test(test_damaged_class_state),
  };
  return cmocka_run_group_tests_name("t511-dsmc-classes", tests, NULL, NULL);
}
