/* t001-errors.c - error codes, messages, version: the contract every module relies on. */
#include "granary_test.h"

static void test_version(void **state) {
  (void)state;
  int a = -1, b = -1, c = -1;
  GRAN_ASSERT_OK(gran_get_version(&a, &b, &c));
  assert_int_equal(a, GRAN_VERSION_MAJOR);
  assert_int_equal(b, GRAN_VERSION_MINOR);
  assert_int_equal(c, GRAN_VERSION_PATCH);
  const char *cfg = NULL;
  GRAN_ASSERT_OK(gran_get_build_config(&cfg));
  assert_non_null(cfg);
  assert_non_null(strstr(cfg, "cuda="));
}

static void test_strerror_names_every_code(void **state) {
  (void)state;
#define CHECK_NAME(name, value, msg) assert_non_null(strstr(gran_strerror(value), #name));
  GRAN_ERROR_LIST(CHECK_NAME)
#undef CHECK_NAME
  assert_non_null(strstr(gran_strerror(12345), "unknown"));
}

static void test_null_argument_named(void **state) {
  (void)state;
  GRAN_ASSERT_ERR(gran_get_version(NULL, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "major"));
  /* the message speaks of the argument; the library's function and source line are kept apart */
  assert_null(strstr(gran_last_error_message(), ".cpp"));
  char where[256];
  GRAN_ASSERT_OK(gran_last_error_location_copy(where, (int64_t)sizeof where));
  assert_non_null(strstr(where, "errors.cpp:"));
  assert_non_null(strstr(where, "GRAN_ERR_ARG"));
  char buf[8];
  GRAN_ASSERT_OK(gran_last_error_copy(buf, (int64_t)sizeof buf));
  assert_int_equal(strlen(buf), sizeof buf - 1); /* truncated, terminated */
  GRAN_ASSERT_OK(gran_clear_error());
  assert_string_equal(gran_last_error_message(), "");
  GRAN_ASSERT_OK(gran_last_error_location_copy(where, (int64_t)sizeof where));
  assert_string_equal(where, "");
  GRAN_ASSERT_ERR(gran_last_error_copy(NULL, 10), GRAN_ERR_ARG);
}

static void test_cuda_query(void **state) {
  (void)state;
  int compiled = -1, n = -1;
  GRAN_ASSERT_OK(gran_cuda_compiled(&compiled));
  assert_true(compiled == 0 || compiled == 1);
  GRAN_ASSERT_OK(gran_cuda_device_count(&n));
  assert_true(n >= 0);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_version),
      cmocka_unit_test(test_strerror_names_every_code),
      cmocka_unit_test(test_null_argument_named),
      cmocka_unit_test(test_cuda_query),
  };
  return cmocka_run_group_tests_name("t001-errors", tests, NULL, NULL);
}
