/* t605-cli.c - the command-line driver ($GRAN_CLI): --help lists run and theory, and run --help
 * every option run parses; `run` writes its output and prints where; --stop-after-checkpoints +
 * --resume give the same file as a straight run; --set overrides scene keys and the run log
 * records the run; `info` names the compiler and the CUDA code; bad scenes exit 1 naming file,
 * line and key; `theory --json` is valid JSON (parsed back here) with the numbers of Bodrova &
 * Osinsky Fig. 2. */
#include "io_test_util.h"
#include "io_tiny_scene.h"
#include "json_test_util.h"

static const char *cli(void) {
  const char *c = getenv("GRAN_CLI");
  return c ? c : "build/granary";
}

/* ---- tests ---------------------------------------------------------------------------------- */

static char outbuf[1 << 20];

static void test_help(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s --help", cli());
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  assert_non_null(strstr(outbuf, "\n  run "));
  assert_non_null(strstr(outbuf, "\n  theory "));
  assert_non_null(strstr(outbuf, "\n  info "));
  snprintf(cmd, sizeof cmd, "%s info --gpu-count", cli());
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  char *end = NULL;
  long n = strtol(outbuf, &end, 10);
  assert_true(end != outbuf && n >= 0);
  snprintf(cmd, sizeof cmd, "%s run --bogus x.toml", cli());
  assert_int_equal(sh(cmd, NULL, 0, 0), 2);
  snprintf(cmd, sizeof cmd, "%s theory", cli());
  assert_int_equal(sh(cmd, NULL, 0, 0), 2);
  snprintf(cmd, sizeof cmd, "%s theory x.toml --times 1,abc", cli());
  assert_int_equal(sh(cmd, NULL, 0, 0), 2);
}

static void test_run_and_resume(void **state) {
  (void)state;
  const char *scene = io_path("tiny.toml");
  const char *a = io_path("cli-a.h5");
  char a_s[600];
  snprintf(a_s, sizeof a_s, "%s", a);
  io_write_file(scene, io_tiny_text("lowrank", io_path("from-scene.h5")));
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "%s run %s -o %s --no-checkpoint", cli(), scene, a_s);
  int st = sh(cmd, outbuf, sizeof outbuf, 0);
  if (st) fail_msg("%s exited %d: %s", cmd, st, outbuf);
  assert_true(io_exists(a_s));
  assert_non_null(strstr(outbuf, "wrote"));
  assert_non_null(strstr(outbuf, a_s));
  assert_non_null(strstr(outbuf, "T_theory")); /* the summary table */
  assert_non_null(strstr(outbuf, "MSD_sim"));

  const char *b = io_path("cli-b.h5");
  const char *ck = io_path("cli-b.ckpt");
  char b_s[600], ck_s[600];
  snprintf(b_s, sizeof b_s, "%s", b);
  snprintf(ck_s, sizeof ck_s, "%s", ck);
  snprintf(cmd, sizeof cmd, "%s run %s -o %s --checkpoint %s --stop-after-checkpoints 1 --quiet", cli(), scene, b_s, ck_s);
  st = sh(cmd, outbuf, sizeof outbuf, 1);
  if (st) fail_msg("%s exited %d: %s", cmd, st, outbuf);
  assert_non_null(strstr(outbuf, "--resume"));
  assert_true(io_exists(ck_s));
  assert_false(io_exists(b_s));
  snprintf(cmd, sizeof cmd, "%s run --resume %s --quiet", cli(), ck_s);
  st = sh(cmd, outbuf, sizeof outbuf, 1);
  if (st) fail_msg("%s exited %d: %s", cmd, st, outbuf);
  assert_true(io_exists(b_s));
  assert_non_null(strstr(outbuf, b_s));
  int nds = 0;
  char first[512] = "";
  int ndiff = io_h5_compare(a_s, b_s, &nds, first, sizeof first);
  if (ndiff) fail_msg("%d of %d datasets differ (first %s)", ndiff, nds, first);
  assert_true(nds >= 25);
  assert_false(io_exists(io_path("from-scene.h5"))); /* -o overrides the scene's path */

  /* resume + a scene at the same time is a usage error */
  snprintf(cmd, sizeof cmd, "%s run %s --resume %s", cli(), scene, ck_s);
  assert_int_equal(sh(cmd, NULL, 0, 0), 2);
}

/* every option `granary run` parses (each strcmp against "-..." in src/cli/run.cpp) is in its --help */
static void test_run_help_complete(void **state) {
  (void)state;
  const char *src = getenv("GRAN_SOURCE_DIR") ? getenv("GRAN_SOURCE_DIR") : ".";
  char path[1024], cmd[1024];
  snprintf(path, sizeof path, "%s/src/cli/run.cpp", src);
  char *code = io_read_file(path);
  assert_non_null(code);
  snprintf(cmd, sizeof cmd, "%s run --help", cli());
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  int n = 0;
  for (const char *c = code; (c = strstr(c, "strcmp(a, \"-")) != NULL; c++) {
    const char *b = c + strlen("strcmp(a, \""), *e = strchr(b, '"');
    assert_non_null(e);
    char opt[64], want[80];
    snprintf(opt, sizeof opt, "%.*s", (int)(e - b), b);
    /* the option as a word of the help text: followed by a space, a comma or a bracket */
    int found = 0;
    for (const char *after = " ,]"; *after && !found; after++) {
      snprintf(want, sizeof want, "%s%c", opt, *after);
      found = strstr(outbuf, want) != NULL;
    }
    if (!found) fail_msg("granary run parses '%s' but run --help does not list it", opt);
    n++;
  }
  assert_true(n >= 18); /* -o --output --checkpoint ... -h --help */
  free(code);
}

/* --set overrides scene keys (checked like the file, stored in the output's scene text); the run
 * log OUTPUT.log holds the input echo, the thermo table and the summary; --log / --no-log; a log
 * that is another file of the run is refused; the first ETA waits for 1 % and 2 s */
static void test_set_and_log(void **state) {
  (void)state;
  const char *scene = io_path("set.toml"), *out = io_path("set.h5");
  char out_s[600], log_s[700], cmd[4096];
  snprintf(out_s, sizeof out_s, "%s", out);
  snprintf(log_s, sizeof log_s, "%s.log", out_s);
  io_write_file(scene, io_tiny_text("lowrank", io_path("never.h5")));
  snprintf(cmd, sizeof cmd, "%s run %s --no-checkpoint --set engine.seed=4242 --set 'output.path=\"%s\"'", cli(), scene,
           out_s);
  int st = sh(cmd, outbuf, sizeof outbuf, 1);
  if (st) fail_msg("%s exited %d: %s", cmd, st, outbuf);
  assert_true(io_exists(out_s));
  assert_false(io_exists(io_path("never.h5")));
  /* progress on a pipe: the first lines (under 1 %% of the work, under 2 s) have no ETA, the last 0:00 */
  const char *first = strstr(outbuf, "[  ");
  assert_non_null(first);
  const char *eol = strchr(first, '\n');
  assert_non_null(eol);
  assert_true(eol - first > 5 && strncmp(eol - 5, "ETA ?", 5) == 0);
  assert_non_null(strstr(outbuf, "[100.0%]"));
  assert_non_null(strstr(strstr(outbuf, "[100.0%]"), "ETA 0:00"));
  assert_non_null(strstr(outbuf, log_s));
  /* the output holds the overridden scene */
  hid_t f = H5Fopen(out_s, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  char *text = io_h5_attr_string(f, "scene");
  assert_non_null(text);
  assert_non_null(strstr(text, "seed = 4242"));
  free(text);
  H5Fclose(f);
  /* the log */
  char *log = io_read_file(log_s);
  assert_non_null(log);
  assert_non_null(strstr(log, "command:   granary run"));
  assert_non_null(strstr(log, "--set engine.seed=4242"));
  assert_non_null(strstr(log, "version:   granary " GRAN_VERSION_STRING));
  assert_non_null(strstr(log, "threads:"));
  assert_non_null(strstr(log, "----- scene text (as run) -----\ntitle = \"tiny\""));
  assert_non_null(strstr(log, "seed = 4242"));
  /* the live thermo table: index, t, T (the gas temperature of that output time), the work */
  const char *live = strstr(log, "   index             t             T      collisions      coll/s");
  assert_non_null(live);
  {
    int idx = 0;
    double t = 0, T = 0;
    assert_int_equal(sscanf(strchr(live, '\n') + 1, "%d %lf %lf", &idx, &t, &T), 3);
    assert_true(idx == 1 && t > 0 && T > 0 && isfinite(T));
  }
  assert_non_null(strstr(outbuf, " T = ")); /* the progress line */
  assert_non_null(strstr(log, "# thermo of the run (from the output file)"));
  assert_non_null(strstr(log, "T_1"));
  assert_non_null(strstr(log, "T_2"));
  assert_non_null(strstr(log, "granary run: wrote"));
  assert_non_null(strstr(log, "T_theory")); /* the summary */
  /* the thermo rows: every output time of the 8 (one row each), index 1..8, t increasing */
  const char *rows = strstr(log, "# thermo of the run");
  rows = strchr(strchr(rows, '\n') + 1, '\n') + 1;
  double tprev = -1;
  for (int i = 1; i <= IO_TINY_NT; i++) {
    int idx = 0;
    double t = 0, T1 = 0, T2 = 0;
    assert_int_equal(sscanf(rows, "%d %lf %lf %lf", &idx, &t, &T1, &T2), 4);
    assert_int_equal(idx, i);
    assert_true(t > tprev && T1 > 0 && T2 > 0);
    tprev = t;
    rows = strchr(rows, '\n') + 1;
  }
  free(log);

  /* --no-log and --log none: no log; --log FILE: there */
  const char *out2 = io_path("set2.h5"), *mylog = io_path("my.log");
  char log2[700];
  snprintf(log2, sizeof log2, "%s.log", out2);
  for (int k = 0; k < 3; k++) {
    snprintf(cmd, sizeof cmd, "%s run %s -o %s --no-checkpoint --force --quiet %s%s", cli(), scene, out2,
             k == 0 ? "--no-log" : k == 1 ? "--log none" : "--log ", k == 2 ? mylog : "");
    st = sh(cmd, outbuf, sizeof outbuf, 1);
    if (st) fail_msg("%s exited %d: %s", cmd, st, outbuf);
    assert_false(io_exists(log2));
  }
  assert_true(io_exists(mylog));
  /* an output in a folder that does not exist yet (out/ of a fresh checkout): the log goes there too */
  {
    char nout[700], nlog[720];
    snprintf(nout, sizeof nout, "%s/newdir/sub/o.h5", io_tmpdir);
    snprintf(nlog, sizeof nlog, "%s.log", nout);
    snprintf(cmd, sizeof cmd, "%s run %s -o %s --no-checkpoint --quiet", cli(), scene, nout);
    st = sh(cmd, outbuf, sizeof outbuf, 1);
    if (st || strstr(outbuf, "no log")) fail_msg("%s exited %d: %s", cmd, st, outbuf);
    assert_true(io_exists(nout));
    assert_true(io_exists(nlog));
  }

  /* a log that is the output, the scene or the checkpoint: refused before the run */
  const char *same[] = {out2, scene, "ck.h5"};
  for (int k = 0; k < 3; k++) {
    char extra[800] = "";
    if (k == 2) snprintf(extra, sizeof extra, "--checkpoint %s/ck.h5 --log %s/./ck.h5", io_tmpdir, io_tmpdir);
    else snprintf(extra, sizeof extra, "--log %s", same[k]);
    snprintf(cmd, sizeof cmd, "%s run %s -o %s --force %s", cli(), scene, out2, extra);
    assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 1);
    assert_non_null(strstr(outbuf, "are the same file"));
  }

  /* --set errors: the key named; a missing '=' is a usage error; not with --resume */
  struct {
    const char *arg, *want;
    int code;
  } bad[] = {
      {"engine.seed='\"x\"'", "--set engine.seed", 1},
      {"engine.sed=7", "engine.sed", 1},
      {"restitution.eps=1.5", "--set restitution.eps", 1},
      {"engine.seed", "expected KEY=VALUE", 2},
      {"=7", "expected KEY=VALUE", 2},
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    snprintf(cmd, sizeof cmd, "%s run %s -o %s --force --set %s", cli(), scene, out2, bad[i].arg);
    st = sh(cmd, outbuf, sizeof outbuf, 1);
    if (st != bad[i].code || !strstr(outbuf, bad[i].want)) fail_msg("%s: exit %d: %s", cmd, st, outbuf);
  }
  snprintf(cmd, sizeof cmd, "%s run --resume x.ckpt --set engine.seed=1", cli());
  assert_int_equal(sh(cmd, NULL, 0, 0), 2);
}

/* granary info: the compiler with its __VERSION__, the flags, the CUDA code built */
static void test_info(void **state) {
  (void)state;
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "%s info", cli());
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  assert_non_null(strstr(outbuf, "compiler:     "));
  assert_non_null(strstr(outbuf, "(__VERSION__ \"" __VERSION__ "\")"));
  assert_non_null(strstr(outbuf, "flags:        "));
  assert_non_null(strstr(outbuf, "CUDA code:    "));
  int compiled = 0;
  GRAN_ASSERT_OK(gran_cuda_compiled(&compiled));
  if (compiled) assert_true(strstr(outbuf, "sm_") || strstr(outbuf, "compute_"));
  else assert_non_null(strstr(outbuf, "CUDA code:    none"));
}

static void test_bad_scene_message(void **state) {
  (void)state;
  const char *bad = io_path("bad.toml");
  io_write_file(bad, "[mixture]\nnspecies = 2\ndensity = [0.1, 0.01]\n[restitution]\neps = 1.5\n[engine]\ncounts = [10, 1]\nt_end = 1.0\n");
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "%s run %s", cli(), bad);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 1);
  assert_non_null(strstr(outbuf, "bad.toml:5:"));
  assert_non_null(strstr(outbuf, "restitution.eps"));
  snprintf(cmd, sizeof cmd, "%s theory %s", cli(), bad);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 1);
  assert_non_null(strstr(outbuf, "bad.toml:5:"));
  /* unwritable output: exit 1, nothing run */
  io_write_file(io_path("blocker"), "x");
  const char *good = io_path("good.toml");
  char outp[700];
  snprintf(outp, sizeof outp, "%s/o.h5", io_path("blocker"));
  io_write_file(good, io_tiny_text("lowrank", outp));
  snprintf(cmd, sizeof cmd, "%s run %s", cli(), good);
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 1), 1);
  assert_non_null(strstr(outbuf, "not writable"));
}

static void test_theory_json(void **state) {
  (void)state;
  char cmd[2048];
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/fig2.toml --json --times 0,1,10,100,1000 --lags 1,10,100", cli(),
           gran_test_source_dir());
  int st = sh(cmd, outbuf, sizeof outbuf, 0);
  if (st) fail_msg("%s exited %d", cmd, st);
  jv root;
  if (!json_parse(outbuf, &root)) fail_msg("theory --json is not valid JSON: %s", outbuf);
  assert_int_equal(root.type, 5);
  assert_true(jnum(jget(&root, "nspecies")) == 2);
  const jv *sp = jget(&root, "species");
  assert_non_null(sp);
  assert_int_equal(sp->type, 4);
  assert_int_equal(sp->n, 2);
  /* Bodrova & Osinsky Fig. 2 caption: T_1(0) = 0.554, T_2(0) = 45.58755, tau0 = 19.258 (printed digits) */
  const double T1 = jnum(jget(&sp->items[0], "T0")), T2 = jnum(jget(&sp->items[1], "T0"));
  const double tau0 = jnum(jget(&root, "tau0"));
  GRAN_ASSERT_ABS(T1, 0.554, 0.0005);
  GRAN_ASSERT_ABS(T2, 45.58755, 0.000005);
  GRAN_ASSERT_ABS(tau0, 19.258, 0.0005);
  GRAN_ASSERT_REL((0.1 * T1 + 0.001 * T2) / 0.101, 1.0, 2e-4); /* <T(0)> = 1 to the caption's digits */
  assert_true(jnum(jget(&sp->items[1], "m")) == 100.0);
  /* T_k(t) follows Haff's law in the HCS: T_k(t) = T_k(0) / (1 + t/tau0)^2 (the caption's
   * temperatures are the HCS to 5 digits: 1e-4) */
  const jv *T = jget(&root, "T");
  assert_non_null(T);
  assert_int_equal(T->n, 5);
  for (int i = 0; i < 5; i++) {
    const double t = jnum(&jget(&root, "times")->items[i]);
    GRAN_ASSERT_REL(jnum(&T->items[i].items[0]), T1 / ((1 + t / tau0) * (1 + t / tau0)), 1e-4);
  }
  const jv *msd = jget(&root, "msd");
  assert_true(jnum(&msd->items[0].items[0]) == 0.0);
  assert_true(jnum(&msd->items[4].items[1]) > jnum(&msd->items[3].items[1]));
  /* TAMSD: lags >= t_meas are null, the others numbers */
  const jv *ta = jget(&root, "tamsd");
  assert_non_null(ta);
  assert_int_equal(ta->n, 5);
  const jv *row = jget(&ta->items[1], "tamsd"); /* t_meas = 1: every lag is >= 1 */
  assert_int_equal(row->items[0].items[0].type, 0);
  row = jget(&ta->items[4], "tamsd"); /* t_meas = 1000 */
  assert_true(jnum(&row->items[2].items[1]) > jnum(&row->items[0].items[1]));
  jfree(&root);

  /* the text form prints the same three numbers */
  snprintf(cmd, sizeof cmd, "%s theory %s/scenes/fig2.toml", cli(), gran_test_source_dir());
  assert_int_equal(sh(cmd, outbuf, sizeof outbuf, 0), 0);
  const char *t0 = strstr(outbuf, "tau0 = ");
  assert_non_null(t0);
  GRAN_ASSERT_ABS(strtod(t0 + 7, NULL), 19.258, 0.0005);
  assert_non_null(strstr(outbuf, " 0.554"));
  assert_non_null(strstr(outbuf, " 45.58755"));
}

static void test_json_of_every_scene(void **state) {
  (void)state;
  const char *names[] = {"default", "fig1", "fig3", "fig5", "fig7", "table1"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s theory %s/scenes/%s.toml --json --times 1,100", cli(), gran_test_source_dir(), names[i]);
    int st = sh(cmd, outbuf, sizeof outbuf, 0);
    if (st) fail_msg("%s exited %d", cmd, st);
    jv root;
    if (!json_parse(outbuf, &root)) fail_msg("%s: not valid JSON: %.400s", names[i], outbuf);
    assert_non_null(jget(&root, "species"));
    assert_non_null(jget(&root, "msd"));
    jfree(&root);
  }
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t605");
  H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_help),
      cmocka_unit_test(test_run_and_resume),
      cmocka_unit_test(test_run_help_complete),
      cmocka_unit_test(test_set_and_log),
      cmocka_unit_test(test_info),
      cmocka_unit_test(test_bad_scene_message),
      cmocka_unit_test(test_theory_json),
      cmocka_unit_test(test_json_of_every_scene),
  };
  return cmocka_run_group_tests_name("t605-cli", tests, NULL, teardown);
}
