/* keyed.h - keyed generators and the multinomial split of a count down a binary tree: the random
 * numbers of a decomposable run, whose draws must not depend on who makes them (a thread, a rank).
 *
 * The generator of (seed, tag, id) is xoshiro256** seeded with the four words
 * splitmix64(b + (4 id + w + 1) G), w = 0..3, b = splitmix64's mix of (seed xor tag), G the
 * golden-ratio increment. For one seed and tag all 4 x ids words are distinct (G is odd, the mix a
 * bijection), so no two generators start in the same state; they are points of the one cycle of
 * length 2^256 - 1, and M generators of at most D draws overlap with probability below
 * M^2 D / 2^256 (1e-47 for 1e12 generators of 1e3 draws), the argument for any two seeds. A tag
 * separates the uses (GSRD's creation: nodes, cells; the cell DSMC: creation, collisions, bath).
 *
 * The split: a count c at node id covering leaves [nlo, nhi) sends a binomial share
 * B(c, (mid - nlo) / (nhi - nlo)) to its left child [nlo, mid), mid = nlo + (nhi - nlo) / 2
 * (root id 1, children 2 id and 2 id + 1), drawn by gsl_ran_binomial from the node's keyed
 * generator: the leaves' counts are a multinomial sample with equal probabilities, and any range
 * of leaves is computed by visiting only its subtrees and the path above them. */
#ifndef GRANARY_CORE_KEYED_H
#define GRANARY_CORE_KEYED_H

#include "core/xoshiro.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include <stdint.h>

namespace gran {

constexpr uint64_t kKeyedGolden = 0x9e3779b97f4a7c15ULL;

inline uint64_t keyed_mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
inline void keyed_rng(uint64_t seed, uint64_t tag, uint64_t id, gran_rng *r) {
  const uint64_t b = keyed_mix64(seed ^ tag);
  for (uint64_t w = 0; w < 4; ++w) r->s[w] = keyed_mix64(b + (4 * id + w + 1) * kKeyedGolden);
}

/* GSL's view of a gran_rng (keyed.cpp): gsl_ran_binomial draws through gsl_rng_uniform (get_double:
 * the 53-bit uniform); get gives the top 32 bits. Seeding is ours (set does nothing). */
extern const gsl_rng_type kKeyedGslType;

/* The counts of the leaves of node (id, [nlo, nhi), c) that lie in [lo, hi): leaf(i, count) for
 * each, in leaf order. kSkipEmpty: subtrees with count 0 are not visited (their leaves get no call),
 * so a sparse split costs O(c log(nhi - nlo)). */
template <bool kSkipEmpty, class Leaf>
void keyed_split(uint64_t seed, uint64_t tag, uint64_t id, int64_t nlo, int64_t nhi, int64_t c, int64_t lo,
                 int64_t hi, const Leaf &leaf) {
  if (nhi <= lo || nlo >= hi) return;
  if (kSkipEmpty && c == 0) return;
  if (nhi - nlo == 1) {
    leaf(nlo, c);
    return;
  }
  const int64_t mid = nlo + (nhi - nlo) / 2;
  int64_t left = 0;
  if (c > 0) {
    gran_rng r;
    keyed_rng(seed, tag, id, &r);
    gsl_rng g;
    g.type = &kKeyedGslType;
    g.state = &r;
    left = (int64_t)gsl_ran_binomial(&g, (double)(mid - nlo) / (double)(nhi - nlo), (unsigned int)c);
  }
  keyed_split<kSkipEmpty>(seed, tag, 2 * id, nlo, mid, left, lo, hi, leaf);
  keyed_split<kSkipEmpty>(seed, tag, 2 * id + 1, mid, nhi, c - left, lo, hi, leaf);
}

}  // namespace gran

#endif
