/* t002-readme.c - the README's C and Fortran examples are the files bindings/examples/example.c
 * and example.f90 verbatim (the test suite compiles and runs those files), so README cannot drift
 * from code that works. */
#include "granary_test.h"

static char *slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *buf = malloc((size_t)n + 1);
  if (buf && fread(buf, 1, (size_t)n, f) != (size_t)n) {
    free(buf);
    buf = NULL;
  }
  if (buf) buf[n] = '\0';
  fclose(f);
  return buf;
}

static void check_example_in_readme(const char *name) {
  char path[4096];
  snprintf(path, sizeof path, "%s/README.md", gran_test_source_dir());
  char *readme = slurp(path);
  if (!readme) fail_msg("cannot read %s", path);
  snprintf(path, sizeof path, "%s/bindings/examples/%s", gran_test_source_dir(), name);
  char *example = slurp(path);
  if (!example) fail_msg("cannot read %s", path);
  if (!strstr(readme, example)) fail_msg("README.md does not contain %s verbatim", name);
  /* and it is short enough to be an example */
  int lines = 0;
  for (const char *c = example; *c; c++) lines += *c == '\n';
  assert_true(lines <= 30);
  free(readme);
  free(example);
}

static void test_c_example(void **state) {
  (void)state;
  check_example_in_readme("example.c");
}
static void test_fortran_example(void **state) {
  (void)state;
  check_example_in_readme("example.f90");
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_c_example),
      cmocka_unit_test(test_fortran_example),
  };
  return cmocka_run_group_tests_name("t002-readme", tests, NULL, NULL);
}
