/* t506-dsmc-checkpoint.c - checkpoint/restart is bit for bit: run to t1, write the state, read it
 * into a new engine, advance both to t2, compare velocities, displacements, times of last
 * collision, counters, ledger, collision counts and trajectories with memcmp. Every selector, with
 * and without observables, constant and viscoelastic restitution. Bad files and mismatched
 * mixtures fail with GRAN_ERR_IO / GRAN_ERR_ARG naming the path; a damaged state (an index out of
 * range) is refused with GRAN_ERR_IO; checksum-consistent generator states no generator reaches
 * (zero, near zero) are refused naming 'rng' or 'rng_lanes'. */
#define _POSIX_C_SOURCE 200809L
#include "io_test_util.h" /* io_edit_raw: an edit through HDF5, checksum recomputed */

#include "dsmc_util.h"

static char g_path[256];

static int setup(void **state) {
  (void)state;
  dsmc_ckpt_path(g_path, sizeof g_path, "t506");
  return 0;
}
static int teardown(void **state) {
  (void)state;
  remove(g_path);
  return 0;
}

/* five species: collision counts 5 x 5 */
static void compare(const gran_dsmc *a, const gran_dsmc *b, int observe) { dsmc_assert_same_state(a, b, observe, 5, 0); }

static gran_mixture *five_species(int visco) {
  gran_mixture *mix;
  double n[5] = {0.1, 0.03, 0.0, 0.004, 0.001}; /* the third species is empty */
  GRAN_ASSERT_OK(gran_mixture_create(5, NULL, NULL, n, &mix));
  if (visco)
    GRAN_ASSERT_OK(gran_mixture_set_viscoelastic(mix, 0.05));
  else
    GRAN_ASSERT_OK(gran_mixture_set_restitution(mix, 0.6));
  return mix;
}

static void test_restart_bit_for_bit(void **state) {
  (void)state;
  const int observes[3] = {0, GRAN_OBSERVE_DISPLACEMENT | GRAN_OBSERVE_COLLISION_COUNTS,
                           GRAN_OBSERVE_TRAJECTORIES | GRAN_OBSERVE_COLLISION_COUNTS};
  for (int visco = 0; visco < 2; visco++) {
    gran_mixture *mix = five_species(visco);
    for (int sel = 0; sel < 6; sel++) /* 4, 5: the low-rank selectors with speed classes */
      for (int q = 0; q < 3; q++) {
        gran_dsmc_options o = dsmc_opts(sel < 4 ? sel : sel == 4 ? GRAN_SELECTOR_LOWRANK : GRAN_SELECTOR_LOWRANK_PAPER,
                                        77 + (uint64_t)sel, 2e4, observes[q]);
        o.speed_classes = sel >= 4;
        o.bound_refresh = 700; /* several tightenings before and after the checkpoint */
        o.traj_per_species = 2;
        o.traj_dt = 0.5;
        o.traj_samples = 40;
        gran_dsmc *a, *b;
        GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &a));
        GRAN_ASSERT_OK(gran_dsmc_advance(a, 7.3));
        GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(a, g_path, "/engine"));
        GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &b));
        compare(a, b, observes[q]);
        GRAN_ASSERT_OK(gran_dsmc_advance(a, 15.0));
        GRAN_ASSERT_OK(gran_dsmc_advance(b, 15.0));
        GRAN_ASSERT_OK(gran_dsmc_advance_collisions(a, 3333));
        GRAN_ASSERT_OK(gran_dsmc_advance_collisions(b, 3333));
        compare(a, b, observes[q]);
        assert_true(dsmc_collisions(a) > 10000);
        /* rewrite into the same file and group (replaced), read back again */
        GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(b, g_path, "/engine"));
        gran_dsmc *c;
        GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &c));
        compare(b, c, observes[q]);
        gran_dsmc_destroy(&a);
        gran_dsmc_destroy(&b);
        gran_dsmc_destroy(&c);
      }
    gran_mixture_destroy(&mix);
  }
}

static void test_checkpoint_errors(void **state) {
  (void)state;
  gran_mixture *mix = five_species(0);
  gran_dsmc_options o = dsmc_opts(GRAN_SELECTOR_LOWRANK, 1, 1e4, 0);
  gran_dsmc *a, *b = (gran_dsmc *)0x1;
  GRAN_ASSERT_OK(gran_dsmc_create(mix, NULL, NULL, &o, &a));
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_write(a, "/nonexistent-dir/x.h5", "/engine"), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "/nonexistent-dir/x.h5"));
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_write(a, g_path, "/"), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_write(a, NULL, "/engine"), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_write(NULL, g_path, "/engine"), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &b), GRAN_ERR_IO); /* no file yet */
  assert_null(b);
  assert_non_null(strstr(gran_last_error_message(), g_path));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_write(a, g_path, "/run/engine")); /* nested group */
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/elsewhere", mix, &b), GRAN_ERR_IO);
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/run/engine", NULL, &b), GRAN_ERR_ARG);
  gran_mixture *other;
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(5, 1.0, 1.0, 0.1, 2.0, &other)); /* same masses: OK */
  GRAN_ASSERT_OK(gran_mixture_set_restitution(other, 0.6));
  GRAN_ASSERT_OK(gran_dsmc_checkpoint_read(g_path, "/run/engine", other, &b));
  gran_dsmc_destroy(&b);
  gran_mixture_destroy(&other);
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(4, 1.0, 1.0, 0.1, 3.0, &other));
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/run/engine", other, &b), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "species"));
  gran_mixture_destroy(&other);
  GRAN_ASSERT_OK(gran_mixture_create_powerlaw(5, 2.0, 1.0, 0.1, 3.0, &other));
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/run/engine", other, &b), GRAN_ERR_ARG);
  gran_mixture_destroy(&other);
  /* generator states a generator never reaches, checksum recomputed: refused naming the field */
  {
    char bad[300];
    snprintf(bad, sizeof bad, "%s.bad", g_path);
    const uint64_t zero[4] = {0, 0, 0, 0}, few[4] = {0xff, 0, 0x3, 0};
    io_edit_raw(g_path, bad, "/run/engine/rng", 0, zero, 4, H5T_NATIVE_UINT64);
    GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(bad, "/run/engine", mix, &b), GRAN_ERR_IO);
    assert_non_null(strstr(gran_last_error_message(), "rng"));
    io_edit_raw(g_path, bad, "/run/engine/rng", 0, few, 4, H5T_NATIVE_UINT64);
    GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(bad, "/run/engine", mix, &b), GRAN_ERR_IO);
    assert_non_null(strstr(gran_last_error_message(), "(rng;"));
    /* lane 3 of the buffered streams: words s[w][3] at w * 8 + 3 */
    for (int w = 0; w < 4; w++) {
      const uint64_t z = 0;
      io_edit_raw(w == 0 ? g_path : bad, bad, "/run/engine/rng_lanes", w * 8 + 3, &z, 1, H5T_NATIVE_UINT64);
    }
    GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(bad, "/run/engine", mix, &b), GRAN_ERR_IO);
    assert_non_null(strstr(gran_last_error_message(), "rng_lanes"));
    assert_null(b);
    remove(bad);
  }
  /* a damaged state: an index outside its array is refused, not used (here the file checksum
   * catches the edit first; t606 recomputes the checksum and reaches the value checks) */
  {
    hid_t f = H5Fopen(g_path, H5F_ACC_RDWR, H5P_DEFAULT);
    assert_true(f >= 0);
    hid_t ds = H5Dopen2(f, "/run/engine/rng_pos", H5P_DEFAULT);
    assert_true(ds >= 0);
    const int64_t bad = 100000;
    assert_true(H5Dwrite(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, &bad) >= 0);
    H5Dclose(ds);
    H5Fclose(f);
    GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/run/engine", mix, &b), GRAN_ERR_IO);
    assert_non_null(strstr(gran_last_error_message(), "damaged"));
    assert_null(b);
  }
  /* a file that is not HDF5 */
  FILE *f = fopen(g_path, "w");
  assert_non_null(f);
  fputs("not hdf5\n", f);
  fclose(f);
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_write(a, g_path, "/engine"), GRAN_ERR_IO);
  GRAN_ASSERT_ERR(gran_dsmc_checkpoint_read(g_path, "/engine", mix, &b), GRAN_ERR_IO);
  gran_dsmc_destroy(&a);
  gran_mixture_destroy(&mix);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test_setup_teardown(test_restart_bit_for_bit, setup, teardown),
      cmocka_unit_test_setup_teardown(test_checkpoint_errors, setup, teardown),
  };
  return cmocka_run_group_tests_name("t506-dsmc-checkpoint", tests, NULL, NULL);
}
