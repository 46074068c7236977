/* t521-dsmc-cell-checkpoint.c - the cell selector resumes bit for bit: a run to t2 in one go and a
 * run to t1, written, read back into a new engine and continued to t2 end with identical
 * velocities, positions, displacements, counters, ledger, collision counts and trajectories
 * (memcmp). Constant, matrix and viscoelastic restitution, with and without observables and the
 * thermostat, several cells, a t1 between two steps. A damaged cell state (a position outside the
 * box, a carried fraction outside [0, 1), a speed bound below a particle's speed; the file
 * checksum recomputed, as after a deliberate edit) is refused with GRAN_ERR_IO naming it. */
#define _POSIX_C_SOURCE 200809L
#include "io_test_util.h" /* first: it sets the feature-test macros */
#include <unistd.h>

#include <hdf5.h>
#include <zlib.h>

#include "dsmc_util.h"

#include <string.h>

static char g_path[256];

static int setup(void **state) {
  (void)state;
  dsmc_ckpt_path(g_path, sizeof g_path, "t521");
  return 0;
}
static int teardown(void **state) {
  (void)state;
  remove(g_path);
  return 0;
}

/* four species (4 x 4 collision counts), the cell selector: positions, ledger and cells too */
static void compare(const gran_dsmc *a, const gran_dsmc *b, int observe) { dsmc_assert_same_state(a, b, observe, 4, 1); }

static gran_mixture *four_species(int model) {
  gran_mixture *mix;
  double n[4] = {0.01, 0.003, 0.0004, 0.0001};
  GRAN_ASSERT_OK(gran_mixture_create(4, NULL, NULL, n, &mix));
  if (model == 0) GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.7));
  if (model == 1) {
    double e[16];
    for (int i = 0; i < 16; i++) e[i] = 0.5 + 0.02 * (i / 4 + i % 4);
    GRAN_ASSERT_OK(gran_mixture_set_restitution_matrix(mix, e));
  }
  if (model == 2) GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.05));
  return mix;
}

static void test_resume_bit_for_bit(void **state) {
  (void)state;
  const int observes[3] = {0, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS,
                           GRAN_OBSERVE_TRAJECTORIES | GRAN_OBSERVE_COLLISION_COUNTS};
  for (int model = 0; model < 3; model++) {
    gran_mixture *mix = four_species(model);
    for (int q = 0; q < 3; q++)
      for (int heat = 0; heat < 2; heat++) {
        gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 31 + (uint64_t)q, 3e5, observes[q]);
        o.traj_per_species = 2;
        o.traj_dt = 0.7;
        o.traj_samples = 60;
        gran_dsmc_cell_options c;
        GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
        c.cells = 3;
        c.dt = 0.4;
        c.heat_rate = heat ? 0.01 : 0.0;
        gran_dsmc *a, *b, *r;
        GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &a));
        GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &b));
        GRAN_ASSERT_OK(gran_dsmc_advance(a, 30.0));
        GRAN_ASSERT_OK(gran_dsmc_advance(b, 13.3)); /* between two steps */
        GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, g_path, "/engine"));
        GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &r));
        compare(b, r, observes[q]);
        GRAN_ASSERT_OK(gran_dsmc_advance(r, 30.0));
        compare(a, r, observes[q]);
        assert_true(dsmc_collisions(a) > 1000);
        GRAN_ASSERT_OK(gran_dsmc_advance_collisions(a, 2000));
        GRAN_ASSERT_OK(gran_dsmc_advance_collisions(r, 2000));
        compare(a, r, observes[q]);
        gran_dsmc_destroy(&a);
        gran_dsmc_destroy(&b);
        gran_dsmc_destroy(&r);
      }
    gran_mixture_destroy(&mix);
  }
}

/* aggregation and fragmentation: particles appear and vanish, sizes grow beyond the mixture's */
static void test_resume_agg(void **state) {
  (void)state;
  double n[20] = {0.01};
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_mixture_create(20, NULL, NULL, n, &mix));
  GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.8));
  for (int place = 0; place < 2; place++) {
    gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 8 + (uint64_t)place, 3e5, 0);
    gran_dsmc_cell_options c;
    GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
    c.cells = 2;
    c.dt = 0.5;
    c.e_agg = 1.5;
    c.e_frag = 2.5;
    c.eps_f = 0.6;
    c.heat_rate = place ? 0.002 : 0.0;
    c.bath_density = place ? 0.0 : 0.004; /* the molecular-gas bath */
    c.bath_T = 1.5;
    c.placement = place ? GRAN_PLACE_COLLISION : GRAN_PLACE_RANDOM;
    gran_dsmc *a, *b, *r;
    GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &a));
    GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &b));
    GRAN_ASSERT_OK(gran_dsmc_advance(a, 80.0));
    GRAN_ASSERT_OK(gran_dsmc_advance(b, 31.2));
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, g_path, "/engine"));
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &r));
    compare(b, r, 0);
    GRAN_ASSERT_OK(gran_dsmc_advance(r, 80.0));
    compare(a, r, 0);
    gran_dsmc_cluster_stats sa, sr;
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(a, &sa));
    GRAN_ASSERT_OK(gran_dsmc_get_cluster_stats(r, &sr));
    assert_memory_equal(&sa, &sr, sizeof sa);
    assert_true(sa.merges > 100 && sa.breakups > 100);
    const gran_particles *pa, *pr;
    GRAN_ASSERT_OK(gran_dsmc_particles(a, &pa));
    GRAN_ASSERT_OK(gran_dsmc_particles(r, &pr));
    assert_memory_equal(pa->species, pr->species, sizeof(int32_t) * (size_t)pa->n);
    gran_dsmc_destroy(&a);
    gran_dsmc_destroy(&b);
    gran_dsmc_destroy(&r);
  }
  gran_mixture_destroy(&mix);
}


/* after an edit through HDF5: recompute granary's file checksum (as t606 does) */

static void edit(const char *dataset, int64_t index, double value) {
  hid_t f = H5Fopen(g_path, H5F_ACC_RDWR, H5P_DEFAULT);
  assert_true(f >= 0);
  hid_t d = H5Dopen2(f, dataset, H5P_DEFAULT);
  assert_true(d >= 0);
  hid_t sp = H5Dget_space(d);
  hsize_t np = (hsize_t)H5Sget_simple_extent_npoints(sp);
  double *v = malloc(np * sizeof *v);
  H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
  v[index] = value;
  H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v);
  free(v);
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  io_refresh_crc(g_path);
}

static void test_damaged(void **state) {
  (void)state;
  gran_mixture *mix = four_species(0);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_CELL, 5, 3e5, 0);
  gran_dsmc_cell_options c;
  GRAN_ASSERT_OK(gran_dsmc_cell_options_default(&c));
  c.cells = 2;
  c.dt = 0.5;
  gran_dsmc *a, *b = NULL;
  GRAN_ASSERT_OK(gran_dsmc_create_cell(mix, NULL, NULL, &o, &c, &a));
  GRAN_ASSERT_OK(gran_dsmc_advance(a, 5));
  const struct {
    const char *ds;
    int64_t i;
    double v;
    const char *why;
  } cases[] = {
      {"/engine/cell_x", 5, -1.0, "positions"},
      {"/engine/cell_x", 7, 1e9, "positions"},
      {"/engine/cell_rem", 3, 1.5, "carried candidate fractions"},
      {"/engine/cell_scalars", 0, 1e-6, "cell speed bound"},
      {"/engine/cell_options_real", 0, -1.0, "'dt'"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(a, g_path, "/engine"));
    edit(cases[k].ds, cases[k].i, cases[k].v);
    GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &b), k == 4 ? GRAN_ERR_ARG : GRAN_ERR_IO);
    if (!strstr(gran_last_error_message(), cases[k].why))
      fail_msg("edit of %s: message '%s' (expected '%s')", cases[k].ds, gran_last_error_message(), cases[k].why);
    assert_null(b);
  }
  gran_dsmc_destroy(&a);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_resume_bit_for_bit, setup, teardown),
      cmocka_unit_test_setup_teardown(test_damaged, setup, teardown),
      cmocka_unit_test_setup_teardown(test_resume_agg, setup, teardown),
  };
  return cmocka_run_group_tests_name("t521-dsmc-cell-checkpoint", tests, NULL, NULL);
}
