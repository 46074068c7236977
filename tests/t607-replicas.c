/* t607-replicas.c - replicas of a run (src/io/run.cpp): R = 1 is the run without replicas bit for
 * bit; the output does not depend on the thread count; replica r gives the same rows whatever R
 * (RNG stream r of the seed); X and X_se are the mean and standard error of the per-replica rows;
 * the standard error of T_1 at the first output time matches the Maxwellian sampling noise
 * sqrt(2 / (3 N_1)) / sqrt(R) (within 3 standard errors of the estimate); a stopped run resumes
 * bit for bit with another thread count; a run that would not fit in memory is refused first. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

static gran_scene *tiny(const char *out, int64_t R, int keep) {
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  GRAN_ASSERT_OK(gran_scene_set_replicas(s, R, keep));
  return s;
}

static void run_to(gran_scene *s, const char *out, int threads) {
  GRAN_ASSERT_OK(gran_set_threads(threads));
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_set_threads(0));
}

static void same_files(const char *a, const char *b) {
  int nd = 0;
  char diff[600] = "";
  int n = io_h5_compare(a, b, &nd, diff, sizeof diff);
  if (n != 0) fail_msg("%s vs %s: %d differences; first: %s", a, b, n, diff);
  assert_true(nd > 10);
}

static int64_t attr_i64(hid_t f, const char *name) {
  int64_t v = -1;
  hid_t a = H5Aopen(f, name, H5P_DEFAULT);
  assert_true(a >= 0);
  H5Aread(a, H5T_NATIVE_INT64, &v);
  H5Aclose(a);
  return v;
}

static void test_one_replica_is_the_plain_run(void **state) {
  (void)state;
  const char *a = io_path("plain.h5"), *b = io_path("r1.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", a), "tiny.toml", &s));
  int64_t R = 0;
  int32_t keep = -1;
  GRAN_ASSERT_OK(gran_scene_replicas(s, &R, &keep));
  assert_int_equal(R, 1);
  assert_int_equal(keep, 0);
  run_to(s, a, 0);
  gran_scene_destroy(&s);
  s = tiny(b, 1, 1);
  run_to(s, b, 2);
  gran_scene_destroy(&s);
  same_files(a, b);
  same_files(b, a);
  hid_t f = H5Fopen(b, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_int_equal(attr_i64(f, "nreplicas"), 1);
  assert_false(H5Lexists(f, "temperatures/T_se", H5P_DEFAULT) > 0);
  H5Fclose(f);
  /* bad arguments are named */
  assert_int_equal(gran_scene_set_replicas(NULL, 2, 0), GRAN_ERR_ARG);
  s = tiny(b, 1, 0);
  assert_int_equal(gran_scene_set_replicas(s, 0, 0), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "replicas"));
  assert_int_equal(gran_scene_set_replicas(s, 2, 7), GRAN_ERR_ARG);
  assert_int_equal(gran_set_threads(-1), GRAN_ERR_ARG);
  gran_scene_destroy(&s);
  assert_int_equal(gran_scene_parse("[mixture]\ndensity = [0.1]\n[engine]\ncounts = [10]\nt_end = 1.0\nreplicas = 0\n"
                                    "[observables]\ntimes = [1.0]\n", "bad.toml", &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "engine.replicas"));
}

static void test_threads_and_streams(void **state) {
  (void)state;
  const char *a = io_path("r4-t1.h5"), *b = io_path("r4-t2.h5"), *c = io_path("r24.h5");
  gran_scene *s = tiny(a, 4, 1);
  run_to(s, a, 1);
  run_to(s, b, 2);
  gran_scene_destroy(&s);
  same_files(a, b); /* the thread count changes nothing, bit for bit */
  s = tiny(c, 24, 1);
  run_to(s, c, 2);
  gran_scene_destroy(&s);
  hid_t f4 = H5Fopen(a, H5F_ACC_RDONLY, H5P_DEFAULT), f24 = H5Fopen(c, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_int_equal(attr_i64(f24, "nreplicas"), 24);
  size_t n4 = 0, n24 = 0, nm = 0, ns = 0;
  double *r4 = io_h5_read_double(f4, "temperatures/T_replicas", &n4);
  double *r24 = io_h5_read_double(f24, "temperatures/T_replicas", &n24);
  double *mean = io_h5_read_double(f24, "temperatures/T", &nm), *se = io_h5_read_double(f24, "temperatures/T_se", &ns);
  const size_t row = (size_t)IO_TINY_NT * IO_TINY_M;
  assert_int_equal(n4, 4 * row);
  assert_int_equal(n24, 24 * row);
  assert_int_equal(nm, row);
  /* replicas 0..3 are the same whatever R: stream r of the seed */
  for (size_t i = 0; i < n4; i++) assert_true(r4[i] == r24[i]);
  /* replicas differ from each other */
  assert_true(r24[0] != r24[row]);
  /* X = mean, X_se = sample sd / sqrt(R) */
  for (size_t i = 0; i < row; i++) {
    double m = 0, v = 0;
    for (int k = 0; k < 24; k++) m += r24[k * row + i];
    m /= 24;
    for (int k = 0; k < 24; k++) v += (r24[k * row + i] - m) * (r24[k * row + i] - m);
    assert_true(fabs(mean[i] - m) <= 1e-14 * fabs(m));
    assert_true(fabs(se[i] - sqrt(v / 23 / 24)) <= 1e-12 * se[i]);
  }
  /* T_1 at the first output time: the Maxwellian start's sampling noise, relative sd sqrt(2/(3 N_1))
   * (N_1 = 2000; ~100 collisions by t = 0.1 change it little); the estimate of se from 24 replicas
   * has a relative standard error 1/sqrt(2*23) = 0.15: allow 3 of those */
  const double want = sqrt(2.0 / (3.0 * 2000.0)) / sqrt(24.0);
  const double got = se[0] / mean[0];
  if (fabs(got / want - 1.0) > 0.45) fail_msg("se(T_1)/T_1 = %g, expected %g", got, want);
  /* event counts are summed over the replicas */
  size_t nc = 0;
  hsize_t d[4];
  assert_int_equal(io_h5_dims(f24, "stats/collisions", d), 1);
  int64_t *coll = calloc(d[0], sizeof *coll), *collr = calloc(24 * d[0], sizeof *collr);
  hid_t ds = H5Dopen2(f24, "stats/collisions", H5P_DEFAULT);
  H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, coll);
  H5Dclose(ds);
  ds = H5Dopen2(f24, "stats/collisions_replicas", H5P_DEFAULT);
  H5Dread(ds, H5T_NATIVE_INT64, H5S_ALL, H5S_ALL, H5P_DEFAULT, collr);
  H5Dclose(ds);
  int64_t sum = 0;
  for (int k = 0; k < 24; k++) sum += collr[(size_t)k * d[0] + d[0] - 1];
  assert_true(sum == coll[d[0] - 1]);
  (void)nc;
  free(coll);
  free(collr);
  free(r4);
  free(r24);
  free(mean);
  free(se);
  H5Fclose(f4);
  H5Fclose(f24);
}

static void test_resume_with_replicas(void **state) {
  (void)state;
  const char *straight = io_path("rs-straight.h5"), *split = io_path("rs-split.h5"), *ck = io_path("rs.ckpt");
  gran_scene *s = tiny(straight, 3, 1);
  run_to(s, straight, 1);
  gran_run_control ctl = {0};
  ctl.stop_after_checkpoints = 1;
  gran_run_result res;
  GRAN_ASSERT_OK(gran_set_threads(1));
  GRAN_ASSERT_OK(gran_scene_run(s, split, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  GRAN_ASSERT_OK(gran_set_threads(3));
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  GRAN_ASSERT_OK(gran_set_threads(0));
  assert_int_equal(res.finished, 1);
  same_files(straight, split);
  same_files(split, straight);
  gran_scene_destroy(&s);
}

static void test_memory_refused_first(void **state) {
  (void)state;
  const char *out = io_path("huge.h5");
  gran_scene *s = NULL;
  char text[2048];
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 1\nmass = [1.0]\ndensity = [0.1]\n[restitution]\neps = 0.9\n"
           "[initial]\ntemperatures = [1.0]\n[engine]\ncounts = [5000000]\nt_end = 1.0\nreplicas = 100000\n"
           "[observables]\ntimes = [1.0]\n[output]\npath = \"%s\"\n", out);
  /* refused with the scene, naming the replicas (one replica fits) */
  assert_int_equal(gran_scene_parse(text, "huge.toml", &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "key 'engine.replicas'"));
  assert_non_null(strstr(gran_last_error_message(), "GB"));
  assert_null(s);
  assert_false(io_exists(out));
}

/* The memory check counts what an engine holds: species arrays and trees grow with M, M x M tables
 * only where the scene asks for them (an estimate of 64 M^2 B per engine refused this 1.2e4-species,
 * 4-replica run as 37 GB). */
static void test_many_species_fit(void **state) {
  (void)state;
  const int M = 12000;
  const char *out = io_path("many.h5");
  char *t = malloc((size_t)M * 40 + 1024);
  char *p = t + sprintf(t, "[mixture]\nnspecies = %d\nmass = [", M);
  for (int k = 0; k < M; k++) p += sprintf(p, "%s%.6g", k ? ", " : "", 1.0 + 0.001 * k);
  p += sprintf(p, "]\ndensity = [");
  for (int k = 0; k < M; k++) p += sprintf(p, "%s0.001", k ? ", " : "");
  sprintf(p, "]\n[restitution]\neps = 0.9\n[initial]\ntemperatures = \"equal\"\n[engine]\nvolume = 1000.0\n"
             "t_end = 0.01\nreplicas = 4\n[observables]\ntimes = [0.01]\ntemperatures = true\ntheory = false\n"
             "[output]\npath = \"%s\"\n", out);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(t, "many.toml", &s));
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, NULL, "", NULL, &res));
  assert_int_equal(res.finished, 1);
  assert_true(io_exists(out));
  gran_scene_destroy(&s);
  free(t);
}

int main(void) {
  io_tmp("t607");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_one_replica_is_the_plain_run),
      cmocka_unit_test(test_threads_and_streams),
      cmocka_unit_test(test_resume_with_replicas),
      cmocka_unit_test(test_memory_refused_first),
      cmocka_unit_test(test_many_species_fit),
  };
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
