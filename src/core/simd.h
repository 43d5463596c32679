// W-lane float packs, the one SIMD vocabulary of mbrt: the node tests and
// traversals (bvh/traverse.h, kd/kd_leaf_blocks.h, msbvh), the object
// binner (bvh/heuristics/binned_sah.cpp), the primitive bounds
// (scene/primitive_bounds.cpp), the leaves' gather into triangle blocks
// (leaves/gathered_runs.h) and the motion node's distance terms are written
// once over Pack<W>. The ISA is picked in isa.h; this file holds
// the portable pack (any W, plain floats) and the SSE (4) and AVX2 (8)
// specialisations, which compute bit for bit what the portable pack does.
//
// Semantics every pack follows (those of the x86 instructions):
// - vmin(a, b) is a < b ? a : b and vmax(a, b) is a > b ? a : b, so the
//   second operand wins on NaN and ties: a NaN slab distance (0 * inf on a
//   box face) never decides. std::min(a, b) is vmin(b, a).
// - Comparisons give either a bit per lane (lessMask: lane i in bit i) or
//   a lane mask (lessLanes: all ones or all zeros), for & and |.
// - fmadd fuses where the target has FMA (isa.h), as madd does; sqrt is
//   the correctly rounded root of every lane, as std::sqrt.
// - load and store need 4 * W-byte alignment (traversal data is aligned);
//   loadu does not. load3 reads x, y, z of a 4-lane pack and no further, at
//   any alignment (a user's vertex buffer).
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "core/isa.h"

namespace mbrt::detail {

// a*b + c, fused where the hardware fuses (the node test and the debug
// walkers use the same formula).
inline float madd(float a, float b, float c) {
  if constexpr (kFusedMultiplyAdd) return std::fma(a, b, c);
  else return a * b + c;
}

// The portable pack: every operation is a loop over the lanes.
template <int W>
struct Pack {
  float v[W];

  static Pack load(const float* p) { return loadu(p); }
  static Pack loadu(const float* p) {
    Pack r;
    for (int i = 0; i < W; ++i) r.v[i] = p[i];
    return r;
  }
  static Pack loadBytes(const uint8_t* p) {  // W unsigned bytes as floats
    Pack r;
    for (int i = 0; i < W; ++i) r.v[i] = float(p[i]);
    return r;
  }
  static Pack set1(float x) {
    Pack r;
    for (float& l : r.v) l = x;
    return r;
  }
  static Pack load3(const float* p) requires(W == 4) {
    Pack r{{0.0f, 0.0f, 0.0f, 0.0f}};
    std::memcpy(r.v, p, 3 * sizeof(float));  // p need not be aligned
    return r;
  }
  static Pack of(float x, float y, float z, float w) requires(W == 4) { return {{x, y, z, w}}; }
  void store(float* p) const {
    for (int i = 0; i < W; ++i) p[i] = v[i];
  }
  // Truncated towards zero; out of range and NaN give INT32_MIN (cvttps).
  void storeTruncated(int32_t* p) const {
    for (int i = 0; i < W; ++i) p[i] = v[i] > -0x1p31f && v[i] < 0x1p31f ? int32_t(v[i]) : INT32_MIN;
  }
  float lane(int i) const { return v[i]; }
  // x, y, z of a, b, c and d as 12 consecutive floats.
  static void storeXyz(Pack a, Pack b, Pack c, Pack d, float* out) requires(W == 4) {
    const Pack* p[4] = {&a, &b, &c, &d};
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) out[3 * k + i] = p[k]->v[i];
  }

  // Lanes x, y, z of a, b, c and d as three packs: x = (a.x, b.x, c.x, d.x)
  // and likewise y and z (four points into structure of arrays).
  static void transposeXyz(Pack a, Pack b, Pack c, Pack d, Pack& x, Pack& y, Pack& z) requires(W == 4) {
    const Pack* p[4] = {&a, &b, &c, &d};
    for (int k = 0; k < 4; ++k) {
      x.v[k] = p[k]->v[0];
      y.v[k] = p[k]->v[1];
      z.v[k] = p[k]->v[2];
    }
  }

  friend Pack fmadd(Pack a, Pack b, Pack c) { return map(a, b, c, [](float x, float y, float z) { return madd(x, y, z); }); }
  friend Pack operator+(Pack a, Pack b) { return map(a, b, [](float x, float y) { return x + y; }); }
  friend Pack operator-(Pack a, Pack b) { return map(a, b, [](float x, float y) { return x - y; }); }
  friend Pack operator*(Pack a, Pack b) { return map(a, b, [](float x, float y) { return x * y; }); }
  friend Pack operator/(Pack a, Pack b) { return map(a, b, [](float x, float y) { return x / y; }); }
  friend Pack vmin(Pack a, Pack b) { return map(a, b, [](float x, float y) { return x < y ? x : y; }); }
  friend Pack vmax(Pack a, Pack b) { return map(a, b, [](float x, float y) { return x > y ? x : y; }); }
  friend Pack abs(Pack a) { return bits(a, a, [](uint32_t x, uint32_t) { return x & 0x7FFFFFFFu; }); }
  friend Pack sqrt(Pack a) { return map(a, a, [](float x, float) { return std::sqrt(x); }); }
  friend Pack operator&(Pack a, Pack b) { return bits(a, b, [](uint32_t x, uint32_t y) { return x & y; }); }
  friend Pack operator|(Pack a, Pack b) { return bits(a, b, [](uint32_t x, uint32_t y) { return x | y; }); }
  friend Pack clearLastLane(Pack a) {
    a.v[W - 1] = 0.0f;
    return a;
  }
  friend Pack lessLanes(Pack a, Pack b) { return lanes(a, b, [](float x, float y) { return x < y; }); }
  friend Pack equalLanes(Pack a, Pack b) { return lanes(a, b, [](float x, float y) { return x == y; }); }
  friend uint32_t lessEqualMask(Pack a, Pack b) { return mask(a, b, [](float x, float y) { return x <= y; }); }
  friend uint32_t lessMask(Pack a, Pack b) { return mask(a, b, [](float x, float y) { return x < y; }); }
  friend uint32_t equalMask(Pack a, Pack b) { return mask(a, b, [](float x, float y) { return x == y; }); }
  // Bit i: lane i's sign bit (of a lane mask: whether lane i is set).
  friend uint32_t laneBits(Pack a) {
    uint32_t m = 0;
    for (int i = 0; i < W; ++i) m |= (std::bit_cast<uint32_t>(a.v[i]) >> 31) << i;
    return m;
  }

 private:
  template <class F>
  static Pack map(Pack a, Pack b, F f) {
    Pack r;
    for (int i = 0; i < W; ++i) r.v[i] = f(a.v[i], b.v[i]);
    return r;
  }
  template <class F>
  static Pack map(Pack a, Pack b, Pack c, F f) {
    Pack r;
    for (int i = 0; i < W; ++i) r.v[i] = f(a.v[i], b.v[i], c.v[i]);
    return r;
  }
  template <class F>
  static Pack bits(Pack a, Pack b, F f) {
    Pack r;
    for (int i = 0; i < W; ++i)
      r.v[i] = std::bit_cast<float>(uint32_t(f(std::bit_cast<uint32_t>(a.v[i]), std::bit_cast<uint32_t>(b.v[i]))));
    return r;
  }
  template <class F>
  static Pack lanes(Pack a, Pack b, F f) {
    Pack r;
    for (int i = 0; i < W; ++i) r.v[i] = std::bit_cast<float>(f(a.v[i], b.v[i]) ? 0xFFFFFFFFu : 0u);
    return r;
  }
  template <class F>
  static uint32_t mask(Pack a, Pack b, F f) {
    uint32_t m = 0;
    for (int i = 0; i < W; ++i) m |= uint32_t(f(a.v[i], b.v[i])) << i;
    return m;
  }
};

#if MBRT_SIMD_LEVEL >= 1
template <>
struct Pack<4> {
  __m128 v;

  static Pack load(const float* p) { return {_mm_load_ps(p)}; }
  static Pack loadu(const float* p) { return {_mm_loadu_ps(p)}; }
  static Pack loadBytes(const uint8_t* p) {
    int32_t word;
    std::memcpy(&word, p, 4);
    const __m128i zero = _mm_setzero_si128();
    const __m128i bytes = _mm_cvtsi32_si128(word);
    return {_mm_cvtepi32_ps(_mm_unpacklo_epi16(_mm_unpacklo_epi8(bytes, zero), zero))};
  }
  static Pack set1(float x) { return {_mm_set1_ps(x)}; }
  static Pack load3(const float* p) {
    double xy;  // x and y as one 8-byte load, z as one 4-byte load (p need not be aligned)
    float z;
    std::memcpy(&xy, p, sizeof xy);
    std::memcpy(&z, p + 2, sizeof z);
    return {_mm_movelh_ps(_mm_castpd_ps(_mm_set_sd(xy)), _mm_set_ss(z))};
  }
  static Pack of(float x, float y, float z, float w) { return {_mm_setr_ps(x, y, z, w)}; }
  void store(float* p) const { _mm_store_ps(p, v); }
  void storeTruncated(int32_t* p) const { _mm_store_si128(reinterpret_cast<__m128i*>(p), _mm_cvttps_epi32(v)); }
  float lane(int i) const {
    alignas(16) float f[4];
    store(f);
    return f[i];
  }
  // Three shuffled stores, not twelve scalar ones.
  static void storeXyz(Pack a, Pack b, Pack c, Pack d, float* out) {
    const __m128 azbx = _mm_shuffle_ps(a.v, b.v, _MM_SHUFFLE(0, 0, 2, 2));
    const __m128 czdx = _mm_shuffle_ps(c.v, d.v, _MM_SHUFFLE(0, 0, 2, 2));
    _mm_storeu_ps(out, _mm_shuffle_ps(a.v, azbx, _MM_SHUFFLE(2, 0, 1, 0)));      // a.xyz b.x
    _mm_storeu_ps(out + 4, _mm_shuffle_ps(b.v, c.v, _MM_SHUFFLE(1, 0, 2, 1)));   // b.yz c.xy
    _mm_storeu_ps(out + 8, _mm_shuffle_ps(czdx, d.v, _MM_SHUFFLE(2, 1, 2, 0)));  // c.z d.xyz
  }

  // Four unpacks and three moves, as _MM_TRANSPOSE4_PS less the w row.
  static void transposeXyz(Pack a, Pack b, Pack c, Pack d, Pack& x, Pack& y, Pack& z) {
    const __m128 ab01 = _mm_unpacklo_ps(a.v, b.v), cd01 = _mm_unpacklo_ps(c.v, d.v);  // a.x b.x a.y b.y, ...
    const __m128 ab23 = _mm_unpackhi_ps(a.v, b.v), cd23 = _mm_unpackhi_ps(c.v, d.v);  // a.z b.z a.w b.w, ...
    x.v = _mm_movelh_ps(ab01, cd01);
    y.v = _mm_movehl_ps(cd01, ab01);
    z.v = _mm_movelh_ps(ab23, cd23);
  }

  friend Pack fmadd(Pack a, Pack b, Pack c) {
#if MBRT_SIMD_FMA
    return {_mm_fmadd_ps(a.v, b.v, c.v)};
#else
    return {_mm_add_ps(_mm_mul_ps(a.v, b.v), c.v)};
#endif
  }
  friend Pack operator+(Pack a, Pack b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Pack operator-(Pack a, Pack b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Pack operator*(Pack a, Pack b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Pack operator/(Pack a, Pack b) { return {_mm_div_ps(a.v, b.v)}; }
  friend Pack vmin(Pack a, Pack b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Pack vmax(Pack a, Pack b) { return {_mm_max_ps(a.v, b.v)}; }
  friend Pack abs(Pack a) { return {_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)}; }
  friend Pack sqrt(Pack a) { return {_mm_sqrt_ps(a.v)}; }
  friend Pack operator&(Pack a, Pack b) { return {_mm_and_ps(a.v, b.v)}; }
  friend Pack operator|(Pack a, Pack b) { return {_mm_or_ps(a.v, b.v)}; }
  friend Pack clearLastLane(Pack a) { return {_mm_and_ps(a.v, _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0)))}; }
  friend Pack lessLanes(Pack a, Pack b) { return {_mm_cmplt_ps(a.v, b.v)}; }
  friend Pack equalLanes(Pack a, Pack b) { return {_mm_cmpeq_ps(a.v, b.v)}; }
  friend uint32_t lessEqualMask(Pack a, Pack b) { return uint32_t(_mm_movemask_ps(_mm_cmple_ps(a.v, b.v))); }
  friend uint32_t lessMask(Pack a, Pack b) { return uint32_t(_mm_movemask_ps(_mm_cmplt_ps(a.v, b.v))); }
  friend uint32_t equalMask(Pack a, Pack b) { return uint32_t(_mm_movemask_ps(_mm_cmpeq_ps(a.v, b.v))); }
  friend uint32_t laneBits(Pack a) { return uint32_t(_mm_movemask_ps(a.v)); }
};
#endif

#if MBRT_SIMD_LEVEL >= 2
template <>
struct Pack<8> {
  __m256 v;

  static Pack load(const float* p) { return {_mm256_load_ps(p)}; }
  static Pack loadu(const float* p) { return {_mm256_loadu_ps(p)}; }
  static Pack loadBytes(const uint8_t* p) {
    return {_mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))))};
  }
  static Pack set1(float x) { return {_mm256_set1_ps(x)}; }
  void store(float* p) const { _mm256_store_ps(p, v); }
  void storeTruncated(int32_t* p) const {
    _mm256_store_si256(reinterpret_cast<__m256i*>(p), _mm256_cvttps_epi32(v));
  }
  float lane(int i) const {
    alignas(32) float f[8];
    store(f);
    return f[i];
  }

  friend Pack fmadd(Pack a, Pack b, Pack c) { return {_mm256_fmadd_ps(a.v, b.v, c.v)}; }
  friend Pack operator+(Pack a, Pack b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend Pack operator-(Pack a, Pack b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Pack operator*(Pack a, Pack b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend Pack operator/(Pack a, Pack b) { return {_mm256_div_ps(a.v, b.v)}; }
  friend Pack vmin(Pack a, Pack b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend Pack vmax(Pack a, Pack b) { return {_mm256_max_ps(a.v, b.v)}; }
  friend Pack abs(Pack a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
  friend Pack sqrt(Pack a) { return {_mm256_sqrt_ps(a.v)}; }
  friend Pack operator&(Pack a, Pack b) { return {_mm256_and_ps(a.v, b.v)}; }
  friend Pack operator|(Pack a, Pack b) { return {_mm256_or_ps(a.v, b.v)}; }
  friend Pack clearLastLane(Pack a) {
    return {_mm256_and_ps(a.v, _mm256_castsi256_ps(_mm256_setr_epi32(-1, -1, -1, -1, -1, -1, -1, 0)))};
  }
  friend Pack lessLanes(Pack a, Pack b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
  friend Pack equalLanes(Pack a, Pack b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)}; }
  friend uint32_t lessEqualMask(Pack a, Pack b) {
    return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)));
  }
  friend uint32_t lessMask(Pack a, Pack b) { return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ))); }
  friend uint32_t equalMask(Pack a, Pack b) {
    return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)));
  }
  friend uint32_t laneBits(Pack a) { return uint32_t(_mm256_movemask_ps(a.v)); }
};
#endif

// Bit i set, for i < N <= 8, when byte p[i] differs from `value`. Reads
// the 8 bytes at p: all of them must be readable.
template <int N>
inline uint32_t bytesDifferMask(const uint8_t* p, uint8_t value) {
  static_assert(N <= 8);
#if MBRT_SIMD_LEVEL >= 1
  const __m128i bytes = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(p));
  return ~uint32_t(_mm_movemask_epi8(_mm_cmpeq_epi8(bytes, _mm_set1_epi8(char(value))))) & ((1u << N) - 1u);
#else
  uint32_t m = 0;
  for (int i = 0; i < N; ++i) m |= uint32_t(p[i] != value) << i;
  return m;
#endif
}

// Bit i set, for i < 4, when p[i] & m is not zero (the lanes of a leaf
// block whose geometry mask meets the ray's).
inline uint32_t nonZeroAndMask4(const uint32_t* p, uint32_t m) {
#if MBRT_SIMD_LEVEL >= 1
  const __m128i v = _mm_and_si128(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)), _mm_set1_epi32(int(m)));
  return ~uint32_t(_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(v, _mm_setzero_si128())))) & 0xFu;
#else
  uint32_t r = 0;
  for (int i = 0; i < 4; ++i) r |= uint32_t((p[i] & m) != 0) << i;
  return r;
#endif
}

// Starts loading the cache line at p into all cache levels (a hint).
inline void prefetch(const void* p) {
#if MBRT_SIMD_LEVEL >= 1
  _mm_prefetch(static_cast<const char*>(p), _MM_HINT_T0);
#elif defined(__GNUC__)
  __builtin_prefetch(p, 0, 3);
#endif
}

// Widest pack for a node of N lanes on this build.
template <int N>
constexpr int packWidth() {
  if (kSimdLevel >= 2 && N >= 8) return 8;
  if (kSimdLevel >= 1 && N >= 4) return 4;
  return 1;
}

}  // namespace mbrt::detail
