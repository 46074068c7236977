/* t642-run-files.c - the files and signals of a run (src/io/run_files.cpp, src/io/run_output.cpp,
 * src/io/h5.cpp, src/cli/run.cpp):
 *  - every file a run writes (output, partial output, the XDMF sidecars of both, each .tmp, the
 *    checkpoint) is compared by identity with the scene, the checkpoint and each other: refused
 *    before any work, naming both roles, the other file untouched;
 *  - the sidecar is renamed into place only after the output file it points to: a failed output
 *    write leaves no .xmf and no .xmf.tmp;
 *  - a FIFO, a folder or a device given as checkpoint or scene is refused before it is opened;
 *  - SIGTERM stops `granary run` like Ctrl-C (partial output, checkpoint, the resume line) with
 *    exit code 143; a write past the file size limit (SIGXFSZ ignored) fails with a named error;
 *  - the run header names the cell selector, and --help the exit codes. */
#include "io_test_util.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>

static const char *cli(void) {
  const char *c = getenv("GRAN_CLI");
  return c ? c : "build/granary";
}

/* a small GSRD scene with field snapshots (so the output has an XDMF sidecar) */
static const char *snap_scene(const char *out, int steps) {
  static char b[1024];
  snprintf(b, sizeof b,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 8\nn0 = 5\ndt = 0.5\nsteps = %d\n"
           "[observables]\nevery = 2\nsnapshots = {every = 1}\n[output]\npath = \"%s\"\n",
           steps, out);
  return b;
}

static void expect_same_file(const gran_scene *s, const char *out, const char *ck, const char *role1, const char *role2) {
  assert_int_equal(gran_scene_run(s, out, ck, NULL, NULL), GRAN_ERR_ARG);
  const char *m = gran_last_error_message();
  assert_non_null(strstr(m, "same file"));
  assert_non_null(strstr(m, role1));
  assert_non_null(strstr(m, role2));
}

static void test_sidecar_roles(void **state) {
  (void)state;
  const char *out = io_path("o.h5");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(snap_scene(out, 4), "snap.toml", &s));
  /* -o o.h5 --checkpoint o.xmf: the checkpoint would be replaced by XDMF text */
  const char *xmf = io_path("o.xmf");
  io_write_file(xmf, "precious");
  expect_same_file(s, out, xmf, "checkpoint", "sidecar of the output");
  expect_same_file(s, out, io_path("o.partial.xmf"), "checkpoint", "sidecar of the partial output");
  expect_same_file(s, out, io_path("o.xmf.tmp"), "checkpoint", "sidecar of the output");
  expect_same_file(s, out, io_path("o.h5.tmp"), "checkpoint", "temporary file of the output");
  char *back = io_read_file(xmf);
  assert_string_equal(back, "precious");
  free(back);
  assert_false(io_exists(out));
  gran_scene_destroy(&s);
  /* a scene file named o2.xmf, run with -o o2.h5 */
  const char *sc = io_path("o2.xmf"), *out2 = io_path("o2.h5");
  io_write_file(sc, snap_scene(out2, 4));
  GRAN_ASSERT_OK(gran_scene_load(sc, &s));
  expect_same_file(s, out2, "", "scene file", "sidecar of the output");
  back = io_read_file(sc);
  assert_string_equal(back, snap_scene(out2, 4));
  free(back);
  gran_scene_destroy(&s);
}

/* the output file cannot be committed (a folder where its .tmp goes): no sidecar is left */
static int block_output(const gran_run_progress *p, void *params) {
  if (p->output_index == p->noutputs) mkdir((const char *)params, 0700);
  return 0;
}

static void test_no_orphan_sidecar(void **state) {
  (void)state;
  const char *out = io_path("b.h5");
  char tmp[600], xmf[600], xtmp[600];
  snprintf(tmp, sizeof tmp, "%s.tmp", out);
  snprintf(xmf, sizeof xmf, "%s/b.xmf", io_tmpdir);
  snprintf(xtmp, sizeof xtmp, "%s/b.xmf.tmp", io_tmpdir);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(snap_scene(out, 4), "snap.toml", &s));
  gran_run_control ctl = {0};
  ctl.progress = block_output;
  ctl.progress_params = tmp;
  assert_int_equal(gran_scene_run(s, out, "", &ctl, NULL), GRAN_ERR_IO);
  assert_false(io_exists(out));
  assert_false(io_exists(xmf));
  assert_false(io_exists(xtmp));
  rmdir(tmp);
  /* the same run, unblocked: both files, the sidecar naming the output */
  GRAN_ASSERT_OK(gran_scene_run(s, out, "", NULL, NULL));
  assert_true(io_exists(out) && io_exists(xmf) && !io_exists(xtmp));
  char *x = io_read_file(xmf);
  assert_non_null(strstr(x, "b.h5:/fields/"));
  free(x);
  gran_scene_destroy(&s);
}

static void alarm_fail(int sig) {
  (void)sig;
  static const char m[] = "t642: blocked on a FIFO\n";
  if (write(2, m, sizeof m - 1) < 0) _exit(2);
  _exit(1);
}

static void test_fifo(void **state) {
  (void)state;
  signal(SIGALRM, alarm_fail);
  alarm(30); /* an open of the FIFO would block forever */
  const char *fifo = io_path("ck.fifo");
  assert_int_equal(mkfifo(fifo, 0600), 0);
  assert_int_equal(gran_scene_resume(fifo, NULL, NULL, NULL), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "not a regular file"));
  gran_scene *s = NULL;
  assert_int_equal(gran_scene_load(fifo, &s), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "not a regular file"));
  assert_int_equal(gran_scene_resume(io_tmpdir, NULL, NULL, NULL), GRAN_ERR_IO); /* a folder */
  assert_non_null(strstr(gran_last_error_message(), "not a regular file"));
  assert_int_equal(gran_scene_resume("/dev/null", NULL, NULL, NULL), GRAN_ERR_IO); /* a device */
  assert_non_null(strstr(gran_last_error_message(), "not a regular file"));
  /* the command line: it reads the checkpoint's output path first */
  char cmd[1200], out[4096] = "";
  snprintf(cmd, sizeof cmd, "%s run --resume %s 2>&1", cli(), fifo);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t n = fread(out, 1, sizeof out - 1, p);
  out[n] = '\0';
  const int st = pclose(p);
  assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 1);
  assert_non_null(strstr(out, "not a regular file"));
  alarm(0);
}

/* build/granary run SCENE in a child (stdout, stderr to files); sig > 0: sent once the first
 * progress line is on stderr; fsize > 0: the child's file size limit. Returns the wait status. */
static int child_run(const char *scene, const char *err, int sig, long fsize) {
  const char *log = io_path("child.out");
  pid_t pid = fork();
  assert_true(pid >= 0);
  if (pid == 0) {
    int fo = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0600), fe = open(err, O_WRONLY | O_CREAT | O_TRUNC, 0600);
    if (fo < 0 || fe < 0) _exit(120);
    dup2(fo, 1);
    dup2(fe, 2);
    if (fsize > 0) {
      struct rlimit rl = {(rlim_t)fsize, (rlim_t)fsize};
      setrlimit(RLIMIT_FSIZE, &rl);
    }
    execl(cli(), cli(), "run", scene, (char *)NULL);
    _exit(121);
  }
  if (sig > 0) {
    for (int k = 0; k < 6000; k++) { /* up to 60 s */
      char *e = io_read_file(err);
      const int started = e && strchr(e, '[') != NULL;
      free(e);
      if (started) break;
      usleep(10000);
    }
    kill(pid, sig);
  }
  int st = 0;
  assert_true(waitpid(pid, &st, 0) == pid);
  return st;
}

static void test_sigterm(void **state) {
  (void)state;
  const char *out = io_path("term.h5"), *sc = io_path("term.toml"), *err = io_path("term.err");
  char text[1024];
  /* long enough never to finish in the test (about a minute per million steps here) */
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 16\nn0 = 5\ndt = 0.1\nsteps = 10000000\n"
           "[observables]\nevery = 10\n[output]\npath = \"%s\"\n", out);
  io_write_file(sc, text);
  const int st = child_run(sc, err, SIGTERM, 0);
  assert_true(WIFEXITED(st));
  assert_int_equal(WEXITSTATUS(st), 143);
  char part[600], ck[600];
  snprintf(part, sizeof part, "%s/term.partial.h5", io_tmpdir);
  snprintf(ck, sizeof ck, "%s.ckpt", out);
  assert_true(io_exists(part));
  assert_true(io_exists(ck));
  assert_false(io_exists(out));
  char *e = io_read_file(err);
  assert_non_null(strstr(e, "Continue with: granary run --resume"));
  free(e);
  /* the partial output is a complete HDF5 file with the rows recorded */
  hid_t f = H5Fopen(part, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  size_t n = 0;
  double *t = io_h5_read_double(f, "temperature/T", &n);
  assert_true(t != NULL && n >= 1);
  free(t);
  H5Fclose(f);
}

static void test_file_size_limit(void **state) {
  (void)state;
  const char *out = io_path("big.h5"), *sc = io_path("big.toml"), *err = io_path("big.err");
  char text[1024];
  snprintf(text, sizeof text,
           "[engine]\ntype = \"srd\"\ndimension = 2\ncells = 16\nn0 = 5\ndt = 0.1\nsteps = 40\n"
           "[observables]\nevery = 1\n[output]\npath = \"%s\"\ncheckpoint = \"\"\n", out);
  io_write_file(sc, text);
  const int st = child_run(sc, err, 0, 4096); /* the output is larger than 4 KiB */
  assert_true(WIFEXITED(st));
  assert_int_equal(WEXITSTATUS(st), 1);
  char *e = io_read_file(err);
  assert_non_null(strstr(e, "File too large"));
  free(e);
  assert_false(io_exists(out));
}

/* the run header names the selector the scene runs */
static void test_header_selector(void **state) {
  (void)state;
  const char *sc = io_path("cell.toml"), *out = io_path("cell.h5");
  char text[1024];
  snprintf(text, sizeof text,
           "[mixture]\nnspecies = 1\nmass = [1.0]\ndensity = [0.01]\n[restitution]\neps = 0.9\n[engine]\n"
           "selector = \"cell\"\ncounts = [200]\nt_end = 1.0\n[cell]\ndt = 0.5\n[observables]\ntimes = [1.0]\n"
           "[output]\npath = \"%s\"\ncheckpoint = \"\"\n", out);
  io_write_file(sc, text);
  char cmd[1200], buf[8192] = "";
  snprintf(cmd, sizeof cmd, "%s run %s 2>&1", cli(), sc);
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t n = fread(buf, 1, sizeof buf - 1, p);
  buf[n] = '\0';
  const int st = pclose(p);
  if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) fail_msg("granary run failed: %s", buf);
  assert_non_null(strstr(buf, "engine dsmc (cell)"));
  /* granary run --help documents the exit codes */
  snprintf(cmd, sizeof cmd, "%s run --help", cli());
  p = popen(cmd, "r");
  n = fread(buf, 1, sizeof buf - 1, p);
  buf[n] = '\0';
  pclose(p);
  assert_non_null(strstr(buf, "143"));
  assert_non_null(strstr(buf, "130"));
}

int main(void) {
  io_tmp("t642");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_sidecar_roles),
      cmocka_unit_test(test_no_orphan_sidecar),
      cmocka_unit_test(test_fifo),
      cmocka_unit_test(test_sigterm),
      cmocka_unit_test(test_file_size_limit),
      cmocka_unit_test(test_header_selector),
  };
  int r = cmocka_run_group_tests(tests, NULL, NULL);
  io_tmp_cleanup();
  return r;
}
