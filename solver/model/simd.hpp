#pragma once
// Eight single-precision lanes as one value, so that a force law written once
// for a scalar type also runs on eight bonds at a time (the lattice sweep,
// lattice_kernel.hpp). With AVX2 each operation is one instruction on a
// 256-bit register; elsewhere (or with PD_PORTABLE_SWEEP) it is a loop over
// the lanes that the compiler vectorises as far as the target allows.
#include <cmath>
#include <cstdint>
#if defined(__SSE__) || defined(__x86_64__)
#include <xmmintrin.h>  // _mm_getcsr, _mm_setcsr
#endif

#if defined(__AVX2__) && defined(__FMA__) && !defined(PD_PORTABLE_SWEEP)
#define PD_SIMD_AVX2 1
#include <immintrin.h>
#endif

namespace pd::simd {

inline constexpr int lanes = 8;

// Scalar forms, so that generic code can call fmadd and sqrt unqualified.
inline double fmadd(double a, double b, double c) { return a * b + c; }
inline float fmadd(float a, float b, float c) { return a * b + c; }

#ifdef PD_SIMD_AVX2

struct Float8 {
  __m256 v;
  Float8() = default;
  Float8(__m256 a) : v(a) {}
  explicit Float8(float x) : v(_mm256_set1_ps(x)) {}  // the same value in every lane
};
struct Mask8 {  // per lane all bits set (true) or clear (false)
  __m256 v;
};

inline Float8 load(const float* p) { return {_mm256_loadu_ps(p)}; }
inline void store(float* p, Float8 a) { _mm256_storeu_ps(p, a.v); }
inline Float8 operator+(Float8 a, Float8 b) { return {_mm256_add_ps(a.v, b.v)}; }
inline Float8 operator-(Float8 a, Float8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
inline Float8 operator*(Float8 a, Float8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline Float8 operator/(Float8 a, Float8 b) { return {_mm256_div_ps(a.v, b.v)}; }
inline Float8 fmadd(Float8 a, Float8 b, Float8 c) { return {_mm256_fmadd_ps(a.v, b.v, c.v)}; }
inline Float8 sqrt(Float8 a) { return {_mm256_sqrt_ps(a.v)}; }
inline Float8 max(Float8 a, Float8 b) { return {_mm256_max_ps(a.v, b.v)}; }
inline Mask8 operator<=(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)}; }
inline Mask8 operator&(Mask8 a, Mask8 b) { return {_mm256_and_ps(a.v, b.v)}; }
// a where the mask is set, 0 elsewhere.
inline Float8 where(Mask8 m, Float8 a) { return {_mm256_and_ps(m.v, a.v)}; }
// Lane t's mask as bit t, and back.
inline unsigned bits(Mask8 m) { return static_cast<unsigned>(_mm256_movemask_ps(m.v)); }
inline Mask8 mask_of_bits(unsigned b) {
  const __m256i lane_bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return {_mm256_castsi256_ps(
      _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(b)), lane_bits), lane_bits))};
}

#else

struct Float8 {
  float v[lanes];
  Float8() = default;
  explicit Float8(float x) {  // the same value in every lane
    for (int t = 0; t < lanes; ++t) v[t] = x;
  }
};
struct Mask8 {
  bool v[lanes];
};

#define PD_SIMD_LANEWISE(expression)          \
  Float8 r;                                   \
  for (int t = 0; t < lanes; ++t) r.v[t] = expression; \
  return r

inline Float8 load(const float* p) { PD_SIMD_LANEWISE(p[t]); }
inline void store(float* p, Float8 a) {
  for (int t = 0; t < lanes; ++t) p[t] = a.v[t];
}
inline Float8 operator+(Float8 a, Float8 b) { PD_SIMD_LANEWISE(a.v[t] + b.v[t]); }
inline Float8 operator-(Float8 a, Float8 b) { PD_SIMD_LANEWISE(a.v[t] - b.v[t]); }
inline Float8 operator*(Float8 a, Float8 b) { PD_SIMD_LANEWISE(a.v[t] * b.v[t]); }
inline Float8 operator/(Float8 a, Float8 b) { PD_SIMD_LANEWISE(a.v[t] / b.v[t]); }
inline Float8 fmadd(Float8 a, Float8 b, Float8 c) { PD_SIMD_LANEWISE(a.v[t] * b.v[t] + c.v[t]); }
inline Float8 sqrt(Float8 a) { PD_SIMD_LANEWISE(std::sqrt(a.v[t])); }
inline Float8 max(Float8 a, Float8 b) { PD_SIMD_LANEWISE(a.v[t] > b.v[t] ? a.v[t] : b.v[t]); }
inline Float8 where(Mask8 m, Float8 a) { PD_SIMD_LANEWISE(m.v[t] ? a.v[t] : 0.0f); }
#undef PD_SIMD_LANEWISE

inline Mask8 operator<=(Float8 a, Float8 b) {
  Mask8 r;
  for (int t = 0; t < lanes; ++t) r.v[t] = a.v[t] <= b.v[t];
  return r;
}
inline Mask8 operator&(Mask8 a, Mask8 b) {
  Mask8 r;
  for (int t = 0; t < lanes; ++t) r.v[t] = a.v[t] && b.v[t];
  return r;
}
inline unsigned bits(Mask8 m) {
  unsigned b = 0;
  for (int t = 0; t < lanes; ++t) b |= static_cast<unsigned>(m.v[t]) << t;
  return b;
}
inline Mask8 mask_of_bits(unsigned b) {
  Mask8 r;
  for (int t = 0; t < lanes; ++t) r.v[t] = ((b >> t) & 1u) != 0;
  return r;
}

#endif

// Subnormal floats (below 1.2e-38) count as zero while this object lives in a
// thread, and results that would be subnormal become zero. Displacements a
// wave has barely reached (1e-40 m) are physically zero, but arithmetic on
// subnormals is microcoded on x86 and runs 10-100x slower: without this the
// first steps of a run, when most of the plate sits in a wave's tail, took
// 2.6x longer. The previous setting is restored, so double-precision code
// elsewhere keeps IEEE behaviour and runs are reproducible whatever thread
// ran which block.
class FlushSubnormals {
 public:
#if defined(__SSE__) || defined(__x86_64__)
  FlushSubnormals() : saved_(_mm_getcsr()) { _mm_setcsr(saved_ | 0x8040u); }  // FTZ (bit 15) | DAZ (bit 6)
  ~FlushSubnormals() { _mm_setcsr(saved_); }

 private:
  unsigned saved_;
#else
  FlushSubnormals() = default;
#endif
  FlushSubnormals(const FlushSubnormals&) = delete;
  FlushSubnormals& operator=(const FlushSubnormals&) = delete;
};

inline Float8& operator+=(Float8& a, Float8 b) { return a = a + b; }

}  // namespace pd::simd
