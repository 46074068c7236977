/* fuzz_resume.c - libFuzzer harness for the entry points that read files: the input is written to
 * a file and handed to gran_scene_resume (a checkpoint), gran_scene_load (a scene file) and
 * gran_srd_checkpoint_read (a GSRD checkpoint; one step is run from what it accepts). A resumed
 * run is stopped at its first output time. Every input must
 * end in GRAN_SUCCESS or a named error, without a crash, a hang or unbounded memory. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "granary.h"

static char dir[64];

static int stop_now(const gran_run_progress *p, void *params) {
  (void)p, (void)params;
  return 1;
}

int LLVMFuzzerTestOneInput(const unsigned char *data, size_t size) {
  if (!dir[0]) {
    snprintf(dir, sizeof dir, "/tmp/granary-fuzz-XXXXXX");
    if (!mkdtemp(dir)) abort();
  }
  char in[128], out[128];
  snprintf(in, sizeof in, "%s/in.ckpt", dir);
  snprintf(out, sizeof out, "%s/out.h5", dir);
  FILE *f = fopen(in, "wb");
  if (!f) abort();
  fwrite(data, 1, size, f);
  fclose(f);
  gran_run_control ctl = {0, stop_now, NULL};
  int st = gran_scene_resume(in, out, &ctl, NULL);
  if (st != GRAN_SUCCESS && gran_last_error_message()[0] == '\0') abort();
  gran_scene *s = NULL;
  st = gran_scene_load(in, &s);
  if (st != GRAN_SUCCESS && gran_last_error_message()[0] == '\0') abort();
  gran_scene_destroy(&s);
  gran_srd *srd = NULL;
  st = gran_srd_checkpoint_read(in, "/srd", &srd);
  if (st != GRAN_SUCCESS && gran_last_error_message()[0] == '\0') abort();
  if (st == GRAN_SUCCESS && gran_srd_advance(srd, 1) != GRAN_SUCCESS && gran_last_error_message()[0] == '\0') abort();
  gran_srd_destroy(&srd);
  remove(out);
  return 0;
}
