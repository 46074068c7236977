/* rng.cpp - public RNG functions: seeding, jumps, reproducible streams, batch draws.
 *
 * Why xoshiro256** (Blackman & Vigna 2021): period 2^256 - 1, passes BigCrush and PractRand, four
 * 64-bit words of state (a POD that Fortran bind(C) types and CUDA kernels hold by value, and that
 * checkpoints store as four integers), sub-ns per draw, and linear over GF(2), so jumps of any
 * length are polynomials in the transition matrix: jump() = 2^128 steps, long_jump() = 2^192.
 * The draws themselves are the inline core in granary_impl.h (hot loops call it directly); the
 * functions here wrap it for batches, for Fortran and for tests.
 *
 * Streams. gran_rng_stream(seed, id) = gran_rng_seed(seed) advanced by id * 2^128 steps, i.e. the
 * state after `id` calls of gran_rng_jump(). Stream id is therefore the id-th consecutive block of
 * length 2^128 of the one period-2^256 sequence that starts at the seeded state: two streams of
 * the same seed are disjoint unless one of them draws more than 2^128 numbers (never, in
 * practice: 10^9 draws/s for 10^20 years), and all 2^64 ids fit in the period (2^192 < 2^256).
 * Different seeds start at splitmix64-scrambled points of the cycle; blocks of two seeds overlap
 * with probability ~ (total draws) * 2^-256 per pair. Advancing by id * 2^128 costs O(log id):
 * with P the characteristic polynomial of the transition matrix T (degree 256, found once by
 * Berlekamp-Massey from 512 output bits), J_k = x^(2^(128+k)) mod P is the jump by 2^(128+k)
 * steps; J_0 is Vigna's JUMP constant and J_(k+1) = J_k^2 mod P, so a stream applies one J_k per
 * set bit of id (<= 64 polynomial applications of 256 steps each, a few microseconds at most).
 * Squaring J_63 once more must give Vigna's LONG_JUMP constant: the table is checked against
 * both published constants when it is built, so a wrong P or a wrong squaring cannot go unnoticed.
 * Hashing (seed, id) through splitmix64 would be cheaper but gives only a probabilistic argument;
 * the jump construction makes non-overlap a property of the arithmetic.
 */
#include "granary_impl.h"

#include <cmath>
#include <vector>

namespace {

/* Vigna's published jump polynomials (xoshiro256starstar.c): x^(2^128) and x^(2^192) mod P,
 * bit j of the 256-bit number (word j/64, bit j%64) = coefficient of x^j. */
const uint64_t kJump[4] = {0x180ec6d33cfd0abaULL, 0xd5a61266f0c9392cULL, 0xa9582618e03fc9aaULL,
                           0x39abdc4529b1661cULL};
const uint64_t kLongJump[4] = {0x76e15d3efefdcbbfULL, 0xc5004e441c522fb3ULL, 0x77710069854ee241ULL,
                               0x39109bb02acbe635ULL};

/* s <- poly(T) s: Horner-free form of Vigna's jump (sum of the states selected by the bits). */
void apply_poly(gran_rng *rng, const uint64_t poly[4]) {
  uint64_t acc[4] = {0, 0, 0, 0};
  for (int i = 0; i < 4; i++)
    for (int b = 0; b < 64; b++) {
      if (poly[i] & (UINT64_C(1) << b))
        for (int w = 0; w < 4; w++) acc[w] ^= rng->s[w];
      gran::rng_next(rng);
    }
  for (int w = 0; w < 4; w++) rng->s[w] = acc[w];
}

/* ---- GF(2) polynomials of degree < 256 modulo P = x^256 + low(x), low of degree < 256 ------- */
struct Poly {
  uint64_t w[4];
};

/* a^2 mod P. Squaring over GF(2) spreads bit j to bit 2j; then reduce the high half. */
Poly square_mod(const Poly &a, const Poly &low) {
  uint64_t r[8] = {0, 0, 0, 0, 0, 0, 0, 0};
  for (int j = 0; j < 256; j++)
    if (a.w[j >> 6] & (UINT64_C(1) << (j & 63))) r[(2 * j) >> 6] |= UINT64_C(1) << ((2 * j) & 63);
  for (int d = 510; d >= 256; d--) {
    if (!(r[d >> 6] & (UINT64_C(1) << (d & 63)))) continue;
    r[d >> 6] ^= UINT64_C(1) << (d & 63); /* x^d = x^(d-256) * low(x) mod P */
    const int sh = d - 256;
    for (int j = 0; j < 256; j++)
      if (low.w[j >> 6] & (UINT64_C(1) << (j & 63))) {
        const int e = j + sh;
        r[e >> 6] ^= UINT64_C(1) << (e & 63);
      }
  }
  Poly out;
  for (int w = 0; w < 4; w++) out.w[w] = r[w];
  return out;
}

/* Characteristic polynomial of the xoshiro256 transition by Berlekamp-Massey on the lowest output
 * bit of s[0]... any nonzero linear functional works because P is primitive. Returns false when
 * the degree is not 256 (cannot happen for a correct generator). */
bool characteristic_low(Poly *low) {
  const int nbits = 512;
  std::vector<uint8_t> s(nbits);
  gran_rng g;
  uint64_t sm = 0x243f6a8885a308d3ULL; /* any state but zero */
  for (int w = 0; w < 4; w++) g.s[w] = gran::splitmix64(&sm);
  for (int n = 0; n < nbits; n++) {
    s[n] = (uint8_t)(g.s[0] & 1u);
    gran::rng_next(&g);
  }
  /* Massey (1969): connection polynomial C(x) = 1 + c_1 x + ... + c_L x^L. */
  std::vector<uint8_t> C(nbits + 1, 0), B(nbits + 1, 0), Tm;
  C[0] = B[0] = 1;
  int L = 0, m = 1;
  for (int n = 0; n < nbits; n++) {
    uint8_t d = s[n];
    for (int i = 1; i <= L; i++) d ^= (uint8_t)(C[i] & s[n - i]);
    if (!d) {
      m++;
    } else if (2 * L <= n) {
      Tm = C;
      for (int i = 0; i + m <= nbits; i++) C[i + m] ^= B[i];
      L = n + 1 - L;
      B = Tm;
      m = 1;
    } else {
      for (int i = 0; i + m <= nbits; i++) C[i + m] ^= B[i];
      m++;
    }
  }
  if (L != 256 || !C[256]) return false;
  /* P(x) = x^256 C(1/x) = x^256 + c_1 x^255 + ... + c_256: coefficient of x^j is c_(256-j). */
  for (int w = 0; w < 4; w++) low->w[w] = 0;
  for (int j = 0; j < 256; j++)
    if (C[256 - j]) low->w[j >> 6] |= UINT64_C(1) << (j & 63);
  return true;
}

/* J_k = x^(2^(128+k)) mod P, k = 0..63, checked against both published constants. */
struct JumpTable {
  bool ok = false;
  Poly j[64];
  JumpTable() {
    Poly low;
    if (!characteristic_low(&low)) return;
    Poly x = {{2, 0, 0, 0}}; /* the polynomial x */
    for (int k = 0; k < 128; k++) x = square_mod(x, low);
    for (int w = 0; w < 4; w++)
      if (x.w[w] != kJump[w]) return;
    j[0] = x;
    for (int k = 1; k < 64; k++) j[k] = square_mod(j[k - 1], low);
    const Poly lj = square_mod(j[63], low);
    for (int w = 0; w < 4; w++)
      if (lj.w[w] != kLongJump[w]) return;
    ok = true;
  }
};

const JumpTable &jump_table() {
  static const JumpTable table; /* thread-safe initialisation (C++11) */
  return table;
}

}  // namespace

/** @brief Seed from one 64-bit value: the four state words are four successive splitmix64 outputs
 *  of `seed` (Vigna's recommendation; never the all-zero state).
 *  @param[out] rng state  @param[in] seed any value */
GRAN_EXTERN int gran_rng_seed(gran_rng *rng, uint64_t seed) {
  GRAN_CHECK_PTR(rng);
  uint64_t x = seed;
  for (int w = 0; w < 4; w++) rng->s[w] = gran::splitmix64(&x);
  return GRAN_SUCCESS;
}

/** @brief Stream `stream_id` of `seed`: gran_rng_seed(seed) advanced by stream_id * 2^128 steps
 *  (equal to stream_id calls of gran_rng_jump), in O(log stream_id). See the file comment.
 *  @param[in] seed  @param[in] stream_id any value  @param[out] rng state */
GRAN_EXTERN int gran_rng_stream(uint64_t seed, uint64_t stream_id, gran_rng *rng) {
  GRAN_CHECK_PTR(rng);
  GRAN_TRY {
    const JumpTable &jt = jump_table();
    GRAN_CHECK(jt.ok, GRAN_ERR_INTERNAL, "jump polynomial table failed its check against the published constants");
    gran_rng g;
    GRAN_CALL(gran_rng_seed(&g, seed));
    for (int k = 0; k < 64; k++)
      if (stream_id & (UINT64_C(1) << k)) apply_poly(&g, jt.j[k].w);
    *rng = g;
    return GRAN_SUCCESS;
  }
  GRAN_CATCH
}

/** @brief Advance by 2^128 steps (2^128 non-overlapping sequences of length 2^128). */
GRAN_EXTERN int gran_rng_jump(gran_rng *rng) {
  GRAN_CHECK_PTR(rng);
  apply_poly(rng, kJump);
  return GRAN_SUCCESS;
}

/** @brief Advance by 2^192 steps (2^64 starting points, each with 2^64 jump() streams). */
GRAN_EXTERN int gran_rng_long_jump(gran_rng *rng) {
  GRAN_CHECK_PTR(rng);
  apply_poly(rng, kLongJump);
  return GRAN_SUCCESS;
}

namespace {
/* Shared argument checks of the batch draws. */
int check_batch(const gran_rng *rng, int64_t n, const void *out, const char *outname) {
  GRAN_CHECK_PTR(rng);
  GRAN_CHECK(n >= 0, GRAN_ERR_ARG, "argument 'n' is negative (" GRAN_I64_FMT ")", n);
  GRAN_CHECK(out != nullptr || n == 0, GRAN_ERR_ARG, "argument '%s' is NULL", outname);
  return GRAN_SUCCESS;
}
}  // namespace

namespace {
/* Batch draw: n values of `draw` on a local copy of the state (kept in registers), then stored. */
template <class T, class Draw> int fill(gran_rng *rng, int64_t n, T *out, Draw draw) {
  GRAN_CALL(check_batch(rng, n, out, "out"));
  gran_rng g = *rng;
  for (int64_t i = 0; i < n; i++) out[i] = draw(&g);
  *rng = g;
  return GRAN_SUCCESS;
}
}  // namespace

/** @brief n raw 64-bit outputs.  @param[in,out] rng  @param[in] n >= 0  @param[out] out n values */
GRAN_EXTERN int gran_rng_u64(gran_rng *rng, int64_t n, uint64_t *out) {
  return fill(rng, n, out, [](gran_rng *g) { return gran::rng_next(g); });
}

/** @brief n uniforms in [0,1): multiples of 2^-53 (the top 53 bits of an output). */
GRAN_EXTERN int gran_rng_uniform(gran_rng *rng, int64_t n, double *out) {
  return fill(rng, n, out, [](gran_rng *g) { return gran::rng_uniform(g); });
}

/** @brief n uniforms in (0,1]: multiples of 2^-53, never 0 (safe for log). */
GRAN_EXTERN int gran_rng_uniform_pos(gran_rng *rng, int64_t n, double *out) {
  return fill(rng, n, out, [](gran_rng *g) { return gran::rng_uniform_pos(g); });
}

/** @brief n exponential deviates of mean 1 (-log of a uniform in (0,1]). */
GRAN_EXTERN int gran_rng_exponential(gran_rng *rng, int64_t n, double *out) {
  return fill(rng, n, out, [](gran_rng *g) { return gran::rng_exponential(g); });
}

/** @brief n standard normal deviates (Marsaglia polar method, one deviate per accepted pair). */
GRAN_EXTERN int gran_rng_normal(gran_rng *rng, int64_t n, double *out) {
  return fill(rng, n, out, [](gran_rng *g) { return gran::rng_normal(g); });
}

/** @brief n unit vectors uniform on the sphere, interleaved xyz (3n doubles). */
GRAN_EXTERN int gran_rng_unit_vector3(gran_rng *rng, int64_t n, double *xyz) {
  GRAN_CALL(check_batch(rng, n, xyz, "xyz"));
  gran_rng g = *rng;
  for (int64_t i = 0; i < n; i++) gran::rng_unit3(&g, xyz + 3 * i);
  *rng = g;
  return GRAN_SUCCESS;
}

/** @brief n unit vectors uniform on the circle, interleaved xy (2n doubles). */
GRAN_EXTERN int gran_rng_unit_vector2(gran_rng *rng, int64_t n, double *xy) {
  GRAN_CALL(check_batch(rng, n, xy, "xy"));
  gran_rng g = *rng;
  for (int64_t i = 0; i < n; i++) gran::rng_unit2(&g, xy + 2 * i);
  *rng = g;
  return GRAN_SUCCESS;
}
