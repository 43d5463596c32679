// The one place that picks the instruction set of the SIMD packs (simd.h).
// No other file tests an ISA macro: code is written over Pack<W> and asks
// packWidth<N>() how wide a pack this build has.
//
// cmake/Isa.cmake sets the compiler's target flags from MBRT_SIMD and, for
// MBRT_SIMD=scalar, defines MBRT_SIMD_SCALAR. Otherwise the widest level the
// compiler targets is used:
//   2  AVX2 with FMA: 8-lane packs (and the 4-lane SSE ones)
//   1  SSE2 (every x86-64): 4-lane packs
//   0  portable scalar packs (loops over plain floats, any W)
// Fused multiply-add follows the target (__FMA__) at every level, so that a
// pack's fmadd and the scalar madd round alike in one build.
#pragma once

#if defined(MBRT_SIMD_SCALAR)
#define MBRT_SIMD_LEVEL 0
#elif defined(__AVX2__) && defined(__FMA__)
#define MBRT_SIMD_LEVEL 2
#elif defined(__SSE2__) || defined(_M_X64)
#define MBRT_SIMD_LEVEL 1
#else
#define MBRT_SIMD_LEVEL 0
#endif

#if defined(__FMA__)
#define MBRT_SIMD_FMA 1
#else
#define MBRT_SIMD_FMA 0
#endif

#if MBRT_SIMD_LEVEL > 0
#include <immintrin.h>
#endif

namespace mbrt::detail {

inline constexpr int kSimdLevel = MBRT_SIMD_LEVEL;
inline constexpr bool kFusedMultiplyAdd = MBRT_SIMD_FMA != 0;

}  // namespace mbrt::detail
