/* xoshiro.h - the xoshiro256** step (Blackman & Vigna) and the uniform, normal and sphere draws on a
 * gran_rng, in plain C that compiles as C99, C++ and CUDA (GRAN_HD): the one definition behind the
 * core's RNG (src/granary_impl.h: gran::rng_*), the GSRD kernels (src/srd/srd_kernels.h) and the
 * CUDA kernels, so that the CPU and the GPU draw the same bits. */
#ifndef GRANARY_XOSHIRO_H
#define GRANARY_XOSHIRO_H

#include <math.h>
#include <stdint.h>

#include "granary.h" /* gran_rng: a POD of four uint64_t */

#ifndef GRAN_HD
#if defined(__CUDACC__)
#define GRAN_HD __host__ __device__
#else
#define GRAN_HD
#endif
#endif

GRAN_HD static inline uint64_t gran_xo_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

/* xoshiro256** 1.0 */
GRAN_HD static inline uint64_t gran_xo_next(gran_rng *r) {
  uint64_t *s = r->s;
  const uint64_t result = gran_xo_rotl(s[1] * 5, 7) * 9;
  const uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = gran_xo_rotl(s[3], 45);
  return result;
}

/* uniform in [0,1): top 53 bits */
GRAN_HD static inline double gran_xo_uniform(gran_rng *r) { return (double)(gran_xo_next(r) >> 11) * 0x1.0p-53; }
/* uniform in (0,1] */
GRAN_HD static inline double gran_xo_uniform_pos(gran_rng *r) {
  return ((double)(gran_xo_next(r) >> 11) + 1.0) * 0x1.0p-53;
}

/* Standard normal by the polar (Marsaglia) method, one deviate per call (the second is discarded,
 * so the four state words describe the stream completely). */
GRAN_HD static inline double gran_xo_normal(gran_rng *r) {
  double u, v, s;
  do {
    u = 2.0 * gran_xo_uniform(r) - 1.0;
    v = 2.0 * gran_xo_uniform(r) - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  return u * sqrt(-2.0 * log(s) / s);
}

/* Uniform direction on the unit sphere (Marsaglia 1972). */
GRAN_HD static inline void gran_xo_unit3(gran_rng *r, double e[3]) {
  double u, v, s;
  do {
    u = 2.0 * gran_xo_uniform(r) - 1.0;
    v = 2.0 * gran_xo_uniform(r) - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0);
  const double f = 2.0 * sqrt(1.0 - s);
  e[0] = u * f;
  e[1] = v * f;
  e[2] = 1.0 - 2.0 * s;
}

#endif
