/* fuzz_scene_set.c - libFuzzer harness for gran_scene_set (`granary run --set KEY=VALUE`): the input
 * is "KEY=VALUE" (first line; the first byte's low bit picks a DSMC or a GSRD base scene), applied to
 * a valid scene. Every input must end in GRAN_SUCCESS or a named error; a refused override leaves
 * the scene's text as it was; an accepted one leaves a text that parses again to the same text. */
#include <stdlib.h>
#include <string.h>

#include "granary.h"

static const char *kDsmc =
    "[mixture]\nnspecies = 2\nmass = [1.0, 4.0]\ndensity = [0.1, 0.02]\n[restitution]\neps = 0.8\n"
    "[engine]\nselector = \"lowrank\"\ncounts = [200, 40]\nseed = 3\nt_end = 5.0\n[observables]\ntimes = [1.0, 5.0]\n"
    "[output]\npath = \"fuzz.h5\"\n";
static const char *kSrd =
    "[engine]\ntype = \"srd\"\ndimension = 2\ncells = [8, 8]\nn0 = 5\ndt = 0.5\nsteps = 10\n[observables]\nevery = 5\n"
    "[output]\npath = \"fuzz.h5\"\n";

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size) {
  if (size < 1 || size > 4096) return 0;
  const char *base = (data[0] & 1) ? kSrd : kDsmc;
  char *in = malloc(size);
  if (!in) return 0;
  memcpy(in, data + 1, size - 1);
  in[size - 1] = '\0';
  char *nl = strchr(in, '\n');
  if (nl) *nl = '\0';
  char *eq = strchr(in, '=');
  if (!eq) {
    free(in);
    return 0;
  }
  *eq = '\0';
  gran_scene *s = NULL;
  if (gran_scene_parse(base, "base.toml", &s) != GRAN_SUCCESS) abort(); /* the base scenes are valid */
  const char *t0 = NULL;
  gran_scene_text(s, &t0);
  char *before = strdup(t0 ? t0 : "");
  const int st = gran_scene_set(s, in, eq + 1);
  const char *t1 = NULL;
  gran_scene_text(s, &t1);
  if (st != GRAN_SUCCESS) {
    if (gran_last_error_message()[0] == '\0') abort();  /* an error must say why */
    if (!t1 || strcmp(before, t1) != 0) abort();        /* and leave the scene as it was */
  } else {
    gran_scene *r = NULL; /* the edited text is a scene of its own */
    if (gran_scene_parse(t1, "set.toml", &r) != GRAN_SUCCESS) abort();
    const char *t2 = NULL;
    gran_scene_text(r, &t2);
    if (!t2 || strcmp(t1, t2) != 0) abort();
    gran_scene_destroy(&r);
  }
  free(before);
  gran_scene_destroy(&s);
  free(in);
  return 0;
}
