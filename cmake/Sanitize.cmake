# Sanitizer and fuzzing builds.
#
#   -DMBRT_SANITIZE=address,undefined   ASan + UBSan on every target (GCC or
#                                       clang), frame pointers kept, the first
#                                       report aborts (no recovery). The tests
#                                       then run at MBRT_DEFAULT_TEST_SCALE
#                                       (0.1: smaller scenes and fewer rays;
#                                       the MBRT_TEST_SCALE environment
#                                       variable overrides it at run time).
#   -DMBRT_FUZZ=ON                      clang only: everything is built with
#                                       libFuzzer coverage + ASan + UBSan and
#                                       the targets in fuzz/ are added.
set(MBRT_DEFAULT_TEST_SCALE 1.0)

if(MBRT_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "MBRT_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  if(NOT MBRT_SANITIZE)
    set(MBRT_SANITIZE "address,undefined")
  endif()
  # The library and everything else get coverage instrumentation; only the
  # fuzz targets link libFuzzer's main (fuzz/CMakeLists.txt).
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()

if(MBRT_SANITIZE)
  message(STATUS "mbrt sanitizers: ${MBRT_SANITIZE}")
  add_compile_options(-fsanitize=${MBRT_SANITIZE} -fno-omit-frame-pointer -fno-sanitize-recover=all)
  add_link_options(-fsanitize=${MBRT_SANITIZE})
  if(MBRT_SANITIZE MATCHES "undefined")
    # Not part of GCC's -fsanitize=undefined: float -> int conversions of NaN
    # or out-of-range values (what hostile input produces). Float division by
    # zero stays allowed: 1/0 = inf is how the kernel treats axis-parallel rays.
    add_compile_options(-fsanitize=float-cast-overflow)
    add_link_options(-fsanitize=float-cast-overflow)
  endif()
  set(MBRT_DEFAULT_TEST_SCALE 0.1)
endif()
