/* t901-layout.c - gran_abi_query against what a C compiler sees in granary.h (the library is C++):
 * every struct size, every field offset and every enum constant, unknown names and NULL arguments.
 * The list of names is src/core/abi_table.inc (generated from the header by bindings/gen_raw.py);
 * the Fortran side is t901-layout-f.f90. */
#include <stddef.h>

#include "granary_test.h"

static void check_abi(const char *name, int64_t expected) {
  int64_t v = INT64_MIN;
  GRAN_ASSERT_OK(gran_abi_query(name, &v));
  if (v != expected) fail_msg("%s: library says " GRAN_I64_FMT ", C compiler " GRAN_I64_FMT, name, v, expected);
}

#define EXPECT_SIZE(type) check_abi("sizeof(" #type ")", (int64_t)sizeof(type))
#define EXPECT_CONST(name) check_abi(#name, (int64_t)(name))

static void test_struct_sizes(void **state) {
  (void)state;
  EXPECT_SIZE(gran_rng);
  EXPECT_SIZE(gran_segtree);
  EXPECT_SIZE(gran_particles);
  EXPECT_SIZE(gran_dsmc_options);
  EXPECT_SIZE(gran_dsmc_stats);
  EXPECT_SIZE(gran_run_progress);
  EXPECT_SIZE(gran_run_control);
  EXPECT_SIZE(gran_run_result);
  EXPECT_SIZE(gran_srd_options); /* GSRD */
  EXPECT_SIZE(gran_srd_obs);     /* GSRD */
  EXPECT_SIZE(gran_dsmc_cell_options); /* cell selector */
  assert_int_equal(sizeof(gran_dsmc_cell_options), 104);
  EXPECT_SIZE(gran_dsmc_cluster_stats);
  assert_int_equal(sizeof(gran_dsmc_cluster_stats), 96);
  EXPECT_SIZE(gran_dsmc_agg_options); /* aggregation in the event selectors */
  assert_int_equal(sizeof(gran_dsmc_agg_options), 32);
  /* the plain structs have the documented sizes (Fortran mirrors rely on them) */
  assert_int_equal(sizeof(gran_rng), 32);
  assert_int_equal(sizeof(gran_segtree), 32);
  assert_int_equal(sizeof(gran_particles), 72);
}

/* every name of the generated table, as a C compiler sees the header */
static void test_generated_table(void **state) {
  (void)state;
  int64_t n = 0;
#define GRAN_ABI_SIZE(type) (check_abi("sizeof(" #type ")", (int64_t)sizeof(type)), n++);
#define GRAN_ABI_OFFSET(type, field) (check_abi("offsetof(" #type ", " #field ")", (int64_t)offsetof(type, field)), n++);
#define GRAN_ABI_CONST(name) (check_abi(#name, (int64_t)(name)), n++);
#include "core/abi_table.inc"
#undef GRAN_ABI_SIZE
#undef GRAN_ABI_OFFSET
#undef GRAN_ABI_CONST
  assert_true(n > 150); /* the table is the whole header, not a part of it */
  /* spot checks of the offsets against the layout documented in the header */
  check_abi("offsetof(gran_rng, s)", 0);
  check_abi("offsetof(gran_particles, v)", 24);
  check_abi("offsetof(gran_dsmc_options, seed)", 8);
  check_abi("offsetof(gran_srd_options, cells)", 16);
  check_abi("offsetof(gran_run_control, progress)", 8);
}

static void test_constants(void **state) {
  (void)state;
#define EXPECT_ERROR(name, value, msg) EXPECT_CONST(name);
  GRAN_ERROR_LIST(EXPECT_ERROR)
#undef EXPECT_ERROR
  EXPECT_CONST(GRAN_VERSION_MAJOR);
  EXPECT_CONST(GRAN_VERSION_MINOR);
  EXPECT_CONST(GRAN_VERSION_PATCH);
  EXPECT_CONST(GRAN_PARTICLES_DISPLACEMENT);
  EXPECT_CONST(GRAN_PARTICLES_POSITION);
  EXPECT_CONST(GRAN_PARTICLES_MASS);
  EXPECT_CONST(GRAN_RESTITUTION_CONSTANT);
  EXPECT_CONST(GRAN_RESTITUTION_MATRIX);
  EXPECT_CONST(GRAN_RESTITUTION_VISCOELASTIC);
  EXPECT_CONST(GRAN_HCS_NORM_MEAN);
  EXPECT_CONST(GRAN_HCS_NORM_T1);
  EXPECT_CONST(GRAN_SELECTOR_LOWRANK);
  EXPECT_CONST(GRAN_SELECTOR_BIRD);
  EXPECT_CONST(GRAN_SELECTOR_LOWRANK_PAPER);
  EXPECT_CONST(GRAN_SELECTOR_BIRD_PAPER);
  EXPECT_CONST(GRAN_OBSERVE_DISPLACEMENT);
  EXPECT_CONST(GRAN_OBSERVE_COLLISION_COUNTS);
  EXPECT_CONST(GRAN_OBSERVE_TRAJECTORIES);
  /* GSRD devices (CUDA backend) */
  EXPECT_CONST(GRAN_SRD_DEVICE_CPU);
  EXPECT_CONST(GRAN_SRD_DEVICE_CUDA);
  EXPECT_CONST(GRAN_SRD_DEVICE_AUTO);
  EXPECT_CONST(GRAN_SRD_DEVICE_REFERENCE);
  EXPECT_CONST(GRAN_SELECTOR_CELL); /* cell selector */
  EXPECT_CONST(GRAN_PLACE_RANDOM);
  EXPECT_CONST(GRAN_PLACE_COLLISION);
  EXPECT_CONST(GRAN_FRAG_MONOMERS); /* aggregation: fragment laws */
  EXPECT_CONST(GRAN_FRAG_BINARY);
  EXPECT_CONST(GRAN_SPEED_CLASSES_OFF); /* speed classes */
  EXPECT_CONST(GRAN_SPEED_CLASSES_ON);
  EXPECT_CONST(GRAN_SPEED_CLASSES_AUTO);
}

static void test_errors(void **state) {
  (void)state;
  int64_t v = 7;
  GRAN_ASSERT_ERR(gran_abi_query("GRAN_ERR_NOTHING", &v), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "GRAN_ERR_NOTHING"));
  assert_int_equal(v, 7); /* untouched */
  GRAN_ASSERT_ERR(gran_abi_query("gran_rng", &v), GRAN_ERR_ARG); /* exact spelling only */
  GRAN_ASSERT_ERR(gran_abi_query("offsetof(gran_rng,s)", &v), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_abi_query("offsetof(gran_rng, nothing)", &v), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "offsetof(gran_rng, nothing)"));
  GRAN_ASSERT_ERR(gran_abi_query(NULL, &v), GRAN_ERR_ARG);
  GRAN_ASSERT_ERR(gran_abi_query("GRAN_ERR_ARG", NULL), GRAN_ERR_ARG);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_struct_sizes),
      cmocka_unit_test(test_generated_table),
      cmocka_unit_test(test_constants),
      cmocka_unit_test(test_errors),
  };
  return cmocka_run_group_tests_name("t901-layout", tests, NULL, NULL);
}
