/* t608-scene-set.c - gran_scene_set: a key of a loaded scene overridden as if the file said
 * `key = value`: a key the file has is replaced in the text (later lines keep their numbers), a key
 * it lacks is added to its table (or a new table), the override passes the schema's checks (an
 * unknown key, a wrong type or a value out of bounds fails naming the key and leaves the scene as
 * it was), replicas set by gran_scene_set_replicas stay, and a run stopped after a checkpoint and
 * resumed gives the file of a straight run of the overridden scene (the checkpoint stores the
 * edited text). */
#include "io_test_util.h"
#include "io_tiny_scene.h"

static const char *kScene =
    "title = \"set\"\n"
    "[mixture]\n"
    "nspecies = 2\n"
    "mass = [1.0,\n"
    "        4.0]\n"
    "density = [0.1, 0.02]\n"
    "[restitution]\n"
    "eps = 0.8   # a comment\n"
    "[engine]\n"
    "counts = [2000, 400]\n"
    "seed = 11\n"
    "t_end = 20.0\n"
    "[observables]\n"
    "times = { log = { start = 0.1, stop = 20.0, n = 8 } }\n"
    "[output]\n"
    "path = \"a.h5\"\n";

static uint64_t seed_of(const gran_scene *s) {
  gran_dsmc_options o;
  GRAN_ASSERT_OK(gran_dsmc_options_default(&o));
  GRAN_ASSERT_OK(gran_scene_dsmc_options(s, &o, NULL, NULL));
  return o.seed;
}

static void test_replace_and_add(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(kScene, "set.toml", &s));
  assert_int_equal(seed_of(s), 11);
  GRAN_ASSERT_OK(gran_scene_set(s, "engine.seed", "7"));
  assert_int_equal(seed_of(s), 7);
  const char *text = NULL, *path = NULL;
  GRAN_ASSERT_OK(gran_scene_text(s, &text));
  assert_non_null(strstr(text, "seed = 7"));
  assert_null(strstr(text, "\nseed = 11\n"));
  /* a value over two lines becomes one line and a blank one: the lines below keep their numbers */
  GRAN_ASSERT_OK(gran_scene_set(s, "mixture.mass", "[1.0, 9.0]"));
  GRAN_ASSERT_OK(gran_scene_text(s, &text));
  int lines = 0;
  for (const char *c = text; *c; c++) lines += *c == '\n';
  assert_int_equal(lines, 16);
  /* the strings of the output table, and a key the file lacks (added under [observables]) */
  GRAN_ASSERT_OK(gran_scene_set(s, "output.path", "\"b.h5\""));
  GRAN_ASSERT_OK(gran_scene_output_path(s, &path));
  assert_string_equal(path, "b.h5");
  GRAN_ASSERT_OK(gran_scene_set(s, "observables.msd", "false"));
  GRAN_ASSERT_OK(gran_scene_set(s, "output.checkpoint_every", "3"));
  /* an inline table replaced whole: the output times */
  GRAN_ASSERT_OK(gran_scene_set(s, "observables.times", "[1.0, 2.0, 5.0]"));
  int64_t nt = 0;
  double t1 = 0;
  GRAN_ASSERT_OK(gran_scene_sizes(s, NULL, &nt, NULL, NULL, &t1));
  assert_int_equal(nt, 3);
  /* a top-level key */
  GRAN_ASSERT_OK(gran_scene_set(s, "title", "\"renamed\""));
  /* the edited text is a scene of its own: parsed again it has every override */
  GRAN_ASSERT_OK(gran_scene_text(s, &text));
  gran_scene *again = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(text, "again.toml", &again));
  assert_int_equal(seed_of(again), 7);
  GRAN_ASSERT_OK(gran_scene_output_path(again, &path));
  assert_string_equal(path, "b.h5");
  gran_mixture *mix = NULL;
  GRAN_ASSERT_OK(gran_scene_mixture(again, &mix));
  double mass[2];
  GRAN_ASSERT_OK(gran_mixture_get(mix, mass, NULL, NULL));
  assert_true(mass[1] == 9.0);
  gran_mixture_destroy(&mix);
  gran_scene_destroy(&again);
  /* a table the scene does not have: added at the end ([initial] is optional) */
  GRAN_ASSERT_OK(gran_scene_set(s, "initial.temperatures", "\"equal\""));
  GRAN_ASSERT_OK(gran_scene_text(s, &text));
  assert_non_null(strstr(text, "[initial]\ntemperatures = \"equal\""));
  gran_scene_destroy(&s);
}

/* the override is checked like the file: the message names the key; the scene is unchanged */
static void test_refused(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(kScene, "set.toml", &s));
  const char *before = NULL, *after = NULL;
  GRAN_ASSERT_OK(gran_scene_text(s, &before));
  char *copy = strdup(before);
  struct {
    const char *key, *value, *want;
    int code;
  } bad[] = {
      {"engine.seed", "\"seven\"", "engine.seed", GRAN_ERR_PARSE},     /* type */
      {"engine.seed", "-1", "engine.seed", GRAN_ERR_PARSE},            /* bound */
      {"engine.replicas", "0", "1..1000000", GRAN_ERR_PARSE},           /* declared bound */
      {"restitution.eps", "1.5", "restitution.eps", GRAN_ERR_PARSE},   /* bound */
      {"engine.sed", "7", "engine.sed", GRAN_ERR_PARSE},               /* unknown key */
      {"nosuch.key", "7", "nosuch", GRAN_ERR_PARSE},                   /* unknown table */
      {"engine.seed", "7 8", "engine.seed", GRAN_ERR_PARSE},           /* not one value */
      {"engine.seed", "7\n[x]", "one line", GRAN_ERR_ARG},             /* injected table */
      {"engine.seed", "", "engine.seed", GRAN_ERR_PARSE},              /* empty */
      {"engine..seed", "7", "engine..seed", GRAN_ERR_ARG},             /* malformed key */
      {"engine", "7", "is a table", GRAN_ERR_ARG},                     /* a whole table */
      {"observables.times.log", "1", "inline table", GRAN_ERR_ARG},    /* inside an inline table */
  };
  for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
    const int st = gran_scene_set(s, bad[i].key, bad[i].value);
    if (st != bad[i].code || !strstr(gran_last_error_message(), bad[i].want))
      fprintf(stderr, "case %zu (%s = %s): %d %s\n", i, bad[i].key, bad[i].value, st, gran_last_error_message());
    assert_int_equal(st, bad[i].code);
    assert_non_null(strstr(gran_last_error_message(), bad[i].want));
    GRAN_ASSERT_OK(gran_scene_text(s, &after));
    assert_string_equal(after, copy);
    assert_int_equal(seed_of(s), 11);
  }
  assert_int_equal(gran_scene_set(NULL, "engine.seed", "1"), GRAN_ERR_ARG);
  assert_int_equal(gran_scene_set(s, NULL, "1"), GRAN_ERR_ARG);
  assert_int_equal(gran_scene_set(s, "engine.seed", NULL), GRAN_ERR_ARG);
  free(copy);
  gran_scene_destroy(&s);
}

/* replicas given through the API stay across an override of another key */
static void test_replicas_kept(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(kScene, "set.toml", &s));
  GRAN_ASSERT_OK(gran_scene_set_replicas(s, 3, 1));
  GRAN_ASSERT_OK(gran_scene_set(s, "engine.seed", "5"));
  int64_t R = 0;
  int32_t keep = 0;
  GRAN_ASSERT_OK(gran_scene_replicas(s, &R, &keep));
  assert_int_equal(R, 3);
  assert_int_equal(keep, 1);
  GRAN_ASSERT_OK(gran_scene_set(s, "engine.replicas", "2"));
  GRAN_ASSERT_OK(gran_scene_replicas(s, &R, &keep));
  assert_int_equal(R, 2);
  gran_scene_destroy(&s);
}

/* stop after a checkpoint, resume: the same file as a straight run of the overridden scene, and a
 * different one from the scene without the override (the seed changes every trajectory) */
static void test_resume_keeps_override(void **state) {
  (void)state;
  const char *straight = io_path("straight.h5"), *resumed = io_path("resumed.h5"), *plain = io_path("plain.h5");
  const char *ck = io_path("resumed.ckpt");
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(io_tiny_text("lowrank", "unused.h5"), "tiny.toml", &s));
  GRAN_ASSERT_OK(gran_scene_run(s, plain, "", NULL, NULL));
  GRAN_ASSERT_OK(gran_scene_set(s, "engine.seed", "12345"));
  GRAN_ASSERT_OK(gran_scene_run(s, straight, "", NULL, NULL));
  gran_run_control ctl = {0};
  ctl.stop_after_checkpoints = 1;
  gran_run_result res = {0};
  GRAN_ASSERT_OK(gran_scene_run(s, resumed, ck, &ctl, &res));
  assert_int_equal(res.finished, 0);
  gran_scene_destroy(&s);
  GRAN_ASSERT_OK(gran_scene_resume(ck, NULL, NULL, &res));
  assert_int_equal(res.finished, 1);
  int nds = 0;
  char diff[512] = "";
  assert_int_equal(io_h5_compare(straight, resumed, &nds, diff, sizeof diff), 0);
  assert_true(nds > 5);
  assert_int_not_equal(io_h5_compare(straight, plain, &nds, diff, sizeof diff), 0);
  /* the output stores the edited scene text */
  hid_t f = H5Fopen(resumed, H5F_ACC_RDONLY, H5P_DEFAULT);
  assert_true(f >= 0);
  char *text = io_h5_attr_string(f, "scene");
  assert_non_null(text);
  assert_non_null(strstr(text, "seed = 12345"));
  free(text);
  H5Fclose(f);
}

static int teardown(void **state) {
  (void)state;
  io_tmp_cleanup();
  return 0;
}

int main(void) {
  io_tmp("t608");
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_replace_and_add),
      cmocka_unit_test(test_refused),
      cmocka_unit_test(test_replicas_kept),
      cmocka_unit_test(test_resume_keeps_override),
  };
  const int rc = cmocka_run_group_tests(tests, NULL, NULL);
  teardown(NULL);
  return rc;
}
