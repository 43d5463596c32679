# Instruction set of the SIMD packs (src/core/isa.h reads the result):
#   MBRT_SIMD=auto    portable x86-64 (SSE packs) plus AVX2+FMA when the build
#                     machine has them (MBRT_AVX2), or everything the machine
#                     has (MBRT_NATIVE); elsewhere the compiler's default
#   MBRT_SIMD=avx2    AVX2+FMA (8-lane packs), whatever the build machine has
#   MBRT_SIMD=sse     x86-64 baseline: SSE2 (4-lane packs), no FMA
#   MBRT_SIMD=scalar  the portable scalar packs, no instruction-set flags;
#                     defines MBRT_SIMD_SCALAR, the one macro isa.h reads
# No FMA contraction: the watertight triangle test needs its edge functions
# rounded exactly as written (explicit fma intrinsics are still used).
set(MBRT_SIMD "auto" CACHE STRING "SIMD packs: auto, avx2, sse or scalar")
set_property(CACHE MBRT_SIMD PROPERTY STRINGS auto avx2 sse scalar)
if(NOT MBRT_SIMD MATCHES "^(auto|avx2|sse|scalar)$")
  message(FATAL_ERROR "MBRT_SIMD=${MBRT_SIMD}: expected auto, avx2, sse or scalar")
endif()

set(MBRT_FP_FLAGS "")
set(MBRT_GNU_LIKE FALSE)
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  set(MBRT_FP_FLAGS -ffp-contract=off)
  set(MBRT_GNU_LIKE TRUE)
endif()
set(MBRT_X86_64 FALSE)
if(CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
  set(MBRT_X86_64 TRUE)
endif()
if(MBRT_SIMD MATCHES "avx2|sse" AND NOT MBRT_X86_64)
  message(FATAL_ERROR "MBRT_SIMD=${MBRT_SIMD} needs an x86-64 target")
endif()

set(MBRT_ISA_FLAGS "")
if(MBRT_SIMD STREQUAL "scalar")
  list(APPEND MBRT_ISA_FLAGS -DMBRT_SIMD_SCALAR=1)
elseif(MBRT_SIMD STREQUAL "avx2")
  if(MBRT_GNU_LIKE)
    set(MBRT_ISA_FLAGS -mavx2 -mfma)
  endif()
elseif(MBRT_SIMD STREQUAL "auto" AND MBRT_GNU_LIKE AND MBRT_X86_64)
  if(MBRT_NATIVE)
    set(MBRT_ISA_FLAGS -march=native)
  elseif(MBRT_AVX2)
    include(CheckCXXSourceRuns)
    set(CMAKE_REQUIRED_FLAGS "-mavx2 -mfma")
    check_cxx_source_runs("
      #include <immintrin.h>
      int main() {
        if (!__builtin_cpu_supports(\"avx2\") || !__builtin_cpu_supports(\"fma\")) return 1;
        __m256 a = _mm256_set1_ps(1.0f);
        a = _mm256_fmadd_ps(a, a, a);
        return _mm256_cvtss_f32(a) == 2.0f ? 0 : 1;
      }" MBRT_HOST_HAS_AVX2)
    unset(CMAKE_REQUIRED_FLAGS)
    if(MBRT_HOST_HAS_AVX2)
      set(MBRT_ISA_FLAGS -mavx2 -mfma)
    endif()
  endif()
endif()
list(APPEND MBRT_ISA_FLAGS ${MBRT_FP_FLAGS})
message(STATUS "mbrt SIMD: ${MBRT_SIMD}, ISA flags: ${MBRT_ISA_FLAGS}")
