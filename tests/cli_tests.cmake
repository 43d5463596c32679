# Tests of the `mbrt` command (included by the top-level CMakeLists.txt when
# both tests and tools are built). Each runs tests/cli/run_cli_test.sh, which
# checks the exit status, what was printed and the files written (with
# mbrt_cli_check: images decode to their size, hit files of the same rays
# and kind are identical, ray files round-trip).
set(MBRT_CLI_SCENE ${PROJECT_SOURCE_DIR}/tests/data/cube.obj)
set(MBRT_CLI_DATA ${PROJECT_SOURCE_DIR}/tests/data)
set(MBRT_CLI_OUT ${PROJECT_BINARY_DIR}/cli_test_output)
set(MBRT_CLI_RUNNER ${PROJECT_SOURCE_DIR}/tests/cli/run_cli_test.sh)
file(MAKE_DIRECTORY ${MBRT_CLI_OUT})
file(WRITE ${MBRT_CLI_OUT}/bad_rays.bin "not a multiple of 36 bytes")

add_executable(mbrt_cli_check ${PROJECT_SOURCE_DIR}/tests/cli/cli_check.cpp)
target_link_libraries(mbrt_cli_check PRIVATE mbrt::mbrt)

# Tests run in parallel: each writes its own files, and NO_TEMP looks at a
# folder only that test writes to.
# mbrt_cli_test(NAME [CODE n] [TIMEOUT s] [OUT regex...] [NO_OUT regex...]
#               [CHECK "mode args"...] [EXISTS path...] [ABSENT path...] [NO_TEMP dir]
#               [SETUP "shell"...] [AFTER "shell"...] [SIGNAL SIG regex] [REQUIRE path]
#               [PLAIN] [FIXTURES_SETUP name] [FIXTURES_REQUIRED name]
#               [SHELL "shell command line"] | ARGS mbrt arguments...)
# CODE defaults to 0; a missing REQUIRE path makes the test skipped (77).
function(mbrt_cli_test name)
  cmake_parse_arguments(PARSE_ARGV 1 T "PLAIN" "CODE;TIMEOUT;REQUIRE;NO_TEMP;FIXTURES_SETUP;FIXTURES_REQUIRED;SHELL"
                        "OUT;NO_OUT;CHECK;EXISTS;ABSENT;SETUP;AFTER;SIGNAL;ARGS")
  set(cmd bash ${MBRT_CLI_RUNNER} --checker $<TARGET_FILE:mbrt_cli_check>)
  if(DEFINED T_CODE)
    list(APPEND cmd --code ${T_CODE})
  endif()
  if(DEFINED T_TIMEOUT)
    list(APPEND cmd --timeout ${T_TIMEOUT})
  endif()
  if(DEFINED T_REQUIRE)
    list(APPEND cmd --require ${T_REQUIRE})
  endif()
  if(DEFINED T_NO_TEMP)
    list(APPEND cmd --no-temp ${T_NO_TEMP})
  endif()
  if(T_PLAIN)
    list(APPEND cmd --no-control-codes)
  endif()
  foreach(kind OUT NO_OUT CHECK EXISTS ABSENT SETUP AFTER)
    string(TOLOWER ${kind} flag)
    string(REPLACE "_" "-" flag ${flag})
    foreach(value IN LISTS T_${kind})
      list(APPEND cmd --${flag} "${value}")
    endforeach()
  endforeach()
  if(T_SIGNAL)
    list(APPEND cmd --signal ${T_SIGNAL})
  endif()
  if(DEFINED T_SHELL)
    # $MBRT stands for the command in the shell line.
    list(APPEND cmd -- env MBRT=$<TARGET_FILE:mbrt_cli> bash -c "${T_SHELL}")
  else()
    list(APPEND cmd -- $<TARGET_FILE:mbrt_cli> ${T_ARGS})
  endif()
  add_test(NAME ${name} COMMAND ${cmd})
  # The runner stops the command after its own timeout; CTest's is a backstop.
  if(DEFINED T_TIMEOUT)
    math(EXPR ctest_timeout "${T_TIMEOUT} + 60")
  else()
    set(ctest_timeout 180)
  endif()
  set_tests_properties(${name} PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT ${ctest_timeout})
  if(T_FIXTURES_SETUP)
    set_tests_properties(${name} PROPERTIES FIXTURES_SETUP ${T_FIXTURES_SETUP})
  endif()
  if(T_FIXTURES_REQUIRED)
    set_tests_properties(${name} PROPERTIES FIXTURES_REQUIRED ${T_FIXTURES_REQUIRED})
  endif()
endfunction()

set(O ${MBRT_CLI_OUT})

# ---- basic runs: exit 0 and the files they write ----------------------------
mbrt_cli_test(cli.version OUT "^mbrt ${PROJECT_VERSION}$" ARGS --version)
mbrt_cli_test(cli.stats OUT "^primitives +12$" "^kind +brute" ARGS stats --scene ${MBRT_CLI_SCENE} --accel brute)
mbrt_cli_test(cli.stats_json OUT "\"primitives\": 12," "^}$" ARGS stats --scene ${MBRT_CLI_SCENE} --accel brute --json)
# The positional scene, as render takes it.
mbrt_cli_test(cli.stats_positional OUT "^primitives +12$" ARGS stats ${MBRT_CLI_SCENE} --accel brute)

# Rays generated and traced in memory, then read back from the file and
# traced again with the same kind: the file round-trips and the two hit
# files are the same bytes.
mbrt_cli_test(cli.trace_generate
  SETUP "rm -f ${O}/rays.bin ${O}/hits.bin"
  OUT "rays +2000: [1-9][0-9]* hits, [1-9][0-9]* misses, 0 invalid" "^wrote +.*hits.bin$"
  CHECK "rays ${O}/rays.bin 2000" "hits ${O}/hits.bin 2000"
  FIXTURES_SETUP cli_rays
  ARGS trace --scene ${MBRT_CLI_SCENE} --accel brute --generate 2000 --rays ${O}/rays.bin --hits ${O}/hits.bin)
mbrt_cli_test(cli.trace_file
  SETUP "rm -f ${O}/hits2.bin"
  OUT "rays +2000: [1-9][0-9]* hits"
  CHECK "same ${O}/hits.bin ${O}/hits2.bin"
  FIXTURES_REQUIRED cli_rays
  ARGS trace ${MBRT_CLI_SCENE} --accel brute --rays ${O}/rays.bin --hits ${O}/hits2.bin)

# A moving built-in scene with the default structure (auto, as every
# subcommand's default), and its ray file traced again.
mbrt_cli_test(cli.trace_procedural
  SETUP "rm -f ${O}/translate_rays.bin ${O}/translate_hits.bin"
  OUT "^accel +auto," "rays +1000: [1-9][0-9]* hits, [0-9]+ misses, 0 invalid"
  CHECK "rays ${O}/translate_rays.bin 1000" "hits ${O}/translate_hits.bin 1000"
  FIXTURES_SETUP cli_translate_rays
  ARGS trace --scene translate --size 0.005 --generate 1000
       --rays ${O}/translate_rays.bin --hits ${O}/translate_hits.bin)
mbrt_cli_test(cli.trace_procedural_file
  SETUP "rm -f ${O}/translate_hits2.bin"
  OUT "^accel +auto,"
  CHECK "same ${O}/translate_hits.bin ${O}/translate_hits2.bin"
  FIXTURES_REQUIRED cli_translate_rays
  ARGS trace translate --size 0.005 --accel auto --rays ${O}/translate_rays.bin --hits ${O}/translate_hits2.bin)
# crowd at 0.2 (90,000 triangles): above the flat trial, its objects stay instances.
mbrt_cli_test(cli.stats_default_kind OUT "^kind +auto " "^object 0: geometry 0, all [0-9]+ triangles: rigid" ARGS stats crowd --size 0.2)

mbrt_cli_test(cli.render
  SETUP "rm -rf ${O}/render && mkdir ${O}/render"
  OUT "^wrote +.*render.png$"
  CHECK "image ${O}/render/render.png 32 18 nonblack"
  NO_TEMP ${O}/render
  ARGS render --scene ${MBRT_CLI_SCENE} --accel brute --width 32 --height 18 --spp 2 --out ${O}/render/render.png)

# An OBJ keyframe sequence given as a glob (quoted on a shell command line).
mbrt_cli_test(cli.stats_obj_sequence OUT "OBJ sequence: 2 keys" "^primitives +"
  ARGS stats --scene ${MBRT_CLI_DATA}/keys/key_*.obj --accel brute --load-info)

# ---- `mbrt render`: the demo by default, heat maps, EXR ---------------------
mbrt_cli_test(cli.render_default_demo
  SETUP "rm -f ${O}/demo.png"
  OUT "^scene +demo" "^accel +auto," "^render +auto: 32x24, 1 spp.*Mrays/s" "^wrote +.*demo.png$"
  CHECK "image ${O}/demo.png 32 24 nonblack"
  ARGS render --size 0.25 --width 32 --height 24 --spp 1 -o ${O}/demo.png)
mbrt_cli_test(cli.render_positional_heat
  SETUP "rm -f ${O}/heat.png"
  OUT "^accel +bvh-segments" "^heat +bvh-segments: nodes visited per primary ray: mean [0-9.]+" "colour bar 0 \\.\\."
  CHECK "image ${O}/heat.png 32 36 nonblack"  # 24 rows and the colour bar
  ARGS render demo --size 0.25 --accel bvh-segments --integrator heat-steps
       --width 32 --height 24 --spp 1 --threads 1 -o ${O}/heat.png)
mbrt_cli_test(cli.render_compare
  SETUP "rm -f ${O}/compare.png"
  OUT "^heat +bvh-interp: intersection tests" "^heat +bvh-segments: intersection tests" "^wrote"
  CHECK "image ${O}/compare.png 52 36 nonblack"  # 24 + 4 + 24 wide
  ARGS render hairball --size 0.002 --accel bvh-interp --compare bvh-segments
       --integrator heat-isects --width 24 --height 24 --spp 1 -o ${O}/compare.png)
if(MBRT_WITH_OPENEXR)
  mbrt_cli_test(cli.render_exr
    SETUP "rm -f ${O}/demo.exr"
    OUT "^wrote +.*demo.exr$"
    CHECK "image ${O}/demo.exr 16 12 nonblack"
    ARGS render --scene demo --size 0.25 --integrator ao --width 16 --height 12 --spp 1 -o ${O}/demo.exr)
else()
  mbrt_cli_test(cli.render_exr CODE 1 OUT "EXR support is not built" NO_OUT "^scene"
    ARGS render --scene demo --size 0.25 --width 16 --height 12 -o ${O}/demo.exr)
endif()
# The fuzzy kd-tree's cluster picture (its paper's Fig. 1) at a sharp instant.
mbrt_cli_test(cli.render_clusters
  SETUP "rm -f ${O}/clusters.png"
  OUT "^wrote +.*clusters.png$"
  CHECK "image ${O}/clusters.png 24 24 nonblack"
  ARGS render skinned --size 0.05 --accel fuzzykd --integrator clusters --camera-shutter 0.5,0.5
       --width 24 --height 24 --spp 1 -o ${O}/clusters.png)
# auto's objects (instances extracted from rigid motion) in the same picture.
mbrt_cli_test(cli.render_clusters_auto
  SETUP "rm -f ${O}/clusters_auto.png"
  OUT "^wrote +.*clusters_auto.png$"
  CHECK "image ${O}/clusters_auto.png 24 24 nonblack"
  ARGS render crowd --size 0.05 --accel auto --integrator clusters --width 24 --height 24 --spp 1
       -o ${O}/clusters_auto.png)
# For an input without a clock, --shutter is the part of the normalized shutter.
mbrt_cli_test(cli.render_shutter_obj
  OUT "shutter \\[0.25, 0.5\\]"
  CHECK "image ${O}/shutter.png 8 8"
  ARGS render ${MBRT_CLI_SCENE} --shutter 0.25,0.5 --width 8 --height 8 --spp 1 -o ${O}/shutter.png)
# A loaded model stands on the stage (a ground plane and a sun) unless --no-stage.
mbrt_cli_test(cli.render_stage
  OUT "^stage +ground plane" "2 geometries"
  CHECK "image ${O}/stage.png 8 8 nonblack"
  ARGS render ${MBRT_CLI_SCENE} --width 8 --height 8 --spp 1 -o ${O}/stage.png)
mbrt_cli_test(cli.render_no_stage
  NO_OUT "^stage"
  OUT "1 geometries"
  ARGS render ${MBRT_CLI_SCENE} --no-stage --width 8 --height 8 --spp 1 -o ${O}/no_stage.png)
mbrt_cli_test(cli.render_scene_file
  CHECK "image ${O}/scene_file.png 16 16 nonblack"
  ARGS render ${MBRT_CLI_DATA}/cube_scene.json --width 16 --height 16 --spp 1 -o ${O}/scene_file.png)

# ---- `mbrt bench`: rays from a file, and a real scene when ../shared is there
mbrt_cli_test(cli.bench_rays_file_make
  SETUP "rm -f ${O}/bench_rays.bin"
  CHECK "rays ${O}/bench_rays.bin 2000"
  FIXTURES_SETUP cli_bench_rays
  ARGS trace --scene translate --size 0.005 --generate 2000 --rays ${O}/bench_rays.bin)
mbrt_cli_test(cli.bench_rays_file
  SETUP "rm -f ${O}/bench.svg"
  OUT "translate \\([0-9]+ primitives, 2000 rays\\)" "\\| stbvh \\|"
  EXISTS ${O}/bench.svg
  FIXTURES_REQUIRED cli_bench_rays
  ARGS bench --quick --scene translate --size 0.005 --accel bvh-interp,stbvh --repeats 1
       --frozen-times 2 --rays-file ${O}/bench_rays.bin --svg ${O}/bench.svg)
# Registered whether or not the data is there: skipped, with the reason, without it.
mbrt_cli_test(cli.bench_real_scene
  REQUIRE ${PROJECT_SOURCE_DIR}/../shared/scenes/wooddoll_utah
  OUT "wooddoll \\(6658 primitives"
  ARGS bench --quick --scene wooddoll --accel bvh-interp --repeats 1 --rays 16 --frozen-times 2)

include(${PROJECT_SOURCE_DIR}/tests/cli_error_tests.cmake)
include(${PROJECT_SOURCE_DIR}/tests/cli_frames_tests.cmake)
include(${CMAKE_CURRENT_LIST_DIR}/cli_bench_tests.cmake)
