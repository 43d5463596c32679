# Instruction-set flags: portable by default, plus AVX2+FMA when the build
# machine has them (MBRT_AVX2), or everything the machine has (MBRT_NATIVE).
# No FMA contraction: the watertight triangle test needs its edge functions
# rounded exactly as written (explicit fma intrinsics are still used).
set(MBRT_FP_FLAGS "")
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
  set(MBRT_FP_FLAGS -ffp-contract=off)
endif()
set(MBRT_ISA_FLAGS "")
if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang" AND CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
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
message(STATUS "mbrt ISA flags: ${MBRT_ISA_FLAGS}")
