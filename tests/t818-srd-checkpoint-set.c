/* t818-srd-checkpoint-set.c - checkpoint sets of a split GSRD gas (src/srd/bricks.h: srd_bricks_save_,
 * srd_bricks_load_, srd_bricks_from_state_, srd_state_from_parts_; the part format in
 * src/srd/checkpoint.cpp), all bricks in this process:
 *  - a gas split into bricks, saved after 13 steps (a sort every 5: particles that arrived since
 *    the last sort sit out of key order, and holes), then stepped 17 more, ends in the same state
 *    bit for bit (the report's order-independent digests of every particle and cell, the ledger,
 *    the clamps, the observables after the steps) as: its parts loaded into another split and
 *    stepped 17; its parts merged into the whole decomposable engine (gran_srd_advance); the whole
 *    engine's state at step 13 split (srd_bricks_from_state_); and the parts given in another
 *    order. For every effect set: periodic 3-D eps < 1 with clamps, 2-D Lees-Edwards with the
 *    global thermostat, 2-D no-slip walls with gravity and the vibrating wall, 3-D slip walls;
 *  - refused with GRAN_ERR_IO naming what was wrong: a part missing from the set, a part given
 *    twice, another generation or step than the checkpoint's, another seed, a part whose scalar
 *    state differs (a part of another run's set at the same step), a missing file, a part of
 *    another split given as the process's own. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granary_test.h"
#include "srd/bricks.h"

enum { SAVE_AT = 13, MORE = 17, MAXP = 8 };

static char g_dir[64];

static gran_srd_options opts(int which) {
  gran_srd_options o;
  gran_srd_options_default(&o);
  o.dim = which == 0 || which == 3 ? 3 : 2;
  o.cells[0] = o.dim == 3 ? 7 : 11;
  o.cells[1] = o.dim == 3 ? 6 : 9;
  o.cells[2] = o.dim == 3 ? 5 : 1;
  o.n0 = 5;
  o.dt = 0.5;
  o.alpha_deg = 130;
  o.seed = 818;
  o.threads = 1;
  o.sort_every = 5;
  o.creation = GRAN_SRD_CREATE_CELLS;
  if (which == 0) {
    o.eps = 0.5;
    o.sigma = 0.5;
  } else if (which == 1) {
    o.shear_rate = 0.05;
    o.thermostat = 2; /* global */
  } else if (which == 2) {
    o.wall_axis = 1;
    o.wall_rule = 1;
    o.accel[1] = -0.02;
    o.vib_amp = 0.1;
    o.vib_omega = 0.3;
    o.eps = 0.8;
    o.sigma = 0.3;
  } else {
    o.wall_axis = 2;
    o.wall_rule = 2;
    o.accel[2] = -0.01;
  }
  return o;
}

static void part_names(const char *tag, int n, char names[][96], const char *ptr[]) {
  for (int b = 0; b < n; ++b) {
    snprintf(names[b], 96, "%s/%s.part-%d", g_dir, tag, b);
    ptr[b] = names[b];
  }
}

/* the end state: the report (digests, ledger) and an observation */
typedef struct {
  srd_bricks_rank_out r;
  gran_srd_obs ob;
} end_state;

static void end_of(srd_bricks_state *st, end_state *e) {
  GRAN_ASSERT_OK(srd_bricks_report_(st, &e->r));
  GRAN_ASSERT_OK(srd_bricks_observe_(st, &e->ob));
}

static void assert_same_end(const end_state *a, const end_state *b, const char *what) {
  if (a->r.digest_particles != b->r.digest_particles) fail_msg("%s: the particles differ", what);
  if (a->r.digest_cells != b->r.digest_cells) fail_msg("%s: the cells (V, RNG states) differ", what);
  assert_int_equal(a->r.n, b->r.n);
  assert_int_equal(a->r.step, b->r.step);
  assert_int_equal(a->r.clamped, b->r.clamped);
  const double la[10] = {a->r.time,     a->r.e_initial, a->r.e_coll,          a->r.e_ext,           a->r.flux_kin,
                         a->r.flux_coll, a->r.dt_max,   a->r.wall_impulse[0], a->r.wall_impulse[1], a->r.wall_impulse[2]};
  const double lb[10] = {b->r.time,     b->r.e_initial, b->r.e_coll,          b->r.e_ext,           b->r.flux_kin,
                         b->r.flux_coll, b->r.dt_max,   b->r.wall_impulse[0], b->r.wall_impulse[1], b->r.wall_impulse[2]};
  for (int q = 0; q < 10; ++q)
    if (memcmp(&la[q], &lb[q], sizeof(double)) != 0) fail_msg("%s: ledger term %d: %.17g vs %.17g", what, q, la[q], lb[q]);
  const double oa[8] = {a->ob.temperature, a->ob.theta_cells, a->ob.e_kin, a->ob.sigma_rho,
                        a->ob.a2,          a->ob.stress_xy,   a->ob.mach,  (double)a->ob.clamped};
  const double ob[8] = {b->ob.temperature, b->ob.theta_cells, b->ob.e_kin, b->ob.sigma_rho,
                        b->ob.a2,          b->ob.stress_xy,   b->ob.mach,  (double)b->ob.clamped};
  for (int q = 0; q < 8; ++q)
    if (memcmp(&oa[q], &ob[q], sizeof(double)) != 0 && !(isnan(oa[q]) && isnan(ob[q])))
      fail_msg("%s: observable %d: %.17g vs %.17g", what, q, oa[q], ob[q]);
}

static int nb_of(const int pg[3]) { return pg[0] * pg[1] * pg[2]; }

static void check_effects(int which) {
  const gran_srd_options o = opts(which);
  const int d3 = o.dim == 3;
  const int save_pg[3] = {2, 2, d3 ? 2 : 1}; /* 8 or 4 bricks */
  const int load_pg[2][3] = {{3, 1, 1}, {1, 3, d3 ? 2 : 1}};
  const int ns = nb_of(save_pg);
  char names[MAXP][96];
  const char *paths[MAXP];
  char tag[16];
  snprintf(tag, sizeof tag, "e%d", which);
  part_names(tag, ns, names, paths);
  /* the run that writes the set, and its end */
  srd_bricks_state *st = NULL;
  end_state ref, got;
  GRAN_ASSERT_OK(srd_bricks_open_(&o, save_pg, NULL, &st));
  GRAN_ASSERT_OK(srd_bricks_step_(st, SAVE_AT));
  assert_int_equal(srd_bricks_held_(st), ns);
  GRAN_ASSERT_OK(srd_bricks_save_(st, paths, 1));
  GRAN_ASSERT_OK(srd_bricks_step_(st, MORE));
  end_of(st, &ref);
  srd_bricks_close_(&st);
  assert_int_equal(ref.r.step, SAVE_AT + MORE);
  /* the parts into other splits */
  for (int g = 0; g < 2; ++g) {
    GRAN_ASSERT_OK(srd_bricks_load_(&o, load_pg[g], NULL, paths, ns, 0, 1, SAVE_AT, &st, NULL));
    GRAN_ASSERT_OK(srd_bricks_step_(st, MORE));
    end_of(st, &got);
    srd_bricks_close_(&st);
    assert_same_end(&ref, &got, g == 0 ? "the set loaded into 3 x 1 x 1" : "the set loaded into 1 x 3 x (2)");
  }
  /* in another order */
  {
    const char *rev[MAXP];
    for (int b = 0; b < ns; ++b) rev[b] = paths[ns - 1 - b];
    GRAN_ASSERT_OK(srd_bricks_load_(&o, save_pg, NULL, rev, ns, 0, 1, SAVE_AT, &st, NULL));
    GRAN_ASSERT_OK(srd_bricks_step_(st, MORE));
    end_of(st, &got);
    srd_bricks_close_(&st);
    assert_same_end(&ref, &got, "the set's parts in reverse order");
  }
  /* merged into the whole engine, stepped there, split again for the report */
  {
    gran_srd *s = NULL;
    GRAN_ASSERT_OK(srd_state_from_parts_(&o, paths, ns, 1, SAVE_AT, &s));
    GRAN_ASSERT_OK(gran_srd_advance(s, MORE));
    const int one[3] = {1, 1, 1};
    GRAN_ASSERT_OK(srd_bricks_from_state_(s, one, NULL, &st));
    GRAN_ASSERT_OK(gran_srd_destroy(&s));
    end_of(st, &got);
    srd_bricks_close_(&st);
    assert_same_end(&ref, &got, "the set merged into the whole engine");
  }
  /* the whole engine's state at the save step split */
  {
    gran_srd *s = NULL;
    GRAN_ASSERT_OK(gran_srd_create(&o, &s));
    GRAN_ASSERT_OK(gran_srd_advance(s, SAVE_AT));
    GRAN_ASSERT_OK(srd_bricks_from_state_(s, load_pg[1], NULL, &st));
    GRAN_ASSERT_OK(gran_srd_destroy(&s));
    GRAN_ASSERT_OK(srd_bricks_step_(st, MORE));
    end_of(st, &got);
    srd_bricks_close_(&st);
    assert_same_end(&ref, &got, "the whole engine at the save step, split");
  }
  /* physics that can fail: the particle count and the ledger */
  const double E = ref.r.energy, err = (ref.r.e_initial + ref.r.e_coll + ref.r.e_ext - E) / ref.r.e_initial;
  if (!(fabs(err) < 1e-12)) fail_msg("effect set %d: ledger E - E0 - e_coll - e_ext = %.3g relative", which, err);
  for (int b = 0; b < ns; ++b) unlink(paths[b]);
}

static void test_periodic_eps(void **state) { (void)state; check_effects(0); }
static void test_lees_edwards(void **state) { (void)state; check_effects(1); }
static void test_walls2(void **state) { (void)state; check_effects(2); }
static void test_walls3(void **state) { (void)state; check_effects(3); }

static void expect_refusal(int rc, const char *text) {
  assert_int_equal(rc, GRAN_ERR_IO);
  if (!strstr(gran_last_error_message(), text)) fail_msg("the refusal says '%s', not '%s'", gran_last_error_message(), text);
}

static void test_refusals(void **state) {
  (void)state;
  gran_srd_options o = opts(1);
  const int pg[3] = {2, 2, 1}, other[3] = {3, 1, 1};
  char names[4][96], onames[4][96];
  const char *paths[4], *opaths[4];
  part_names("bad", 4, names, paths);
  part_names("oth", 4, onames, opaths);
  srd_bricks_state *st = NULL;
  GRAN_ASSERT_OK(srd_bricks_open_(&o, pg, NULL, &st));
  GRAN_ASSERT_OK(srd_bricks_step_(st, 4));
  GRAN_ASSERT_OK(srd_bricks_save_(st, paths, 2));
  srd_bricks_close_(&st);
  gran_srd *s = NULL;
  /* a part missing from the set */
  gran_clear_error();
  expect_refusal(srd_bricks_load_(&o, other, NULL, paths, 3, 0, 2, 4, &st, NULL), "3 parts were given");
  assert_null(st);
  expect_refusal(srd_state_from_parts_(&o, paths, 3, 2, 4, &s), "3 parts were given");
  assert_null(s);
  /* a part given twice */
  const char *twice[4] = {paths[0], paths[1], paths[2], paths[1]};
  expect_refusal(srd_bricks_load_(&o, other, NULL, twice, 4, 0, 2, 4, &st, NULL), "as an earlier part does");
  /* another generation, another step */
  expect_refusal(srd_bricks_load_(&o, other, NULL, paths, 4, 0, 3, 4, &st, NULL),
                 "is of generation 2 at step 4, and the checkpoint commits generation 3 at step 4");
  expect_refusal(srd_state_from_parts_(&o, paths, 4, 2, 5, &s), "commits generation 2 at step 5");
  /* another seed: the option named */
  gran_srd_options o2 = o;
  o2.seed = 819;
  expect_refusal(srd_bricks_load_(&o2, other, NULL, paths, 4, 0, 2, 4, &st, NULL), "option 'seed' differs");
  /* a part of another run's set at the same step (its stress window reset at step 2): its scalar
   * state differs */
  GRAN_ASSERT_OK(srd_bricks_open_(&o, pg, NULL, &st));
  GRAN_ASSERT_OK(srd_bricks_step_(st, 2));
  GRAN_ASSERT_OK(srd_bricks_stress_reset_(st));
  GRAN_ASSERT_OK(srd_bricks_step_(st, 2));
  GRAN_ASSERT_OK(srd_bricks_save_(st, opaths, 2));
  srd_bricks_close_(&st);
  const char *mixed[4] = {paths[0], paths[1], paths[2], opaths[3]};
  expect_refusal(srd_bricks_load_(&o, other, NULL, mixed, 4, 0, 2, 4, &st, NULL), "its scalar state (time, ledger, streams) differs");
  expect_refusal(srd_state_from_parts_(&o, mixed, 4, 2, 4, &s), "its scalar state (time, ledger, streams) differs");
  /* a missing file */
  unlink(paths[2]);
  expect_refusal(srd_bricks_load_(&o, other, NULL, paths, 4, 0, 2, 4, &st, NULL), paths[2]);
  /* one process's own part: of another split than its own (all bricks here: refused too) */
  expect_refusal(srd_bricks_load_(&o, other, NULL, paths, 1, 1, 2, 4, &st, NULL), "and this process runs brick");
  assert_null(st);
  for (int b = 0; b < 4; ++b) unlink(paths[b]), unlink(opaths[b]);
}

int main(void) {
  snprintf(g_dir, sizeof g_dir, "/tmp/granary-t818-XXXXXX");
  if (!mkdtemp(g_dir)) return 1;
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_periodic_eps), cmocka_unit_test(test_lees_edwards), cmocka_unit_test(test_walls2),
      cmocka_unit_test(test_walls3),       cmocka_unit_test(test_refusals),
  };
  const int rc = cmocka_run_group_tests(tests, NULL, NULL);
  rmdir(g_dir);
  return rc;
}
