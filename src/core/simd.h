// W-lane float packs for the node test: AVX2+FMA (8), SSE (4) and a portable
// scalar (1). Only these few operations differ per ISA; the node test and
// the traversal are written once over Pack<W> (traverse.h).
//
// vmin/vmax follow the x86 rule "return the second operand when either is
// NaN", so a NaN slab distance (0 * inf on a box face) never decides.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__) || defined(_M_X64)
#include <immintrin.h>
#define MBRT_BVH_SSE 1
#endif
#if defined(__AVX2__) && defined(__FMA__)
#define MBRT_BVH_AVX2 1
#endif

namespace mbrt::detail {

// a*b + c, fused where the hardware fuses (the node test and the debug
// walkers use the same formula).
inline float madd(float a, float b, float c) {
#if defined(__FMA__)
  return std::fma(a, b, c);
#else
  return a * b + c;
#endif
}

template <int W>
struct Pack;

template <>
struct Pack<1> {
  float v;
  static Pack load(const float* p) { return {*p}; }
  static Pack loadBytes(const uint8_t* p) { return {float(*p)}; }  // W unsigned bytes as floats
  static Pack set1(float x) { return {x}; }
  friend Pack fmadd(Pack a, Pack b, Pack c) { return {madd(a.v, b.v, c.v)}; }
  friend Pack operator-(Pack a, Pack b) { return {a.v - b.v}; }
  friend Pack operator*(Pack a, Pack b) { return {a.v * b.v}; }
  friend Pack vmin(Pack a, Pack b) { return {a.v < b.v ? a.v : b.v}; }
  friend Pack vmax(Pack a, Pack b) { return {a.v > b.v ? a.v : b.v}; }
  friend uint32_t lessEqualMask(Pack a, Pack b) { return a.v <= b.v ? 1u : 0u; }
  friend uint32_t lessMask(Pack a, Pack b) { return a.v < b.v ? 1u : 0u; }
  void store(float* p) const { *p = v; }
};

#ifdef MBRT_BVH_SSE
template <>
struct Pack<4> {
  __m128 v;
  static Pack load(const float* p) { return {_mm_load_ps(p)}; }
  static Pack loadBytes(const uint8_t* p) {
    int32_t word;
    std::memcpy(&word, p, 4);
    const __m128i zero = _mm_setzero_si128();
    const __m128i bytes = _mm_cvtsi32_si128(word);
    return {_mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero))};
  }
  static Pack set1(float x) { return {_mm_set1_ps(x)}; }
  friend Pack fmadd(Pack a, Pack b, Pack c) {
#if defined(__FMA__)
    return {_mm_fmadd_ps(a.v, b.v, c.v)};
#else
    return {_mm_add_ps(_mm_mul_ps(a.v, b.v), c.v)};
#endif
  }
  friend Pack operator-(Pack a, Pack b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Pack operator*(Pack a, Pack b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Pack vmin(Pack a, Pack b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Pack vmax(Pack a, Pack b) { return {_mm_max_ps(a.v, b.v)}; }
  friend uint32_t lessEqualMask(Pack a, Pack b) { return uint32_t(_mm_movemask_ps(_mm_cmple_ps(a.v, b.v))); }
  friend uint32_t lessMask(Pack a, Pack b) { return uint32_t(_mm_movemask_ps(_mm_cmplt_ps(a.v, b.v))); }
  void store(float* p) const { _mm_store_ps(p, v); }
};
#endif

#ifdef MBRT_BVH_AVX2
template <>
struct Pack<8> {
  __m256 v;
  static Pack load(const float* p) { return {_mm256_load_ps(p)}; }
  static Pack loadBytes(const uint8_t* p) {
    return {_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))))};
  }
  static Pack set1(float x) { return {_mm256_set1_ps(x)}; }
  friend Pack fmadd(Pack a, Pack b, Pack c) { return {_mm256_fmadd_ps(a.v, b.v, c.v)}; }
  friend Pack operator-(Pack a, Pack b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Pack operator*(Pack a, Pack b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend Pack vmin(Pack a, Pack b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend Pack vmax(Pack a, Pack b) { return {_mm256_max_ps(a.v, b.v)}; }
  friend uint32_t lessEqualMask(Pack a, Pack b) {
    return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)));
  }
  friend uint32_t lessMask(Pack a, Pack b) { return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ))); }
  void store(float* p) const { _mm256_store_ps(p, v); }
};
#endif

// Widest pack for a node of N lanes on this build.
template <int N>
constexpr int packWidth() {
#if defined(MBRT_BVH_AVX2)
  if (N >= 8) return 8;
#endif
#if defined(MBRT_BVH_SSE)
  if (N >= 4) return 4;
#endif
  return 1;
}

}  // namespace mbrt::detail
