/* t604-checkpoint.c - checkpoints and resume: a run split by restarts writes an output whose
 * datasets equal those of the uninterrupted run bit for bit (both selectors, one and two
 * restarts); checkpoint files are replaced atomically; bad checkpoints are refused. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

static void split_run_equals_straight_run(const char *selector) {
  char name[64];
  snprintf(name, sizeof name, "straight-%s.h5", selector);
  const char *straight = io_path(name);
  snprintf(name, sizeof name, "split-%s.h5", selector);
  const char *split = io_path(name);
  snprintf(name, sizeof name, "split-%s.ckpt", selector);
  const char *ck = io_path(name);
  char straight_s[600], split_s[600], ck_s[600];
  snprintf(straight_s, sizeof straight_s, "%s", straight);
  snprintf(split_s, sizeof split_s, "%s", split);
  snprintf(ck_s, sizeof ck_s, "%s", ck);

  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text(selector, split_s), "tiny.toml", &s));
  gran_run_result res;
  /* uninterrupted, no checkpoints at all */
  GRAN_ASSERT_OK(gran_scene_run(s, straight_s, "", NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_int_equal(res.checkpoints, 0);
  const int64_t total_collisions = res.collisions;

  /* stop after the first checkpoint (checkpoint_every = 2: after output time 2) */
  gran_run_control ctl = {1, NULL, NULL};
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, ck_s, &ctl, &res));
  assert_int_equal(res.finished, 0);
  assert_int_equal(res.checkpoints, 1);
  assert_true(res.collisions > 0 && res.collisions < total_collisions);
  assert_true(io_exists(ck_s));
  assert_false(io_exists(split_s)); /* no output yet */
  char tmp[700];
  snprintf(tmp, sizeof tmp, "%s.tmp", ck_s);
  assert_false(io_exists(tmp));
  /* the checkpoint holds the scene and the observer state */
  hid_t f = H5Fopen(ck_s, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  char *a = io_h5_attr_string(f, "format");
  assert_string_equal(a, "granary-checkpoint 1");
  free(a);
  a = io_h5_attr_string(f, "scene");
  assert_string_equal(a, io_tiny_text(selector, split_s));
  free(a);
  a = io_h5_attr_string(f, "output");
  assert_string_equal(a, split_s);
  free(a);
  int64_t next = -1;
  hid_t at = H5Aopen(f, "next_index", H5P_DEFAULT);
  H5Aread(at, H5T_NATIVE_INT64, &next);
  H5Aclose(at);
  assert_int_equal(next, 2);
  assert_true(H5Lexists(f, "engine", H5P_DEFAULT) > 0);
  assert_true(H5Lexists(f, "observer", H5P_DEFAULT) > 0);
  H5Fclose(f);

  /* resume, stop again after one more checkpoint (a checkpoint written by a resumed run) */
  int64_t c1 = res.collisions;
  GRAN_ASSERT_OK(gran_scene_resume(ck_s, NULL, &ctl, &res));
  assert_int_equal(res.finished, 0);
  assert_true(res.collisions > c1);
  /* resume to the end */
  GRAN_ASSERT_OK(gran_scene_resume(ck_s, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_int_equal(res.collisions, total_collisions);
  assert_true(io_exists(split_s));
  assert_false(io_exists(ck_s)); /* removed after success */

  int nds = 0;
  char first[512] = "";
  int ndiff = io_h5_compare(straight_s, split_s, &nds, first, sizeof first);
  if (ndiff != 0) fail_msg("%s: %d of %d datasets differ after resume (first: %s)", selector, ndiff, nds, first);
  assert_true(nds >= 25);
  ndiff = io_h5_compare(split_s, straight_s, &nds, first, sizeof first); /* and no extra ones */
  assert_int_equal(ndiff, 0);
  gran_scene_destroy(&s);
}

static void test_resume_bit_exact_lowrank(void **state) {
  (void)state;
  split_run_equals_straight_run("lowrank");
}

static void test_resume_bit_exact_bird(void **state) {
  (void)state;
  split_run_equals_straight_run("bird");
}

static void test_keep_and_override(void **state) {
  (void)state;
  const char *out = io_path("keep.h5");
  char text[8192];
  strcpy(text, io_tiny_text("lowrank", out));
  strcat(text, "keep_checkpoint = true\n");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "keep.toml", &s));
  const char *ck = io_path("keep.ckpt");
  gran_run_control ctl = {2, NULL, NULL};
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  assert_int_equal(res.checkpoints, 2);
  /* resume into another output file */
  const char *other = io_path("other.h5");
  GRAN_ASSERT_OK(gran_scene_resume(ck, other, NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_true(io_exists(other));
  assert_false(io_exists(out));
  assert_true(io_exists(ck)); /* keep_checkpoint = true */
  gran_scene_destroy(&s);
}

static void test_bad_checkpoints(void **state) {
  (void)state;
  GRAN_ASSERT_ERR(gran_scene_resume(io_path("missing.ckpt"), NULL, NULL, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "missing.ckpt"));
  const char *txt = io_path("text.ckpt");
  io_write_file(txt, "this is not HDF5\n");
  GRAN_ASSERT_ERR(gran_scene_resume(txt, NULL, NULL, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "text.ckpt"));
  /* an output file is not a checkpoint */
  const char *out = io_path("plain.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, NULL));
  GRAN_ASSERT_ERR(gran_scene_resume(out, io_path("x.h5"), NULL, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "not a granary checkpoint"));
  gran_run_control neg = {-2, NULL, NULL};
  GRAN_ASSERT_ERR(gran_scene_resume(out, NULL, &neg, NULL), GRAN_ERR_ARG);
  gran_scene_destroy(&s);
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t604");
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_resume_bit_exact_lowrank),
      cmocka_unit_test(test_resume_bit_exact_bird),
      cmocka_unit_test(test_keep_and_override),
      cmocka_unit_test(test_bad_checkpoints),
  };
  return cmocka_run_group_tests_name("t604-checkpoint", tests, NULL, teardown);
}
