/* exactsum.cpp - normalisation, merge and the correctly rounded value of the exact accumulator
 * (src/core/exactsum.h). */
#include "core/exactsum.h"

#include <cmath>

namespace {

constexpr int kL = GRAN_EXACTSUM_LIMBS;

/* bit b (0 = weight 2^-1074) of a normalised non-negative accumulator */
inline unsigned bit_of(const int64_t *l, int b) { return (unsigned)((uint64_t)l[b >> 5] >> (b & 31)) & 1u; }

/* any bit below b set */
bool sticky_below(const int64_t *l, int b) {
  if (b <= 0) return false;
  const int j = b >> 5;
  for (int i = 0; i < j; ++i)
    if (l[i] != 0) return true;
  const uint64_t mask = (UINT64_C(1) << (b & 31)) - 1;
  return ((uint64_t)l[j] & mask) != 0;
}

} // namespace

extern "C" void gran_exactsum_normalize_(gran_exactsum *a) {
  int64_t carry = 0;
  for (int j = 0; j < kL - 1; ++j) {
    const int64_t v = a->limb[j] + carry;
    a->limb[j] = v & INT64_C(0xffffffff);
    carry = v >> 32; /* arithmetic: floor(v / 2^32) */
  }
  a->limb[kL - 1] += carry;
  a->pending = 0;
}

extern "C" void gran_exactsum_merge_(gran_exactsum *a, const gran_exactsum *b) {
  /* both at most GRAN_EXACTSUM_DEFER adds from normalised: |limb| < 2^62 + 2^32 each, the sum fits */
  gran_exactsum_normalize_(a);
  for (int j = 0; j < kL; ++j) a->limb[j] += b->limb[j];
  a->pending = GRAN_EXACTSUM_DEFER - 1;
  gran_exactsum_normalize_(a);
  a->pinf += b->pinf;
  a->ninf += b->ninf;
  a->nan += b->nan;
  a->nonneg += b->nonneg;
  a->n += b->n;
}

extern "C" double gran_exactsum_value_(gran_exactsum *a) {
  if (a->nan || (a->pinf && a->ninf)) return std::nan("");
  if (a->pinf) return HUGE_VAL;
  if (a->ninf) return -HUGE_VAL;
  gran_exactsum_normalize_(a);
  int64_t m[kL];
  bool neg = a->limb[kL - 1] < 0;
  if (neg) { /* the magnitude: -sum, normalised again */
    gran_exactsum t;
    for (int j = 0; j < kL; ++j) t.limb[j] = -a->limb[j];
    gran_exactsum_normalize_(&t);
    for (int j = 0; j < kL; ++j) m[j] = t.limb[j];
  } else {
    for (int j = 0; j < kL; ++j) m[j] = a->limb[j];
  }
  int h = kL - 1;
  while (h >= 0 && m[h] == 0) --h;
  if (h < 0) return (a->n > 0 && a->nonneg == 0) ? -0.0 : 0.0;
  /* the top limb of a magnitude is < 2^32 too (|sum| < 2^64 x 2^1024) */
  const int msb = 32 * h + 63 - __builtin_clzll((unsigned long long)m[h]);
  const int lsb = msb - 52 > 0 ? msb - 52 : 0; /* the result's last bit (subnormals: bit 0) */
  uint64_t mant = 0;
  for (int b = msb; b >= lsb; --b) mant = (mant << 1) | bit_of(m, b);
  if (lsb > 0 && bit_of(m, lsb - 1) && (sticky_below(m, lsb - 1) || (mant & 1u))) ++mant;
  /* mant <= 2^53 (a carry out of 53 bits stays exact: ldexp of 2^53 is exact or overflows) */
  const double r = std::ldexp((double)mant, lsb - 1074);
  return neg ? -r : r;
}
