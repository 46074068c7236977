/* exactsum.h - exact, order-independent summation of doubles: a fixed-point superaccumulator over
 * the whole double range (R. M. Neal, "Fast exact summation using small and large
 * superaccumulators", arXiv:1505.05571, the small one). The sum is held exactly as 68 signed limbs
 * of 32 bits each (limb j weighs 2^(32 j - 1074)) in int64 words, so that a limb absorbs up to 2^30
 * adds before its carries are propagated (deferred carries). Any order and any grouping of adds,
 * and merging accumulators, give the same state after normalisation and so the same bits;
 * gran_exactsum_value_ rounds the exact sum once, to nearest, ties to even. Inf and NaN inputs
 * are counted: the value is then what IEEE addition gives (NaN for a NaN or for +inf and -inf,
 * else the infinity); a finite sum beyond DBL_MAX gives +-inf. The sum of nothing but -0 (at
 * least one) is -0, any other exact zero +0. Plain data (a fixed array of int64, 584 B): it can be
 * copied, written or sent (MPI_INT64_T x 73) and merged elsewhere. Plain C, callable from C tests. */
#ifndef GRAN_EXACTSUM_H
#define GRAN_EXACTSUM_H

#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { GRAN_EXACTSUM_LIMBS = 68, GRAN_EXACTSUM_DEFER = 1 << 30 };

typedef struct gran_exactsum {
  int64_t limb[GRAN_EXACTSUM_LIMBS]; /* limb j: weight 2^(32 j - 1074); normalised: 0 <= limb < 2^32
                                        below the top one, which carries the sign */
  int64_t pending;                   /* adds since the last normalisation (<= GRAN_EXACTSUM_DEFER) */
  int64_t pinf, ninf, nan;           /* +inf, -inf and NaN inputs */
  int64_t nonneg;                    /* inputs other than -0 (0 with inputs: the sum is -0) */
  int64_t n;                         /* inputs */
} gran_exactsum;

static inline void gran_exactsum_init_(gran_exactsum *a) { memset(a, 0, sizeof *a); }

/* carries propagated: limbs 0 .. 66 in [0, 2^32), the top limb signed */
void gran_exactsum_normalize_(gran_exactsum *a);

static inline void gran_exactsum_add_(gran_exactsum *a, double x) {
  uint64_t u;
  memcpy(&u, &x, sizeof u);
  const int neg = (int)(u >> 63);
  const int E = (int)((u >> 52) & 0x7ff);
  const uint64_t frac = u & ((UINT64_C(1) << 52) - 1);
  a->n++;
  if (!(neg && E == 0 && frac == 0)) a->nonneg++;
  if (E == 0x7ff) {
    if (frac) a->nan++;
    else if (neg) a->ninf++;
    else a->pinf++;
    return;
  }
  if (E == 0 && frac == 0) return;
  const uint64_t m = E ? frac | (UINT64_C(1) << 52) : frac;
  const int p = E ? E - 1 : 0; /* x = m 2^(p - 1074) */
  const int j = p >> 5;
  const unsigned __int128 v = (unsigned __int128)m << (p & 31); /* < 2^84: three limbs */
  const int64_t l0 = (int64_t)(uint32_t)v, l1 = (int64_t)(uint32_t)(v >> 32), l2 = (int64_t)(uint32_t)(v >> 64);
  if (neg) {
    a->limb[j] -= l0;
    a->limb[j + 1] -= l1;
    a->limb[j + 2] -= l2;
  } else {
    a->limb[j] += l0;
    a->limb[j + 1] += l1;
    a->limb[j + 2] += l2;
  }
  if (++a->pending >= GRAN_EXACTSUM_DEFER) gran_exactsum_normalize_(a);
}

/* a += b (exact; b unchanged) */
void gran_exactsum_merge_(gran_exactsum *a, const gran_exactsum *b);
/* the exact sum rounded to the nearest double (ties to even); a is normalised, its value unchanged */
double gran_exactsum_value_(gran_exactsum *a);

#ifdef __cplusplus
}
#endif

#endif
