/* t620-scene-keys.c - the key table of each engine (`granary keys --format markdown`, $GRAN_CLI) and
 * the scene parser agree both ways:
 *   - every key of the table is accepted: a scene of that engine with the key set parses, or is
 *     refused for its value or its context (the message names the key, never "unknown key");
 *   - every key the parser accepts is in the table: each table's "unknown key" message lists the
 *     keys the parser knows there, and each of them is a row of the table; a key not in the table
 *     is refused as unknown, in every table.
 * Also: the markdown form (one table per engine, the seven columns) and the text form. */
#include "granary_test.h"

#include <sys/wait.h>

#define MAXROWS 400
#define MAXLINES 64

/* dst = src, which must fit (a longer cell fails the test rather than being cut) */
static void copy_cell(char *dst, size_t size, const char *src) {
  const size_t n = strlen(src);
  assert_true(n < size);
  memcpy(dst, src, n + 1);
}

static const char *cli(void) {
  const char *c = getenv("GRAN_CLI");
  return c ? c : "build/granary";
}

/* runs cmd, its stdout into a new buffer; returns the exit status */
static int run_cmd(const char *cmd, char **out) {
  FILE *p = popen(cmd, "r");
  assert_non_null(p);
  size_t cap = 1 << 16, n = 0, got;
  char *b = malloc(cap);
  while ((got = fread(b + n, 1, cap - 1 - n, p)) > 0) {
    n += got;
    if (cap - 1 - n < 4096) b = realloc(b, cap *= 2);
  }
  b[n] = '\0';
  *out = b;
  const int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

typedef struct {
  char engine[16];
  char table[96], name[64], type[64], def[96];
} row;

static row rows[MAXROWS];
static int nrows;

/* strip spaces and backticks */
static void trim(char *s) {
  char *a = s;
  while (*a == ' ' || *a == '`') a++;
  size_t n = strlen(a);
  while (n > 0 && (a[n - 1] == ' ' || a[n - 1] == '`')) n--;
  memmove(s, a, n);
  s[n] = '\0';
}

/* the cells of a markdown row ("\|" is a literal bar); returns the count */
static int cells(const char *line, char out[][256], int max) {
  int n = -1;
  size_t k = 0;
  for (const char *p = line; *p && *p != '\n'; p++) {
    if (*p == '\\' && p[1] == '|') {
      if (n >= 0 && k < 255) out[n][k++] = '|';
      p++;
    } else if (*p == '|') {
      if (n >= 0) out[n][k] = '\0', trim(out[n]);
      if (++n >= max) return n;
      k = 0;
    } else if (n >= 0 && k < 255) {
      out[n][k++] = *p;
    }
  }
  return n;
}

static void load_table(void) {
  char cmd[1024], *md = NULL;
  snprintf(cmd, sizeof cmd, "%s keys --format markdown", cli());
  assert_int_equal(run_cmd(cmd, &md), 0);
  char engine[16] = "";
  int sections = 0;
  for (char *line = md; *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : line + strlen(line)) {
    if (!strncmp(line, "## ", 3)) {
      const char *t = strstr(line, "type = \"");
      assert_non_null(t);
      sscanf(t + 8, "%15[^\"]", engine);
      sections++;
      continue;
    }
    if (line[0] != '|') continue;
    char c[8][256];
    const int n = cells(line, c, 8);
    if (!strcmp(c[0], "key")) { /* the header: the seven columns, in this order */
      const char *want[7] = {"key", "type", "default", "bounds", "unit", "meaning", "C field"};
      assert_int_equal(n, 7);
      for (int i = 0; i < 7; i++) assert_string_equal(c[i], want[i]);
      continue;
    }
    if (!strncmp(c[0], "---", 3)) continue;
    assert_int_equal(n, 7);
    assert_true(nrows < MAXROWS);
    row *r = &rows[nrows++];
    copy_cell(r->engine, sizeof r->engine, engine);
    char *dot = strrchr(c[0], '.');
    if (dot) {
      *dot = '\0';
      copy_cell(r->table, sizeof r->table, c[0]);
      copy_cell(r->name, sizeof r->name, dot + 1);
    } else {
      r->table[0] = '\0';
      copy_cell(r->name, sizeof r->name, c[0]);
    }
    copy_cell(r->type, sizeof r->type, c[1]);
    copy_cell(r->def, sizeof r->def, c[2]);
    assert_true(strcmp(c[5], "-") != 0); /* every key has a meaning and a C field */
    assert_true(strcmp(c[6], "-") != 0);
  }
  free(md);
  assert_int_equal(sections, 2);
}

static const row *find_row(const char *engine, const char *table, const char *name) {
  for (int i = 0; i < nrows; i++)
    if (!strcmp(rows[i].engine, engine) && !strcmp(rows[i].table, table) && !strcmp(rows[i].name, name)) return &rows[i];
  return NULL;
}

/* ---- scenes as (table, line) pairs ---- */
typedef struct {
  int n;
  char table[MAXLINES][96];
  char line[MAXLINES][256];
} scene;

static void put(scene *s, const char *table, const char *line) {
  /* a line for a key the scene has already replaces it */
  size_t klen = strcspn(line, " =");
  for (int i = 0; i < s->n; i++)
    if (!strcmp(s->table[i], table) && !strncmp(s->line[i], line, klen) &&
        (s->line[i][klen] == ' ' || s->line[i][klen] == '=')) {
      snprintf(s->line[i], sizeof s->line[i], "%s", line);
      return;
    }
  assert_true(s->n < MAXLINES);
  snprintf(s->table[s->n], sizeof s->table[0], "%s", table);
  snprintf(s->line[s->n], sizeof s->line[0], "%s", line);
  s->n++;
}

static void base(scene *s, const char *engine) {
  s->n = 0;
  if (!strcmp(engine, "srd")) {
    put(s, "engine", "type = \"srd\"");
    put(s, "engine", "dimension = 2");
    put(s, "engine", "cells = 4");
    put(s, "engine", "steps = 10");
  } else {
    put(s, "mixture", "density = [0.1]");
    put(s, "engine", "counts = [10]");
    put(s, "engine", "t_end = 1.0");
  }
}

/* TOML text: top-level lines first, then each table in order of first use */
static char *text_of(const scene *s) {
  char *t = calloc(1, 32768);
  for (int i = 0; i < s->n; i++)
    if (!s->table[i][0]) strcat(t, s->line[i]), strcat(t, "\n");
  for (int i = 0; i < s->n; i++) {
    if (!s->table[i][0]) continue;
    int first = 1;
    for (int j = 0; j < i; j++)
      if (!strcmp(s->table[j], s->table[i])) first = 0;
    if (!first) continue;
    strcat(t, "[");
    strcat(t, s->table[i]);
    strcat(t, "]\n");
    for (int j = i; j < s->n; j++)
      if (!strcmp(s->table[j], s->table[i])) strcat(t, s->line[j]), strcat(t, "\n");
  }
  return t;
}

/* What a key needs besides itself to be valid ("table|line" pairs, one per string). */
typedef struct {
  const char *engine, *key;
  const char *lines[6];
} context;
static const context kContext[] = {
    {"dsmc", "mixture.mass", {"mixture|mass = [2.0]"}},
    {"dsmc", "mixture.sigma", {"mixture|sigma = [1.0]"}},
    {"dsmc", "mixture.density_law", {"-mixture|density", "mixture|density_law = {n1 = 0.1, theta = 1.0}",
                                     "mixture|nspecies = 2", "engine|counts = [10, 10]"}},
    {"dsmc", "mixture.g2_matrix", {"mixture|g2_matrix = [[1.0]]"}},
    {"dsmc", "mixture.density", {"mixture|density = [0.1]"}},
    {"dsmc", "restitution.eps_matrix", {"restitution|eps_matrix = [[0.5]]"}},
    {"dsmc", "restitution.beta", {"restitution|beta = 0.1", "initial|temperatures = \"equal\""}},
    {"dsmc", "restitution.beta_matrix", {"restitution|beta_matrix = [[0.1]]", "initial|temperatures = \"equal\""}},
    {"dsmc", "restitution.material", {"restitution|material = {A = 0.01, Y = 1.0, nu = 0.3}",
                                      "initial|temperatures = \"equal\""}},
    {"dsmc", "restitution.material.A", {"restitution.material|A = 0.01", "restitution.material|Y = 1.0",
                                        "restitution.material|nu = 0.3", "initial|temperatures = \"equal\""}},
    {"dsmc", "restitution.material.Y", {"restitution.material|A = 0.01", "restitution.material|Y = 1.0",
                                        "restitution.material|nu = 0.3", "initial|temperatures = \"equal\""}},
    {"dsmc", "restitution.material.nu", {"restitution.material|A = 0.01", "restitution.material|Y = 1.0",
                                         "restitution.material|nu = 0.3", "initial|temperatures = \"equal\""}},
    {"dsmc", "restitution.model", {"restitution|model = \"constant\""}},
    {"dsmc", "initial.temperatures", {"initial|temperatures = \"equal\""}},
    {"dsmc", "initial.T1", {"initial|T1 = 2.0"}},
    {"dsmc", "engine.selector", {"engine|selector = \"bird\""}},
    {"dsmc", "engine.counts", {"engine|counts = [10]"}},
    {"dsmc", "engine.N1", {"engine|N1 = 10"}},
    {"dsmc", "engine.volume", {"engine|volume = 100.0"}},
    {"dsmc", "engine.speed_classes", {"engine|speed_classes = false"}},
    {"dsmc", "cell", {"engine|selector = \"cell\"", "cell|dt = 0.01"}},
    {"dsmc", "aggregation", {"aggregation|e_agg = 0.1", "observables|msd = false"}},
    {"dsmc", "observables.times", {"observables|times = [0.5, 1.0]"}},
    {"dsmc", "observables.velocity_distribution", {"observables|velocity_distribution = true"}},
    {"dsmc", "observables.tamsd", {"observables|tamsd = {tracers = 2, dt = 0.1, samples = 5}"}},
    {"dsmc", "observables.tamsd.tracers", {"observables.tamsd|tracers = 2", "observables.tamsd|dt = 0.1",
                                           "observables.tamsd|samples = 5"}},
    {"dsmc", "observables.tamsd.dt", {"observables.tamsd|tracers = 2", "observables.tamsd|dt = 0.1",
                                      "observables.tamsd|samples = 5"}},
    {"dsmc", "observables.tamsd.samples", {"observables.tamsd|tracers = 2", "observables.tamsd|dt = 0.1",
                                           "observables.tamsd|samples = 5"}},
    {"dsmc", "observables.tamsd.lags", {"observables.tamsd|tracers = 2", "observables.tamsd|dt = 0.1",
                                        "observables.tamsd|samples = 5", "observables.tamsd|lags = [0.1, 0.2]"}},
    {"dsmc", "observables.theory_sonine", {"observables|theory_sonine = true"}},
    {"dsmc", "observables.sonine_order", {"observables|theory_sonine = true", "observables|sonine_order = 3"}},
    {"dsmc", "output.checkpoint", {"output|checkpoint = \"t620.ckpt\""}},
    {"dsmc", "output.path", {"output|path = \"t620.h5\""}},
    {"srd", "engine.type", {"engine|type = \"srd\""}},
    {"srd", "engine.cells", {"engine|cells = [4, 4]"}},
    {"srd", "engine.box", {"engine|box = [4.0, 4.0]"}},
    {"srd", "engine.n0", {"engine|n0 = 5"}},
    {"srd", "engine.particles_per_cell", {"engine|particles_per_cell = 5"}},
    {"srd", "engine.eps", {"engine|eps = 0.9", "engine|sigma = 0.05"}},
    {"srd", "engine.t_end", {"engine|t_end = 10.0"}},
    {"srd", "engine.thermostat", {"engine|thermostat = \"global\""}},
    {"srd", "boundaries", {"boundaries|lees_edwards = {shear_rate = 0.01}"}},
    {"srd", "boundaries.lees_edwards", {"boundaries|lees_edwards = {shear_rate = 0.01}"}},
    {"srd", "boundaries.lees_edwards.shear_rate", {"boundaries.lees_edwards|shear_rate = 0.01"}},
    {"srd", "boundaries.walls", {"boundaries|walls = {axis = \"y\"}"}},
    {"srd", "boundaries.walls.axis", {"boundaries.walls|axis = \"y\""}},
    {"srd", "boundaries.walls.rule", {"boundaries.walls|axis = \"y\"", "boundaries.walls|rule = \"slip\""}},
    {"srd", "boundaries.walls.T", {"boundaries.walls|axis = \"y\"", "boundaries.walls|T = 1.0"}},
    {"srd", "boundaries.vibrating_wall", {"boundaries|walls = {axis = \"y\"}",
                                          "boundaries|vibrating_wall = {amplitude = 0.1, omega = 0.1}"}},
    {"srd", "boundaries.vibrating_wall.amplitude", {"boundaries.walls|axis = \"y\"",
                                                    "boundaries.vibrating_wall|amplitude = 0.1",
                                                    "boundaries.vibrating_wall|omega = 0.1"}},
    {"srd", "boundaries.vibrating_wall.omega", {"boundaries.walls|axis = \"y\"",
                                                "boundaries.vibrating_wall|amplitude = 0.1",
                                                "boundaries.vibrating_wall|omega = 0.1"}},
    {"srd", "forces", {"forces|gravity = [0.0, -0.001]"}},
    {"srd", "forces.gravity", {"forces|gravity = [0.0, -0.001]"}},
    {"srd", "forces.body_force", {"forces|body_force = [0.001, 0.0]"}},
    {"srd", "observables.times", {"observables|times = [1.0, 10.0]"}},
    {"srd", "observables.stress", {"observables|stress = true", "boundaries.lees_edwards|shear_rate = 0.01"}},
    {"srd", "observables.structure_factor", {"observables|structure_factor = {bins = 2}"}},
    {"srd", "observables.snapshots", {"observables|snapshots = {every = 2}"}},
    {"srd", "observables.snapshots.times", {"observables.snapshots|times = [5.0]"}},
    {"srd", "observables.snapshots.every", {"observables.snapshots|every = 2"}},
};

static const context *context_of(const char *engine, const char *key) {
  for (size_t i = 0; i < sizeof kContext / sizeof kContext[0]; i++)
    if (!strcmp(kContext[i].engine, engine) && !strcmp(kContext[i].key, key)) return &kContext[i];
  return NULL;
}

/* "table|line" (replacing a line of that key), or "-table|key": the key removed */
static void put_pair(scene *s, const char *pair) {
  if (pair[0] == '-') {
    const char *bar = strchr(pair, '|');
    const size_t tl = (size_t)(bar - pair - 1), kl = strlen(bar + 1);
    for (int i = 0; i < s->n; i++)
      if (strlen(s->table[i]) == tl && !strncmp(s->table[i], pair + 1, tl) && !strncmp(s->line[i], bar + 1, kl) &&
          (s->line[i][kl] == ' ' || s->line[i][kl] == '=')) {
        for (int j = i + 1; j < s->n; j++) strcpy(s->table[j - 1], s->table[j]), strcpy(s->line[j - 1], s->line[j]);
        s->n--;
        return;
      }
    fail_msg("no line '%s' to remove", pair);
  }
  char t[96];
  const char *bar = strchr(pair, '|');
  assert_non_null(bar);
  snprintf(t, sizeof t, "%.*s", (int)(bar - pair), pair);
  put(s, t, bar + 1);
}

/* What every key of a table needs (the table reached by the parser and valid without the key). */
static void prereq(scene *s, const char *engine, const char *table) {
  if (!strcmp(engine, "dsmc") && !strcmp(table, "cell")) {
    put(s, "engine", "selector = \"cell\"");
    put(s, "cell", "dt = 0.01");
  }
  if (!strcmp(engine, "dsmc") && !strcmp(table, "mixture.density_law")) {
    put_pair(s, "-mixture|density");
    put(s, "mixture", "nspecies = 1");
    put(s, "mixture.density_law", "n1 = 0.1");
  }
}

/* a value of the key's documented type: its default where the table gives a plain one */
static void value_of(const row *r, char *out, size_t len) {
  const char *d = r->def;
  char *end = NULL;
  if (!strcmp(r->type, "boolean")) snprintf(out, len, "%s", !strcmp(d, "false") ? "false" : "true");
  else if (!strcmp(r->type, "string")) snprintf(out, len, "%s", d[0] == '"' ? d : "\"x\"");
  else if ((!strcmp(r->type, "float") || !strcmp(r->type, "integer")) && (strtod(d, &end), end != d && !*end))
    snprintf(out, len, "%s", d);
  else if (!strcmp(r->type, "float")) snprintf(out, len, "1.0");
  else if (!strcmp(r->type, "integer")) snprintf(out, len, "1");
  else snprintf(out, len, "{}"); /* tables */
}

/* Every row: a scene with the key parses, or is refused naming the key (not as unknown). */
static void test_every_key_is_accepted(void **state) {
  (void)state;
  int tried = 0, parsed = 0;
  for (int i = 0; i < nrows; i++) {
    const row *r = &rows[i];
    char key[192];
    snprintf(key, sizeof key, "%s%s%s", r->table, r->table[0] ? "." : "", r->name);
    scene s;
    base(&s, r->engine);
    prereq(&s, r->engine, r->table);
    const context *c = context_of(r->engine, key);
    if (c) {
      for (int j = 0; j < 6 && c->lines[j]; j++) put_pair(&s, c->lines[j]);
    } else if (!r->table[0] && strstr(r->type, "table")) {
      char hdr[160];
      snprintf(hdr, sizeof hdr, "%s|# (empty)", r->name);
      put_pair(&s, hdr);
    } else {
      char v[128], line[256];
      value_of(r, v, sizeof v);
      snprintf(line, sizeof line, "%s = %s", r->name, v);
      put(&s, r->table, line);
    }
    char *text = text_of(&s);
    gran_scene *sc = NULL;
    gran_clear_error();
    const int st = gran_scene_parse(text, "keys.toml", &sc);
    const char *msg = gran_last_error_message();
    char quoted[200];
    snprintf(quoted, sizeof quoted, "'%s'", key);
    if (st == GRAN_SUCCESS) {
      parsed++;
      gran_scene_destroy(&sc);
    } else if (strstr(msg, "unknown key") || strstr(msg, "not declared") || !strstr(msg, key)) {
      /* refused: for the key's value or context, naming it */
      fail_msg("engine %s, key %s: refused as not accepted: %s\n%s", r->engine, key, msg, text);
    }
    (void)quoted;
    free(text);
    tried++;
  }
  assert_true(tried == nrows);
  assert_true(tried >= 100);
  assert_true(parsed >= tried * 9 / 10); /* nearly every key with a plain value makes a valid scene */
}

/* The parser's known keys of every table (from its "unknown key" message) are rows of the table;
 * a key not in the table is refused in every table. */
static void check_table(const char *engine, const char *where) {
  scene s;
  base(&s, engine);
  prereq(&s, engine, where);
  char pair[256];
  snprintf(pair, sizeof pair, "%s|zz_not_a_key = 1", where);
  put_pair(&s, pair);
  char *text = text_of(&s);
  gran_scene *sc = NULL;
  gran_clear_error();
  assert_int_equal(gran_scene_parse(text, "keys.toml", &sc), GRAN_ERR_PARSE);
  const char *msg = gran_last_error_message();
  char want[256];
  snprintf(want, sizeof want, "key '%s%szz_not_a_key': unknown key", where, where[0] ? "." : "");
  if (!strstr(msg, want)) fail_msg("engine %s, table '%s': %s\n%s", engine, where, msg, text);
  const char *known = strstr(msg, "(known keys here: ");
  assert_non_null(known);
  char list[2048];
  snprintf(list, sizeof list, "%s", known + strlen("(known keys here: "));
  char *close = strrchr(list, ')');
  assert_non_null(close);
  *close = '\0';
  int nknown = 0;
  for (char *k = strtok(list, ", "); k; k = strtok(NULL, ", ")) {
    if (!find_row(engine, where, k))
      fail_msg("engine %s: the parser accepts '%s' in table '%s', the key table has no such row", engine, k, where);
    nknown++;
  }
  /* and the key table has no row there that the parser does not know */
  int nrow = 0;
  for (int j = 0; j < nrows; j++)
    if (!strcmp(rows[j].engine, engine) && !strcmp(rows[j].table, where)) nrow++;
  assert_int_equal(nknown, nrow);
  free(text);
}

static void test_every_accepted_key_is_in_table(void **state) {
  (void)state;
  int tables = 0;
  for (int i = 0; i < nrows; i++) {
    const row *r = &rows[i];
    if (i == 0 || strcmp(rows[i - 1].engine, r->engine)) check_table(r->engine, ""), tables++;
    if (!strstr(r->type, "table")) continue;
    char path[192];
    snprintf(path, sizeof path, "%s%s%s", r->table, r->table[0] ? "." : "", r->name);
    check_table(r->engine, path);
    tables++;
  }
  assert_true(tables >= 20);
}

static void test_text_form(void **state) {
  (void)state;
  char cmd[1024], *out = NULL;
  snprintf(cmd, sizeof cmd, "%s keys srd", cli());
  assert_int_equal(run_cmd(cmd, &out), 0);
  assert_non_null(strstr(out, "GSRD"));
  assert_non_null(strstr(out, "engine.alpha"));
  assert_non_null(strstr(out, "(0, 180]"));
  assert_null(strstr(out, "mixture.nspecies")); /* one engine only */
  free(out);
  snprintf(cmd, sizeof cmd, "%s keys nosuchengine 2>/dev/null", cli());
  assert_int_equal(run_cmd(cmd, &out), 2);
  free(out);
  snprintf(cmd, sizeof cmd, "%s keys --format html 2>/dev/null", cli());
  assert_int_equal(run_cmd(cmd, &out), 2);
  free(out);
}

static int setup(void **state) {
  (void)state;
  load_table();
  return 0;
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_every_key_is_accepted),
      cmocka_unit_test(test_every_accepted_key_is_in_table),
      cmocka_unit_test(test_text_form),
  };
  return cmocka_run_group_tests_name("t620-scene-keys", tests, setup, NULL);
}
