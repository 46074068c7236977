/* json_test_util.h - a small JSON parser (RFC 8259 values) for the tests of `granary theory --json`
 * and `sh`, which runs a command and captures its output (the same as those of t605-cli.c). */
#ifndef GRANARY_JSON_TEST_UTIL_H
#define GRANARY_JSON_TEST_UTIL_H
#include <ctype.h>
#include <sys/wait.h>

#include "granary_test.h"

/* runs a shell command, captures stdout (and stderr when merge), returns the exit status */
static inline int sh(const char *cmd, char *out, size_t len, int merge) {
  char full[4096];
  const int w = snprintf(full, sizeof full, "%s%s", cmd, merge ? " 2>&1" : " 2>/dev/null");
  if (w < 0 || (size_t)w >= sizeof full) fail_msg("command longer than %zu bytes: %.80s...", sizeof full, cmd);
  FILE *p = popen(full, "r");
  if (!p) return -1;
  size_t n = 0;
  if (out && len) {
    size_t got;
    while (n + 1 < len && (got = fread(out + n, 1, len - 1 - n, p)) > 0) n += got;
    out[n] = '\0';
  } else {
    char buf[4096];
    while (fread(buf, 1, sizeof buf, p) > 0) {
    }
  }
  int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

typedef struct jv {
  int type; /* 0 null, 1 bool, 2 number, 3 string, 4 array, 5 object */
  double num;
  char *str;
  int n;
  struct jv *items; /* array items / object values */
  char **keys;
} jv;

static const char *jp;
static int jerr;

static inline void jws(void) {
  while (*jp == ' ' || *jp == '\n' || *jp == '\t' || *jp == '\r') jp++;
}

static inline char *jstring(void) {
  if (*jp != '"') {
    jerr = 1;
    return NULL;
  }
  jp++;
  size_t cap = 64, n = 0;
  char *s = malloc(cap);
  while (*jp && *jp != '"') {
    char c = *jp++;
    if ((unsigned char)c < 0x20) jerr = 1;
    if (c == '\\') {
      char e = *jp++;
      if (e == 'u') {
        for (int i = 0; i < 4; i++)
          if (!isxdigit((unsigned char)*jp++)) jerr = 1;
        c = '?';
      } else if (strchr("\"\\/bfnrt", e)) {
        c = e == 'n' ? '\n' : e == 't' ? '\t' : e;
      } else {
        jerr = 1;
      }
    }
    if (n + 2 > cap) s = realloc(s, cap *= 2);
    s[n++] = c;
  }
  if (*jp != '"') jerr = 1;
  else jp++;
  s[n] = '\0';
  return s;
}

static inline void jparse(jv *v) {
  memset(v, 0, sizeof *v);
  jws();
  if (*jp == '{' || *jp == '[') {
    int obj = *jp == '{';
    v->type = obj ? 5 : 4;
    jp++;
    jws();
    char close = obj ? '}' : ']';
    if (*jp == close) {
      jp++;
      return;
    }
    for (;;) {
      v->items = realloc(v->items, sizeof(jv) * (size_t)(v->n + 1));
      v->keys = realloc(v->keys, sizeof(char *) * (size_t)(v->n + 1));
      v->keys[v->n] = NULL;
      if (obj) {
        jws();
        v->keys[v->n] = jstring();
        jws();
        if (*jp != ':') {
          jerr = 1;
          return;
        }
        jp++;
      }
      jparse(&v->items[v->n]);
      v->n++;
      if (jerr) return;
      jws();
      if (*jp == ',') {
        jp++;
        continue;
      }
      if (*jp == close) {
        jp++;
        return;
      }
      jerr = 1;
      return;
    }
  } else if (*jp == '"') {
    v->type = 3;
    v->str = jstring();
  } else if (!strncmp(jp, "null", 4)) {
    v->type = 0;
    jp += 4;
  } else if (!strncmp(jp, "true", 4) || !strncmp(jp, "false", 5)) {
    v->type = 1;
    v->num = *jp == 't';
    jp += *jp == 't' ? 4 : 5;
  } else {
    /* JSON number grammar: -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)? */
    const char *s = jp;
    if (*jp == '-') jp++;
    if (*jp == '0') jp++;
    else if (isdigit((unsigned char)*jp)) while (isdigit((unsigned char)*jp)) jp++;
    else jerr = 1;
    if (*jp == '.') {
      jp++;
      if (!isdigit((unsigned char)*jp)) jerr = 1;
      while (isdigit((unsigned char)*jp)) jp++;
    }
    if (*jp == 'e' || *jp == 'E') {
      jp++;
      if (*jp == '+' || *jp == '-') jp++;
      if (!isdigit((unsigned char)*jp)) jerr = 1;
      while (isdigit((unsigned char)*jp)) jp++;
    }
    v->type = 2;
    v->num = strtod(s, NULL);
  }
}

static inline int json_parse(const char *text, jv *root) {
  jp = text;
  jerr = 0;
  jparse(root);
  jws();
  return !jerr && *jp == '\0';
}

static inline const jv *jget(const jv *o, const char *key) {
  if (!o || o->type != 5) return NULL;
  for (int i = 0; i < o->n; i++)
    if (o->keys[i] && !strcmp(o->keys[i], key)) return &o->items[i];
  return NULL;
}

static inline double jnum(const jv *v) {
  if (!v || v->type != 2) fail_msg("expected a JSON number");
  return v->num;
}

static inline void jfree(jv *v) {
  for (int i = 0; i < v->n; i++) {
    jfree(&v->items[i]);
    free(v->keys[i]);
  }
  free(v->items);
  free(v->keys);
  free(v->str);
}

/* element i of a JSON array (NULL when not an array or out of range) */
static inline const jv *jat(const jv *a, int i) {
  if (!a || a->type != 4 || i < 0 || i >= a->n) return NULL;
  return &a->items[i];
}

#endif
