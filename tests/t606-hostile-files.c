/* t606-hostile-files.c - what the outside audit broke, one class per test: two spellings of one
 * file, a full disk during a write, bit-flipped and edited checkpoints, files that are not
 * scenes (/dev/zero, a FIFO), and a 1e5-number array. Each must end in a named error, exit
 * normally, and leave every earlier file as it was. */
#include "io_test_util.h"
#include "io_tiny_scene.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <zlib.h>

/* ---- one file under two names ---------------------------------------------------------------- */
static void test_same_file_two_spellings(void **state) {
  (void)state;
  char dotted[700], out_rel[700];
  const char *out = io_path("same.h5");
  snprintf(dotted, sizeof dotted, "%s/./same.h5", io_tmpdir);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  /* -o out.h5 --checkpoint ./out.h5: refused before any work, nothing written or deleted */
  GRAN_ASSERT_ERR(gran_scene_run(s, out, dotted, NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "same file"));
  assert_false(io_exists(out));
  /* a symbolic link is the same file too */
  snprintf(out_rel, sizeof out_rel, "%s/link.h5", io_tmpdir);
  io_write_file(out, "x");
  assert_int_equal(symlink(out, out_rel), 0);
  GRAN_ASSERT_ERR(gran_scene_run(s, out, out_rel, NULL, NULL), GRAN_ERR_ARG);
  gran_scene_destroy(&s);

  /* -o never overwrites the scene it reads */
  const char *scene = io_path("scene.toml");
  char alias[700];
  snprintf(alias, sizeof alias, "%s/../%s/scene.toml", io_tmpdir, strrchr(io_tmpdir, '/') + 1);
  io_write_file(scene, io_tiny_text("lowrank", io_path("o.h5")));
  char *before = io_read_file(scene);
  GRAN_ASSERT_OK(gran_scene_load(scene, &s));
  GRAN_ASSERT_ERR(gran_scene_run(s, alias, "", NULL, NULL), GRAN_ERR_ARG);
  assert_non_null(strstr(gran_last_error_message(), "scene file"));
  GRAN_ASSERT_ERR(gran_scene_run(s, NULL, scene, NULL, NULL), GRAN_ERR_ARG);
  char *after = io_read_file(scene);
  assert_string_equal(before, after);
  free(before);
  free(after);
  gran_scene_destroy(&s);
}

/* ---- a full disk -----------------------------------------------------------------------------
 * RLIMIT_FSIZE makes write(2) fail with EFBIG past a size, as a full disk fails with ENOSPC: in a
 * child process (so the limit does not outlive the test), a run whose output cannot be written
 * must return GRAN_ERR_IO naming the file, leave the previous output untouched and no .tmp file,
 * and exit normally (HDF5's shutdown at exit used to crash here). */
static void test_full_disk(void **state) {
  (void)state;
  const char *out = io_path("full.h5");
  io_write_file(out, "PREVIOUS OUTPUT\n");
  fflush(NULL);
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    signal(SIGXFSZ, SIG_IGN);
    struct rlimit rl = {4096, 4096};
    setrlimit(RLIMIT_FSIZE, &rl);
    gran_scene *s = NULL;
    if (gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s)) _exit(10);
    gran_run_result res;
    int st = gran_scene_run(s, NULL, io_path("full.ckpt"), NULL, &res);
    gran_scene_destroy(&s);
    if (st != GRAN_ERR_IO) _exit(11);
    if (!strstr(gran_last_error_message(), "full.")) _exit(12);
    /* the public checkpoint writer too (it used to crash at exit) */
    gran_mixture *mix = NULL;
    gran_dsmc *sim = NULL;
    gran_dsmc_options o;
    double n = 0.1;
    gran_dsmc_options_default(&o);
    o.volume = 2e4;
    if (gran_mixture_create(1, NULL, NULL, &n, &mix) || gran_dsmc_create(mix, NULL, NULL, &o, &sim)) _exit(13);
    if (gran_dsmc_checkpoint_write(sim, io_path("full-engine.h5"), "/engine") != GRAN_ERR_IO) _exit(14);
    gran_dsmc_destroy(&sim);
    gran_mixture_destroy(&mix);
    exit(0); /* through atexit: HDF5's shutdown runs */
  }
  int status = 0;
  assert_int_equal(waitpid(pid, &status, 0), pid);
  assert_true(WIFEXITED(status));
  assert_int_equal(WEXITSTATUS(status), 0);
  char *c = io_read_file(out);
  assert_string_equal(c, "PREVIOUS OUTPUT\n");
  free(c);
  char tmp[700];
  snprintf(tmp, sizeof tmp, "%s.tmp", out);
  assert_false(io_exists(tmp));
  snprintf(tmp, sizeof tmp, "%s.tmp", io_path("full.ckpt"));
  assert_false(io_exists(tmp));
}

/* ---- damaged checkpoints ------------------------------------------------------------------- */

/* a checkpoint of the tiny run, stopped after its first checkpoint */
static void make_checkpoint(const char *ck, const char *out) {
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", out), "tiny.toml", &s));
  gran_run_control ctl = {1, NULL, NULL};
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_run(s, out, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  gran_scene_destroy(&s);
}

/* Every single-bit flip is refused by the file checksum before HDF5 reads the file: 300 flips
 * spread over the file (the header, HDF5's metadata, the particle data). */
static void test_bit_flips(void **state) {
  (void)state;
  char ck[700], bad[700];
  snprintf(ck, sizeof ck, "%s", io_path("flip.ckpt"));
  snprintf(bad, sizeof bad, "%s", io_path("flipped.ckpt"));
  make_checkpoint(ck, io_path("flip.h5"));
  size_t n = 0;
  unsigned char *img = io_read_all(ck, &n);
  assert_true(n > 4096);
  uint64_t x = 12345;
  for (int trial = 0; trial < 300; trial++) {
    x = x * 6364136223846793005ULL + 1442695040888963407ULL;
    const size_t pos = trial < 40 ? (size_t)trial * 13 : (size_t)((x >> 11) % n);
    const int bit = (int)((x >> 3) & 7);
    img[pos] ^= (unsigned char)(1u << bit);
    io_write_all(bad, img, n);
    img[pos] ^= (unsigned char)(1u << bit);
    gran_clear_error();
    int st = gran_scene_resume(bad, io_path("flipped.h5"), NULL, NULL);
    if (st != GRAN_ERR_IO) fail_msg("flip of bit %d at byte %zu: status %d (%s)", bit, pos, st, gran_last_error_message());
    if (!strstr(gran_last_error_message(), "flipped.ckpt"))
      fail_msg("flip of bit %d at byte %zu: message does not name the file: %s", bit, pos, gran_last_error_message());
  }
  /* a truncated file */
  io_write_all(bad, img, n / 2);
  GRAN_ASSERT_ERR(gran_scene_resume(bad, io_path("flipped.h5"), NULL, NULL), GRAN_ERR_IO);
  free(img);
  /* the undamaged checkpoint still resumes */
  gran_run_result res;
  GRAN_ASSERT_OK(gran_scene_resume(ck, io_path("flip.h5"), NULL, &res));
  assert_int_equal(res.finished, 1);
}

/* An edit made through HDF5 with the checksum recomputed (a deliberate edit, or damage the CRC
 * missed, io_refresh_crc): the values themselves are checked against the scene and the invariants. */
static void edit_and_expect(const char *ck, const char *dataset, int64_t index, double value, int is_int,
                            const char *why) {
  const char *ed = io_path("edited.ckpt");
  io_edit_copy(ck, ed, dataset, index, value, is_int);
  gran_clear_error();
  int st = gran_scene_resume(ed, io_path("edited.h5"), NULL, NULL);
  if (st == GRAN_SUCCESS || !strstr(gran_last_error_message(), why))
    fail_msg("edit of %s[%" PRId64 "] = %g: status %d, message '%s' (expected '%s')", dataset, index, value, st,
             gran_last_error_message(), why);
}

static void test_edited_checkpoints(void **state) {
  (void)state;
  char ck[700];
  snprintf(ck, sizeof ck, "%s", io_path("edit.ckpt"));
  make_checkpoint(ck, io_path("edit.h5"));
  /* a count edited to 1e9 would ask for 12 GB: refused before any allocation */
  edit_and_expect(ck, "engine/counts", 0, 1e9, 1, "velocity values");
  /* a NaN speed bound would change the physics quietly */
  edit_and_expect(ck, "engine/bound", 1, NAN, 0, "speed bounds");
  /* a bound below the fastest particle of its species breaks the rejection sampling */
  edit_and_expect(ck, "engine/bound", 0, 1e-3, 0, "speed bounds");
  /* a velocity */
  edit_and_expect(ck, "engine/v", 7, INFINITY, 0, "velocities");
  /* a tree node that is no longer the sum of its children */
  edit_and_expect(ck, "engine/tree_u0", 1, 12345.0, 0, "tree");
  /* the pipeline head beyond its array */
  edit_and_expect(ck, "engine/counters", 7, 99, 1, "pipeline");
}

/* ---- things that are not scenes ------------------------------------------------------------ */
static void test_not_scene_files(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_load("/dev/zero", &s), GRAN_ERR_IO); /* would be read without end */
  assert_non_null(strstr(gran_last_error_message(), "not a regular file"));
  const char *fifo = io_path("fifo.toml");
  assert_int_equal(mkfifo(fifo, 0600), 0);
  GRAN_ASSERT_ERR(gran_scene_load(fifo, &s), GRAN_ERR_IO); /* would block forever */
  assert_null(s);
  GRAN_ASSERT_ERR(gran_scene_load(io_tmpdir, &s), GRAN_ERR_IO); /* a folder */
  /* a file over the 16 MiB limit is refused from its size, unread */
  const char *big = io_path("big.toml");
  int fd = open(big, O_WRONLY | O_CREAT | O_TRUNC, 0600);
  assert_true(fd >= 0);
  assert_int_equal(ftruncate(fd, (off_t)17 << 20), 0);
  close(fd);
  GRAN_ASSERT_ERR(gran_scene_load(big, &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "16 MiB"));
  /* deep nesting (a few thousand levels overflowed toml11's stack) */
  char *deep = malloc(20000);
  strcpy(deep, "[mixture]\ndensity = ");
  for (int i = 0; i < 5000; i++) strcat(deep, "[");
  GRAN_ASSERT_ERR(gran_scene_parse(deep, "deep.toml", &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "deep.toml:2"));
  free(deep);
}

/* A 1e5-number array on one line parses (it took 40 s with toml11 alone: quadratic in the length
 * of a line) and its values arrive in order; a message after it still names the right line. */
static void test_long_array(void **state) {
  (void)state;
  const int n = 100000;
  char *t = malloc((size_t)n * 24 + 256);
  char *p = t + sprintf(t, "[mixture]\nnspecies = %d\ndensity = [", n);
  for (int k = 0; k < n; k++) p += sprintf(p, "%s%.6g", k ? ", " : "", 0.1 / (1.0 + k));
  strcpy(p, "]\n[engine]\nvolume = 10.0\nt_end = 1.0\nmax_memory_gb = 100\n");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(t, "long.toml", &s));
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(s, &mix));
  double *d = malloc(sizeof(double) * (size_t)n);
  GRAN_ASSERT_OK(gran_mixture_get(mix, NULL, NULL, d));
  assert_true(d[0] == 0.1 && fabs(d[n - 1] - 0.1 / n) < 1e-6 * 0.1 / n);
  free(d);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&s);
  strcpy(strstr(t, "t_end = 1.0"), "t_end = -1.0\n");
  GRAN_ASSERT_ERR(gran_scene_parse(t, "long.toml", &s), GRAN_ERR_PARSE);
  assert_non_null(strstr(gran_last_error_message(), "long.toml:6:"));
  free(t);
}

static int setup(void **state) {
  (void)state;
  io_tmp("t606");
  return 0;
}
static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_same_file_two_spellings), cmocka_unit_test(test_full_disk),
      cmocka_unit_test(test_bit_flips),              cmocka_unit_test(test_edited_checkpoints),
      cmocka_unit_test(test_not_scene_files),        cmocka_unit_test(test_long_array),
  };
  return cmocka_run_group_tests_name("t606-hostile-files", tests, setup, teardown);
}
