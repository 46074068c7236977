/* t602-scene-errors.c - every kind of bad scene is rejected before any work with
 * GRAN_ERR_PARSE and a message "FILE:LINE: key 'table.key': why" (table-driven). */
#include "granary_test.h"

/* A valid scene; cases replace one line or append lines. Line numbers:
 *  1 [mixture]  2 nspecies  3 mass  4 density  5 [restitution]  6 eps  7 [initial]  8 temperatures
 *  9 t_start  10 [engine]  11 counts  12 t_end  13 [observables]  14 times  15 [output]  16 path */
static const char *kBase[] = {
    "[mixture]",
    "nspecies = 2",
    "mass = [1.0, 100.0]",
    "density = [0.1, 0.001]",
    "[restitution]",
    "eps = 0.5",
    "[initial]",
    "temperatures = \"equal\"",
    "t_start = 0.0",
    "[engine]",
    "counts = [100, 10]",
    "t_end = 10.0",
    "[observables]",
    "times = [1.0, 2.0, 10.0]",
    "[output]",
    "path = \"x.h5\"",
};
#define NBASE ((int)(sizeof kBase / sizeof kBase[0]))

typedef struct {
  const char *what;    /* description */
  int line;            /* line of kBase to replace (1-based), 0: none */
  const char *replace; /* new text of that line ("" deletes it) */
  const char *append;  /* appended at the end (after line 16), or NULL */
  int code;            /* expected status */
  int msg_line;        /* line the message must name, 0: any */
  const char *key;     /* must appear in the message */
  const char *why;     /* must appear in the message */
} bad_case;

static const bad_case kCases[] = {
    {"unknown key at top level", 0, NULL, "colour = 3", GRAN_ERR_PARSE, 0, "output.colour", "unknown key"},
    {"unknown key in a table", 4, "densty = [0.1, 0.001]", NULL, GRAN_ERR_PARSE, 4, "mixture.densty", "unknown key"},
    {"unknown table", 0, NULL, "[effects]\nshear = 1", GRAN_ERR_PARSE, 17, "'effects'", "unknown key"},
    {"wrong type: string for a number", 6, "eps = \"half\"", NULL, GRAN_ERR_PARSE, 6, "restitution.eps", "expected a number"},
    {"wrong type: integer for a boolean", 14, "msd = 1\ntimes = [1.0, 2.0, 10.0]", NULL, GRAN_ERR_PARSE, 14, "observables.msd", "expected true or false"},
    {"wrong type: array of strings", 3, "mass = [\"a\", \"b\"]", NULL, GRAN_ERR_PARSE, 3, "mixture.mass", "expected a number"},
    {"negative count", 11, "counts = [100, -10]", NULL, GRAN_ERR_PARSE, 11, "engine.counts", ">= 0"},
    {"non-integral count", 11, "counts = [100, 1.5]", NULL, GRAN_ERR_PARSE, 11, "engine.counts", "expected an integer"},
    {"eps > 1", 6, "eps = 1.5", NULL, GRAN_ERR_PARSE, 6, "restitution.eps", "[0, 1]"},
    {"eps < 0", 6, "eps = -0.1", NULL, GRAN_ERR_PARSE, 6, "restitution.eps", "[0, 1]"},
    {"eps matrix entry > 1", 6, "eps_matrix = [[0.5, 1.2], [1.2, 0.5]]", NULL, GRAN_ERR_PARSE, 6, "restitution.eps_matrix", "[0, 1]"},
    {"asymmetric matrix", 6, "eps_matrix = [[0.5, 0.6], [0.7, 0.5]]", NULL, GRAN_ERR_PARSE, 6, "restitution.eps_matrix", "symmetric"},
    {"t_end before t_start", 9, "t_start = 20.0", NULL, GRAN_ERR_PARSE, 12, "engine.t_end", "not after t_start"},
    {"times not increasing", 14, "times = [1.0, 3.0, 2.0]", NULL, GRAN_ERR_PARSE, 14, "observables.times", "increase"},
    {"time after t_end", 14, "times = [1.0, 20.0]", NULL, GRAN_ERR_PARSE, 14, "observables.times", "after t_end"},
    {"time before t_start", 9, "t_start = 1.5", NULL, GRAN_ERR_PARSE, 14, "observables.times", "before t_start"},
    {"mismatched array lengths", 3, "mass = [1.0, 2.0, 3.0]", NULL, GRAN_ERR_PARSE, 3, "mixture.mass", "3 entries"},
    {"counts length mismatch", 11, "counts = [100]", NULL, GRAN_ERR_PARSE, 11, "engine.counts", "1 entries"},
    {"temperature list length", 8, "temperatures = [1.0, 2.0, 3.0]", NULL, GRAN_ERR_PARSE, 8, "initial.temperatures", "3 entries"},
    {"matrix of the wrong size", 6, "eps_matrix = [[0.5]]", NULL, GRAN_ERR_PARSE, 6, "restitution.eps_matrix", "rows"},
    {"NaN", 6, "eps = nan", NULL, GRAN_ERR_PARSE, 6, "restitution.eps", "not finite"},
    {"inf", 12, "t_end = inf", NULL, GRAN_ERR_PARSE, 12, "engine.t_end", "not finite"},
    {"-inf in an array", 4, "density = [0.1, -inf]", NULL, GRAN_ERR_PARSE, 4, "mixture.density", "not finite"},
    {"misspelt table name", 10, "[engine_]", NULL, GRAN_ERR_PARSE, 10, "'engine_'", "unknown key"},
    {"missing density", 4, "", NULL, GRAN_ERR_PARSE, 1, "mixture.density", "missing"},
    {"missing particle numbers", 11, "", NULL, GRAN_ERR_PARSE, 10, "engine.counts", "missing"},
    {"missing nspecies and arrays", 0, NULL, NULL, GRAN_ERR_PARSE, 0, NULL, NULL}, /* placeholder, replaced below */
    {"syntax error", 3, "mass = [1.0, ", NULL, GRAN_ERR_PARSE, 0, "syntax", ""},
    {"duplicate key", 0, NULL, "path = \"y.h5\"", GRAN_ERR_PARSE, 0, "syntax", ""},
    {"unknown model", 6, "model = \"plastic\"", NULL, GRAN_ERR_PARSE, 6, "restitution.model", "plastic"},
    {"unknown table name", 0, NULL, "[engine2]", GRAN_ERR_PARSE, 17, "engine2", "unknown key"},
    {"unknown temperatures word", 8, "temperatures = \"warm\"", NULL, GRAN_ERR_PARSE, 8, "initial.temperatures", "warm"},
    {"nspecies zero", 2, "nspecies = 0", NULL, GRAN_ERR_PARSE, 2, "mixture.nspecies", ">= 1"},
    {"negative density", 4, "density = [0.1, -0.001]", NULL, GRAN_ERR_PARSE, 4, "mixture.density", "negative"},
    {"mass not positive", 3, "mass = [1.0, 0.0]", NULL, GRAN_ERR_PARSE, 3, "mixture.mass", "> 0"},
    {"both density and density_law", 0, NULL, NULL, GRAN_ERR_PARSE, 0, NULL, NULL}, /* placeholder */
    {"log grid from zero", 14, "times = { log = { start = 0.0, stop = 10.0, n = 5 } }", NULL, GRAN_ERR_PARSE, 14, "observables.times.log.start", "start > 0"},
    {"grid with unknown key", 14, "times = { log = { start = 1.0, stop = 10.0, n = 5, m = 1 } }", NULL, GRAN_ERR_PARSE, 14, "observables.times.log.m", "unknown key"},
    {"tamsd beyond t_end", 14, "tamsd = { tracers = 2, dt = 1.0, samples = 100 }", NULL, GRAN_ERR_PARSE, 14, "observables.tamsd.samples", "t_end"},
    {"tamsd without dt", 14, "tamsd = { tracers = 2, samples = 5 }", NULL, GRAN_ERR_PARSE, 14, "observables.tamsd.dt", "missing"},
    {"tamsd lag too long", 14, "tamsd = { tracers = 2, dt = 1.0, samples = 5, lags = [1.0, 4.0] }", NULL, GRAN_ERR_PARSE, 14, "observables.tamsd.lags", "outside"},
    {"negative seed", 12, "seed = -3", NULL, GRAN_ERR_PARSE, 12, "engine.seed", ">= 0"},
    {"float seed", 12, "seed = 3.0", NULL, GRAN_ERR_PARSE, 12, "engine.seed", "expected an integer"},
    {"output equals checkpoint", 0, NULL, "checkpoint = \"x.h5\"", GRAN_ERR_PARSE, 17, "output.checkpoint", "differ"},
    {"negative checkpoint interval", 0, NULL, "checkpoint_interval = -1", GRAN_ERR_PARSE, 17, "output.checkpoint_interval", ">= 0"},
    {"viscoelastic without beta", 6, "model = \"viscoelastic\"", NULL, GRAN_ERR_PARSE, 5, "restitution.beta", "missing"},
    {"eps with the viscoelastic model", 5, "[restitution]\nmodel = \"viscoelastic\"\nbeta = 0.1", NULL, GRAN_ERR_PARSE, 0, "restitution.eps", "not used"},
    {"temperature that overflows", 9, "T_mean = 1e308", NULL, GRAN_ERR_PARSE, 9, "initial.T_mean", "overflow"},
    {"material whose beta overflows", 6, "material = { A = 1e308, Y = 1e308, nu = 0.3 }", NULL, GRAN_ERR_PARSE, 6, "restitution.material", "overflows"},
    {"nesting too deep", 4, "density = [[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[[0.1]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]]", NULL, GRAN_ERR_PARSE, 4, "nested deeper", ""},
    {"invalid UTF-8 in a literal string", 0, NULL, "[output2]\nx = 'abc\xff\xfe'", GRAN_ERR_PARSE, 18, "invalid UTF-8", ""},
    {"memory beyond the limit", 11, "counts = [100000000, 10]\nmax_memory_gb = 0.5", NULL, GRAN_ERR_PARSE, 11, "engine.counts", "max_memory_gb"},
    {"species beyond the memory", 2, "nspecies = 100000000", NULL, GRAN_ERR_PARSE, 2, "mixture.nspecies", "max_memory_gb"},
    {"Poisson ratio out of range", 6, "material = { A = 1.0, Y = 1.0, nu = 0.7 }", NULL, GRAN_ERR_PARSE, 6, "restitution.material.nu", "Poisson"},
};
#define NCASES ((int)(sizeof kCases / sizeof kCases[0]))

static char *build(const bad_case *c) {
  size_t cap = 8192;
  char *s = calloc(cap, 1);
  for (int i = 1; i <= NBASE; i++) {
    const char *line = (c->line == i) ? c->replace : kBase[i - 1];
    if (c->line == i && line[0] == '\0') {
      strcat(s, "# (removed)\n"); /* keep the line numbers */
      continue;
    }
    strcat(s, line);
    strcat(s, "\n");
  }
  if (c->append) {
    strcat(s, c->append);
    strcat(s, "\n");
  }
  return s;
}

static void check_case(const bad_case *c, const char *text) {
  gran_scene *s = (gran_scene *)0x1;
  gran_clear_error();
  int st = gran_scene_parse(text, "bad.toml", &s);
  const char *msg = gran_last_error_message();
  if (st != c->code) fail_msg("case '%s': status %d (%s), expected %d; message: %s\n%s", c->what, st, gran_strerror(st), c->code, msg, text);
  assert_null(s); /* nothing handed out */
  if (c->key && !strstr(msg, c->key)) fail_msg("case '%s': message does not name '%s': %s", c->what, c->key, msg);
  if (c->why && c->why[0] && !strstr(msg, c->why)) fail_msg("case '%s': message lacks '%s': %s", c->what, c->why, msg);
  if (!strstr(msg, "bad.toml:")) fail_msg("case '%s': message does not name the file: %s", c->what, msg);
  if (c->msg_line) {
    char want[64];
    snprintf(want, sizeof want, "bad.toml:%d:", c->msg_line);
    if (!strstr(msg, want)) fail_msg("case '%s': message does not name line %d: %s", c->what, c->msg_line, msg);
  }
}

static void test_table(void **state) {
  (void)state;
  /* the base scene itself is valid */
  bad_case none = {"none", 0, NULL, NULL, 0, 0, NULL, NULL};
  char *ok = build(&none);
  gran_scene *s = NULL;
  GRAN_ASSERT_OK(gran_scene_parse(ok, "bad.toml", &s));
  gran_scene_destroy(&s);
  free(ok);
  int n = 0;
  for (int i = 0; i < NCASES; i++) {
    if (!kCases[i].key) continue; /* placeholders: tested by hand below */
    char *t = build(&kCases[i]);
    check_case(&kCases[i], t);
    free(t);
    n++;
  }
  assert_true(n >= 40);
}

static void test_by_hand(void **state) {
  (void)state;
  /* no nspecies and no arrays */
  bad_case c1 = {"missing nspecies", 0, NULL, NULL, GRAN_ERR_PARSE, 1, "mixture.nspecies", "missing"};
  check_case(&c1, "[mixture]\ng2 = 1.0\n[engine]\ncounts = [1]\nt_end = 1.0\n");
  bad_case c2 = {"density and density_law", 0, NULL, NULL, GRAN_ERR_PARSE, 4, "mixture.density_law", "not both"};
  check_case(&c2, "[mixture]\nnspecies = 1\ndensity = [0.1]\ndensity_law = { n1 = 0.1 }\n[engine]\ncounts = [1]\nt_end = 1.0\n");
  bad_case c3 = {"missing [mixture]", 0, NULL, NULL, GRAN_ERR_PARSE, 1, "mixture", "missing"};
  check_case(&c3, "[engine]\ncounts = [1]\nt_end = 1.0\n");
  bad_case c4 = {"no t_end, no times", 0, NULL, NULL, GRAN_ERR_PARSE, 3, "engine.t_end", "missing"};
  check_case(&c4, "[mixture]\ndensity = [0.1]\n[engine]\ncounts = [1]\n");
  bad_case c5 = {"unknown selector", 0, NULL, NULL, GRAN_ERR_PARSE, 5, "engine.selector", "nanbu"};
  check_case(&c5, "[mixture]\ndensity = [0.1]\n[engine]\ncounts = [1]\nselector = \"nanbu\"\nt_end = 1.0\n");
  bad_case c6 = {"huge N1", 0, NULL, NULL, GRAN_ERR_PARSE, 4, "engine.N1", "[1, 1e12]"};
  check_case(&c6, "[mixture]\ndensity = [0.1]\n[engine]\nN1 = 1e13\nt_end = 1.0\n");
  bad_case c7 = {"unknown engine type", 0, NULL, NULL, GRAN_ERR_PARSE, 4, "engine.type", "gsrd"};
  check_case(&c7, "[mixture]\ndensity = [0.1]\n[engine]\ntype = \"gsrd\"\ncounts = [1]\nt_end = 1.0\n");
  bad_case c9 = {"wrong type: table expected", 0, NULL, NULL, GRAN_ERR_PARSE, 1, "key 'initial'", "expected a table"};
  check_case(&c9, "initial = 3\n[mixture]\ndensity = [0.1]\n[engine]\ncounts = [1]\nt_end = 1.0\n");
  bad_case c10 = {"missing [engine]", 0, NULL, NULL, GRAN_ERR_PARSE, 1, "key 'engine'", "missing"};
  check_case(&c10, "[mixture]\ndensity = [0.1]\n");
  /* viscoelastic restitution has no HCS: the default (and the explicit) "hcs" start is refused at load */
  bad_case c11 = {"viscoelastic with the HCS start", 0, NULL, NULL, GRAN_ERR_PARSE, 6, "initial.temperatures", "no homogeneous"};
  check_case(&c11, "[mixture]\ndensity = [0.1]\n[restitution]\nbeta = 0.1\n[initial]\ntemperatures = \"hcs\"\n[engine]\ncounts = [1]\nt_end = 1.0\n");
  bad_case c12 = {"viscoelastic without [initial]", 0, NULL, NULL, GRAN_ERR_PARSE, 1, "key 'initial'", "no homogeneous"};
  check_case(&c12, "[mixture]\ndensity = [0.1]\n[restitution]\nbeta = 0.1\n[engine]\ncounts = [1]\nt_end = 1.0\n");
  bad_case c8 = {"velocity_distribution bins", 0, NULL, NULL, GRAN_ERR_PARSE, 6, "observables.velocity_distribution.bins", "[1, 1e6]"};
  check_case(&c8, "[mixture]\ndensity = [0.1]\n[engine]\ncounts = [1]\n[observables]\nvelocity_distribution = { bins = 0 }\ntimes = [1.0]\n");
}

static void test_missing_file(void **state) {
  (void)state;
  gran_scene *s = NULL;
  GRAN_ASSERT_ERR(gran_scene_load("/nonexistent-dir/none.toml", &s), GRAN_ERR_IO);
  assert_non_null(strstr(gran_last_error_message(), "/nonexistent-dir/none.toml"));
  assert_null(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_table),
      cmocka_unit_test(test_by_hand),
      cmocka_unit_test(test_missing_file),
  };
  return cmocka_run_group_tests_name("t602-scene-errors", tests, NULL, NULL);
}
