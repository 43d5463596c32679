# mbrt_thread_tests: the concurrent tracing tests (tests/threads/), on the
# kernel library alone, so that a ThreadSanitizer build
# (-DMBRT_SANITIZE=thread, scripts/test-tsan.sh) needs to compile only
# mbrt_accel and this target.
add_executable(mbrt_thread_tests ${PROJECT_SOURCE_DIR}/tests/threads/test_concurrent_trace.cpp)
target_include_directories(mbrt_thread_tests PRIVATE ${PROJECT_SOURCE_DIR}/tests)
target_link_libraries(mbrt_thread_tests PRIVATE mbrt::accel GTest::gtest GTest::gtest_main)
target_compile_options(mbrt_thread_tests PRIVATE ${MBRT_ISA_FLAGS})
target_compile_definitions(mbrt_thread_tests PRIVATE MBRT_DEFAULT_TEST_SCALE=${MBRT_DEFAULT_TEST_SCALE})
add_test(NAME threads.concurrent_trace COMMAND mbrt_thread_tests)

# Under TSan, TBB's allocator is replaced by one on malloc that TSan sees
# (tests/threads/tbbmalloc_for_tsan.cpp): linked first-hand (no --as-needed),
# with the soname libtbb looks for, so that the real one is never loaded.
if(MBRT_SANITIZE MATCHES "thread")
  add_library(mbrt_tbbmalloc_for_tsan SHARED ${PROJECT_SOURCE_DIR}/tests/threads/tbbmalloc_for_tsan.cpp)
  set_target_properties(mbrt_tbbmalloc_for_tsan PROPERTIES OUTPUT_NAME tbbmalloc SOVERSION 2)
  target_link_libraries(mbrt_thread_tests PRIVATE -Wl,--no-as-needed mbrt_tbbmalloc_for_tsan -Wl,--as-needed)
endif()
