/* theory_simd.h - the SIMD width and helpers of the theory's pair passes (cooling.cpp, sonine.cpp):
 * std::sqrt does not vectorise under -fmath-errno, so the passes use the intrinsics' square root on
 * GCC vector types of the widest ISA the build targets. Internal; included inside an anonymous
 * namespace of each user. */
#ifndef GRANARY_THEORY_SIMD_H
#define GRANARY_THEORY_SIMD_H

#include <cmath>
#include <cstring>
#if defined(__AVX512F__) || defined(__AVX__) || defined(__SSE2__)
#include <immintrin.h>
#endif

namespace gran_theory_simd {
#if defined(__AVX512F__)
const int VW = 8;
typedef double vd __attribute__((vector_size(64)));
inline vd vsqrt(vd x) { return (vd)_mm512_mask_sqrt_pd((__m512d)x, (__mmask8)-1, (__m512d)x); }
#elif defined(__AVX__)
const int VW = 4;
typedef double vd __attribute__((vector_size(32)));
inline vd vsqrt(vd x) { return (vd)_mm256_sqrt_pd((__m256d)x); }
#elif defined(__SSE2__)
const int VW = 2;
typedef double vd __attribute__((vector_size(16)));
inline vd vsqrt(vd x) { return (vd)_mm_sqrt_pd((__m128d)x); }
#else
const int VW = 1;
typedef double vd;
inline vd vsqrt(vd x) { return std::sqrt(x); }
#endif

inline vd vload(const double *p) {
  vd v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void vstore(double *p, vd v) { std::memcpy(p, &v, sizeof v); }
inline double hsum(vd v) {
  double a[sizeof(vd) / sizeof(double)];
  std::memcpy(a, &v, sizeof v);
  double s = 0.0;
  for (double x : a) s += x;
  return s;
}

/* single precision, the same register width (VWF lanes) */
#if defined(__AVX512F__)
const int VWF = 16;
typedef float vf __attribute__((vector_size(64)));
inline vf vsqrt(vf x) { return (vf)_mm512_mask_sqrt_ps((__m512)x, (__mmask16)-1, (__m512)x); }
#elif defined(__AVX__)
const int VWF = 8;
typedef float vf __attribute__((vector_size(32)));
inline vf vsqrt(vf x) { return (vf)_mm256_sqrt_ps((__m256)x); }
#elif defined(__SSE2__)
const int VWF = 4;
typedef float vf __attribute__((vector_size(16)));
inline vf vsqrt(vf x) { return (vf)_mm_sqrt_ps((__m128)x); }
#else
const int VWF = 1;
typedef float vf;
inline vf vsqrt(vf x) { return std::sqrt(x); }
#endif
inline vf vloadf(const float *p) {
  vf v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
inline void vstore(float *p, vf v) { std::memcpy(p, &v, sizeof v); }
inline float hsum(vf v) {
  float a[sizeof(vf) / sizeof(float)];
  std::memcpy(a, &v, sizeof v);
  float s = 0.0f;
  for (float x : a) s += x;
  return s;
}
}  // namespace gran_theory_simd

#endif
