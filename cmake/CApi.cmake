# The C API (include/mbrt/mbrt.h, src/c/): the shared library libmbrt.so,
# its install and pkg-config file, the C example and the C tests.
#
# libmbrt.so links mbrt_io (the loaders of its animations, and through it
# mbrt_scenes and mbrt_accel) statically and exports the C API only: the C
# layer is compiled with hidden visibility and a version script makes every
# other symbol (the static C++ code pulled in) local, so that the library
# cannot clash with another copy of TBB-using C++ code. libpng and OpenEXR
# (mbrt_io's) become libmbrt's dependencies.
enable_language(C)
include(GNUInstallDirs)

# The version macros of mbrt.h are written by hand (the header needs no
# generated file); they must agree with the project's version.
file(READ ${PROJECT_SOURCE_DIR}/include/mbrt/mbrt.h _mbrt_h)
foreach(part MAJOR MINOR PATCH)
  string(REGEX MATCH "#define MBRT_VERSION_${part} ([0-9]+)" _m "${_mbrt_h}")
  if(NOT CMAKE_MATCH_1 STREQUAL PROJECT_VERSION_${part})
    message(FATAL_ERROR "include/mbrt/mbrt.h: MBRT_VERSION_${part} is '${CMAKE_MATCH_1}', "
                        "the project's version is ${PROJECT_VERSION}: update the header")
  endif()
endforeach()

file(GLOB MBRT_C_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/c/*.cpp)
add_library(mbrt_c SHARED ${MBRT_C_SOURCES})
add_library(mbrt::c ALIAS mbrt_c)
set_target_properties(mbrt_c PROPERTIES
  OUTPUT_NAME mbrt
  EXPORT_NAME c
  VERSION ${PROJECT_VERSION}
  SOVERSION 0
  CXX_VISIBILITY_PRESET hidden
  VISIBILITY_INLINES_HIDDEN ON
  LINK_DEPENDS ${PROJECT_SOURCE_DIR}/src/c/exports.map)
target_include_directories(mbrt_c PUBLIC
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
target_include_directories(mbrt_c PRIVATE ${PROJECT_SOURCE_DIR}/src)
target_link_libraries(mbrt_c PRIVATE mbrt_io)
target_compile_options(mbrt_c PRIVATE ${MBRT_ISA_FLAGS} $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra>)
target_link_options(mbrt_c PRIVATE
  -Wl,--version-script=${PROJECT_SOURCE_DIR}/src/c/exports.map -Wl,--no-undefined)

install(TARGETS mbrt_c EXPORT mbrtTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})

# The static C library libmbrt.a, installed beside libmbrt.so: the C layer,
# the loaders, the scene suite and the kernel (mbrt_io, mbrt_scenes,
# mbrt_accel) merged into one archive, so that
# `cc app.c $(pkg-config --static --libs mbrt)` links without the shared one.
add_library(mbrt_c_part STATIC ${MBRT_C_SOURCES})
target_include_directories(mbrt_c_part PRIVATE ${PROJECT_SOURCE_DIR}/include ${PROJECT_SOURCE_DIR}/src)
target_link_libraries(mbrt_c_part PRIVATE mbrt_io)
target_compile_options(mbrt_c_part PRIVATE ${MBRT_ISA_FLAGS})
set(MBRT_C_STATIC ${PROJECT_BINARY_DIR}/static/libmbrt.a)
add_custom_command(OUTPUT ${MBRT_C_STATIC}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${PROJECT_BINARY_DIR}/static
  COMMAND ${CMAKE_COMMAND} -DOUTPUT=${MBRT_C_STATIC} -DAR=${CMAKE_AR}
          "-DINPUTS=$<TARGET_FILE:mbrt_c_part>|$<TARGET_FILE:mbrt_io>|$<TARGET_FILE:mbrt_scenes>|$<TARGET_FILE:mbrt_accel>"
          -P ${PROJECT_SOURCE_DIR}/cmake/MergeStatic.cmake
  DEPENDS mbrt_c_part mbrt_io mbrt_scenes mbrt_accel ${PROJECT_SOURCE_DIR}/cmake/MergeStatic.cmake VERBATIM)
add_custom_target(mbrt_c_static ALL DEPENDS ${MBRT_C_STATIC})
install(FILES ${MBRT_C_STATIC} DESTINATION ${CMAKE_INSTALL_LIBDIR})
# What a static link needs besides libmbrt.a (pkg-config --static): the
# loaders' libpng and OpenEXR as their own pkg-config files name them.
find_package(PkgConfig REQUIRED)
set(_mbrt_io_modules libpng)
if(MBRT_WITH_OPENEXR)
  list(APPEND _mbrt_io_modules OpenEXR)
endif()
execute_process(COMMAND ${PKG_CONFIG_EXECUTABLE} --libs ${_mbrt_io_modules}
                RESULT_VARIABLE _mbrt_pc_rc OUTPUT_VARIABLE _mbrt_io_libs OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT _mbrt_pc_rc EQUAL 0)
  message(FATAL_ERROR "pkg-config knows no ${_mbrt_io_modules}: the static libmbrt.a needs their link flags")
endif()
set(MBRT_PC_LIBS_PRIVATE "${_mbrt_io_libs} -ltbb -lstdc++ -lm -lpthread")
if(MBRT_WITH_EMBREE)
  string(PREPEND MBRT_PC_LIBS_PRIVATE "-lembree3 ")
endif()

# pkg-config: `cc trace.c $(pkg-config --cflags --libs mbrt)`. The prefix is
# found from the file's own place (${pcfiledir}), so that the file stays
# true wherever `cmake --install --prefix` puts it.
file(RELATIVE_PATH _mbrt_pc_to_prefix "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
string(REGEX REPLACE "/$" "" _mbrt_pc_to_prefix "${_mbrt_pc_to_prefix}")
file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/mbrt.pc @ONLY CONTENT
"prefix=\${pcfiledir}/@_mbrt_pc_to_prefix@
libdir=\${prefix}/@CMAKE_INSTALL_LIBDIR@
includedir=\${prefix}/@CMAKE_INSTALL_INCLUDEDIR@

Name: mbrt
Description: Motion-blur ray tracing (C API)
Version: @PROJECT_VERSION@
Libs: -L\${libdir} -lmbrt
Libs.private: @MBRT_PC_LIBS_PRIVATE@
Cflags: -I\${includedir}
")
install(FILES ${PROJECT_BINARY_DIR}/mbrt.pc DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

if(MBRT_BUILD_TESTS)
  enable_testing()
  find_package(Threads REQUIRED)
  set(_mbrt_c_warnings $<$<C_COMPILER_ID:GNU,Clang>:-Wall -Wextra -pedantic -Werror>)

  add_executable(mbrt_c_example ${PROJECT_SOURCE_DIR}/examples/c/trace.c)
  set_target_properties(mbrt_c_example PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
  target_compile_options(mbrt_c_example PRIVATE ${_mbrt_c_warnings})
  target_link_libraries(mbrt_c_example PRIVATE mbrt_c)
  add_test(NAME capi.example COMMAND mbrt_c_example)
  add_executable(mbrt_c_frames ${PROJECT_SOURCE_DIR}/examples/c/frames.c)
  set_target_properties(mbrt_c_frames PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
  target_compile_options(mbrt_c_frames PRIVATE ${_mbrt_c_warnings})
  target_link_libraries(mbrt_c_frames PRIVATE mbrt_c)
  add_test(NAME capi.frames_example COMMAND mbrt_c_frames)

  add_executable(mbrt_c_tests ${PROJECT_SOURCE_DIR}/tests/c/test_capi.c ${PROJECT_SOURCE_DIR}/tests/c/test_capi_errors.c
    ${PROJECT_SOURCE_DIR}/tests/c/test_capi_batches.c ${PROJECT_SOURCE_DIR}/tests/c/test_capi_auto.c
    ${PROJECT_SOURCE_DIR}/tests/c/capi_test.c)
  set_target_properties(mbrt_c_tests PROPERTIES C_STANDARD 99 C_STANDARD_REQUIRED ON C_EXTENSIONS OFF)
  target_compile_options(mbrt_c_tests PRIVATE ${_mbrt_c_warnings})
  target_link_libraries(mbrt_c_tests PRIVATE mbrt_c Threads::Threads m)
  target_compile_definitions(mbrt_c_tests PRIVATE MBRT_TEST_DATA="${PROJECT_SOURCE_DIR}/tests/data")
  # One CTest per case of tests/c/test_capi.c (its main runs the case named).
  foreach(case IN ITEMS version null_handles wrong_handles bad_arguments bad_kind error_callback
                        release_in_use frozen_scene time_range_and_mask srt_instances filters agreement batched soa
                        threads stats memory_budget auto_options animation animation_layouts animation_errors)
    add_test(NAME capi.${case} COMMAND mbrt_c_tests ${case})
  endforeach()
  set_tests_properties(capi.agreement PROPERTIES COST 500)  # a long one: started early

  # Only the C API leaves libmbrt.so.
  add_test(NAME capi.exports_only_c_api
           COMMAND bash ${PROJECT_SOURCE_DIR}/tests/c/check_exports.sh $<TARGET_FILE:mbrt_c>)
  # A sanitized libmbrt.so needs its runtime linked into the program first.
  set(MBRT_PLAIN_CC_FLAGS "")
  if(MBRT_SANITIZE)
    set(MBRT_PLAIN_CC_FLAGS "-fsanitize=${MBRT_SANITIZE}")
  endif()
  # A plain C compiler builds the example with mbrt.h alone and libmbrt.so.
  add_test(NAME capi.plain_cc
           COMMAND bash ${PROJECT_SOURCE_DIR}/tests/c/plain_cc.sh ${PROJECT_SOURCE_DIR}
                   $<TARGET_FILE_DIR:mbrt_c> ${PROJECT_BINARY_DIR}/capi_plain_cc "${MBRT_PLAIN_CC_FLAGS}")
  # The examples link statically against libmbrt.a alone (no libmbrt.so).
  add_test(NAME capi.static_link
           COMMAND bash ${PROJECT_SOURCE_DIR}/tests/c/static_link.sh ${PROJECT_SOURCE_DIR} ${MBRT_C_STATIC}
                   ${PROJECT_BINARY_DIR}/capi_static "${MBRT_PLAIN_CC_FLAGS} ${MBRT_PC_LIBS_PRIVATE}")
  # The example of docs/c-api.md compiles and runs.
  add_test(NAME capi.doc_example
           COMMAND bash ${PROJECT_SOURCE_DIR}/tests/c/doc_example.sh ${PROJECT_SOURCE_DIR}
                   $<TARGET_FILE_DIR:mbrt_c> ${PROJECT_BINARY_DIR}/capi_doc_example "${MBRT_PLAIN_CC_FLAGS}")
endif()
