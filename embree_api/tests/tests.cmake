# The Embree API's tests (docs/embree-api.md): the comparisons with the real
# libembree3 in one process (the renamed build beside it), errors,
# scenarios; the thread test on the shared library itself.
find_package(Threads REQUIRED)
set(_tests ${CMAKE_CURRENT_LIST_DIR})

if(TARGET embree)
  add_executable(mbrt_embree_api_tests
    ${_tests}/test_world.cpp ${_tests}/side_real.cpp ${_tests}/side_mbrt.cpp ${_tests}/test_compare.cpp
    ${_tests}/test_filters.cpp ${_tests}/test_errors.cpp ${_tests}/test_scenarios.cpp
    ${PROJECT_SOURCE_DIR}/tests/reference64.cpp)
  target_include_directories(mbrt_embree_api_tests PRIVATE ${_tests} ${PROJECT_SOURCE_DIR}/tests ${MBRT_EMBREE3_INCLUDE_DIR})
  target_link_libraries(mbrt_embree_api_tests PRIVATE mbrt_embree_api_renamed embree GTest::gtest GTest::gtest_main)
  target_compile_options(mbrt_embree_api_tests PRIVATE ${MBRT_ISA_FLAGS})
  target_compile_definitions(mbrt_embree_api_tests PRIVATE MBRT_DEFAULT_TEST_SCALE=${MBRT_DEFAULT_TEST_SCALE})
  gtest_discover_tests(mbrt_embree_api_tests TEST_PREFIX embree_api. DISCOVERY_TIMEOUT 60)
else()
  add_test(NAME embree_api.comparisons_skipped
           COMMAND ${CMAKE_COMMAND} -E echo "the comparisons with the real Embree need MBRT_WITH_EMBREE (libembree-dev)")
endif()

# Concurrent tracing on the shared library (scripts/test-tsan.sh runs it
# under ThreadSanitizer).
add_executable(mbrt_embree_api_thread_tests ${_tests}/test_threads.cpp)
target_include_directories(mbrt_embree_api_thread_tests PRIVATE ${MBRT_EMBREE3_INCLUDE_DIR})
target_link_libraries(mbrt_embree_api_thread_tests PRIVATE mbrt_embree_api GTest::gtest GTest::gtest_main Threads::Threads)
if(TARGET mbrt_tbbmalloc_for_tsan)
  target_link_libraries(mbrt_embree_api_thread_tests PRIVATE -Wl,--no-as-needed mbrt_tbbmalloc_for_tsan -Wl,--as-needed)
endif()
add_test(NAME embree_api.threads COMMAND mbrt_embree_api_thread_tests)

# The clients below are unsanitized programs (Embree's tutorials and
# embree_verify, Python with Open3D, Blender) that would load this library:
# a sanitized build of it cannot be loaded into them (the sanitizer's runtime
# must come first in the process), so a sanitized build leaves them to the
# default build (scripts/test.sh), which runs them all.
if(MBRT_SANITIZE)
  add_test(NAME embree_api.clients_skipped
           COMMAND ${CMAKE_COMMAND} -E echo
                   "the Embree API's clients run in the unsanitized build (MBRT_SANITIZE=${MBRT_SANITIZE} here)")
  return()
endif()

# Embree's tutorials on both libraries, pictures and rays compared
# (clients/tutorials.sh; skipped without Debian's embree-tools).
add_test(NAME embree_api.tutorials
         COMMAND bash ${PROJECT_SOURCE_DIR}/embree_api/clients/tutorials.sh ${PROJECT_BINARY_DIR}
                 ${PROJECT_BINARY_DIR}/embree_tutorials)
set_tests_properties(embree_api.tutorials PROPERTIES SKIP_RETURN_CODE 77 COST 200)

# The tests of Embree's own embree_verify that cover what the library
# implements (clients/verify.sh; skipped without Debian's embree-tools).
add_test(NAME embree_api.verify COMMAND bash ${PROJECT_SOURCE_DIR}/embree_api/clients/verify.sh ${PROJECT_BINARY_DIR})
set_tests_properties(embree_api.verify PROPERTIES SKIP_RETURN_CODE 77 COST 300)

# Real clients through their drivers (clients/README.md): Open3D's
# RaycastingScene and Blender's Cycles, each with Debian's libembree3 and
# with this one, compared (skipped without python3-open3d / blender).
add_test(NAME embree_api.open3d
         COMMAND bash ${PROJECT_SOURCE_DIR}/embree_api/clients/open3d/run.sh ${PROJECT_BINARY_DIR}/embree_api)
add_test(NAME embree_api.cycles
         COMMAND bash ${PROJECT_SOURCE_DIR}/embree_api/clients/cycles/run.sh ${PROJECT_BINARY_DIR}/embree_api
                 ${PROJECT_BINARY_DIR}/embree_cycles)
set_tests_properties(embree_api.open3d PROPERTIES SKIP_RETURN_CODE 77 COST 100)
set_tests_properties(embree_api.cycles PROPERTIES SKIP_RETURN_CODE 77 COST 1000)
