/* io_tiny_scene.h - the small scene the io tests run (about 1e4 collisions: well under a second,
 * also under ASan). Every observable is on. %s slots: selector, output path. */
#ifndef GRANARY_IO_TINY_SCENE_H
#define GRANARY_IO_TINY_SCENE_H

#define IO_TINY_NT 8 /* output times */
#define IO_TINY_M 2  /* species */

static const char *kTinyFmt =
    "title = \"tiny\"\n"
    "[mixture]\n"
    "nspecies = 2\n"
    "mass = [1.0, 4.0]\n"
    "density = [0.1, 0.02]\n"
    "[restitution]\n"
    "eps = 0.8\n"
    "[initial]\n"
    "temperatures = \"hcs\"\n"
    "[engine]\n"
    "selector = \"%s\"\n"
    "counts = [2000, 400]\n"
    "seed = 11\n"
    "t_end = 20.0\n"
    "[observables]\n"
    "times = { log = { start = 0.1, stop = 20.0, n = 8 } }\n"
    "temperatures = true\n"
    "msd = true\n"
    "energy = true\n"
    "momentum = true\n"
    "collision_counts = true\n"
    "sonine_a2 = true\n"
    "velocity_distribution = { bins = 8, cmax = 3.0 }\n"
    "tamsd = { tracers = 5, dt = 0.5, samples = 21, lags = [0.5, 1.0, 5.0] }\n"
    "[output]\n"
    "path = \"%s\"\n"
    "checkpoint_every = 2\n";

static inline char *io_tiny_text(const char *selector, const char *out) {
  static char buf[4096];
  snprintf(buf, sizeof buf, kTinyFmt, selector, out);
  return buf;
}

#endif
