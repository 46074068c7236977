/* fuzz_scene.c - libFuzzer harness for the scene parser (gran_scene_parse) and what a run derives
 * from a scene before it allocates an engine (mixture, initial temperatures, engine options).
 * Build and run: make fuzz (see README). Every input must end in GRAN_SUCCESS or a named error. */
#include <stdlib.h>
#include <string.h>

#include "granary.h"

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size) {
  char *text = malloc(size + 1);
  if (!text) return 0;
  memcpy(text, data, size);
  text[size] = '\0';
  gran_scene *s = NULL;
  int st = gran_scene_parse(text, "fuzz.toml", &s);
  if (st != GRAN_SUCCESS && gran_last_error_message()[0] == '\0') abort(); /* an error must say why */
  if (st == GRAN_SUCCESS) {
    int64_t M = 0, nt = 0, nl = 0;
    double t0, t1;
    gran_scene_sizes(s, &M, &nt, &nl, &t0, &t1);
    gran_mixture *mix = NULL;
    if (M <= 4096 && gran_scene_mixture(s, &mix) == GRAN_SUCCESS) {
      double *T0 = malloc(sizeof(double) * (size_t)M);
      double tau0;
      gran_dsmc_options opt;
      if (T0) gran_scene_initial_temperatures(s, mix, T0, &tau0);
      gran_scene_dsmc_options(s, &opt, NULL, NULL);
      free(T0);
      gran_mixture_destroy(&mix);
    }
    gran_scene_destroy(&s);
  }
  free(text);
  return 0;
}
