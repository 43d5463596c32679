# Runs the `mbrt` command on a tiny OBJ scene (included by the top-level
# CMakeLists.txt when both tests and tools are built).
set(MBRT_CLI_SCENE ${PROJECT_SOURCE_DIR}/tests/data/cube.obj)
set(MBRT_CLI_OUT ${PROJECT_BINARY_DIR}/cli_test_output)
file(MAKE_DIRECTORY ${MBRT_CLI_OUT})
file(WRITE ${MBRT_CLI_OUT}/bad_rays.bin "not a multiple of 36 bytes")

add_test(NAME cli.version COMMAND mbrt_cli --version)
set_tests_properties(cli.version PROPERTIES PASS_REGULAR_EXPRESSION "^mbrt ${PROJECT_VERSION}")

add_test(NAME cli.stats COMMAND mbrt_cli stats --scene ${MBRT_CLI_SCENE} --accel brute)
set_tests_properties(cli.stats PROPERTIES PASS_REGULAR_EXPRESSION "primitives +12")

add_test(NAME cli.stats_json COMMAND mbrt_cli stats --scene ${MBRT_CLI_SCENE} --accel brute --json)
set_tests_properties(cli.stats_json PROPERTIES PASS_REGULAR_EXPRESSION "\"primitives\": 12,")

add_test(NAME cli.trace_generate
         COMMAND mbrt_cli trace --scene ${MBRT_CLI_SCENE} --accel brute --generate 2000
                 --rays ${MBRT_CLI_OUT}/rays.bin --hits ${MBRT_CLI_OUT}/hits.bin)
set_tests_properties(cli.trace_generate PROPERTIES
  PASS_REGULAR_EXPRESSION "rays +2000: [1-9][0-9]* hits, [1-9][0-9]* misses, 0 invalid"
  FIXTURES_SETUP cli_rays)

add_test(NAME cli.trace_file
         COMMAND mbrt_cli trace --scene ${MBRT_CLI_SCENE} --accel brute
                 --rays ${MBRT_CLI_OUT}/rays.bin --hits ${MBRT_CLI_OUT}/hits2.bin)
set_tests_properties(cli.trace_file PROPERTIES
  PASS_REGULAR_EXPRESSION "rays +2000: [1-9][0-9]* hits"
  FIXTURES_REQUIRED cli_rays)

add_test(NAME cli.render
         COMMAND mbrt_cli render --scene ${MBRT_CLI_SCENE} --accel brute --width 32 --height 18 --spp 2
                 --out ${MBRT_CLI_OUT}/render.png)
set_tests_properties(cli.render PROPERTIES PASS_REGULAR_EXPRESSION "wrote +.*render.png")

# Errors: a message, no crash, the documented exit codes (2 usage, 1 failure).
add_test(NAME cli.error_bad_accel COMMAND mbrt_cli stats --scene ${MBRT_CLI_SCENE} --accel nope)
set_tests_properties(cli.error_bad_accel PROPERTIES
  PASS_REGULAR_EXPRESSION "mbrt: error: .*unknown accel kind 'nope' \\(available: brute")
add_test(NAME cli.error_bad_accel_code COMMAND mbrt_cli stats --scene ${MBRT_CLI_SCENE} --accel nope)
set_tests_properties(cli.error_bad_accel_code PROPERTIES WILL_FAIL TRUE)

add_test(NAME cli.error_bad_ray_file
         COMMAND mbrt_cli trace --scene ${MBRT_CLI_SCENE} --accel brute
                 --rays ${MBRT_CLI_OUT}/bad_rays.bin --hits ${MBRT_CLI_OUT}/bad_hits.bin)
set_tests_properties(cli.error_bad_ray_file PROPERTIES
  PASS_REGULAR_EXPRESSION "mbrt: error: .*bad_rays.bin: size 26 bytes is not a multiple of 36")

add_test(NAME cli.error_missing_scene COMMAND mbrt_cli stats --scene ${MBRT_CLI_OUT}/missing.obj --accel brute)
set_tests_properties(cli.error_missing_scene PROPERTIES
  PASS_REGULAR_EXPRESSION "mbrt: error: cannot open '.*missing.obj'")

add_test(NAME cli.error_no_subcommand COMMAND mbrt_cli)
set_tests_properties(cli.error_no_subcommand PROPERTIES PASS_REGULAR_EXPRESSION "mbrt: error: ")

# A small built-in scene with the default structure.
add_test(NAME cli.trace_procedural
         COMMAND mbrt_cli trace --scene translate --size 0.005 --generate 1000
                 --rays ${MBRT_CLI_OUT}/translate_rays.bin --hits ${MBRT_CLI_OUT}/translate_hits.bin)
set_tests_properties(cli.trace_procedural PROPERTIES
  PASS_REGULAR_EXPRESSION "rays +1000: [1-9][0-9]* hits, [0-9]+ misses, 0 invalid")
add_test(NAME cli.error_unknown_scene COMMAND mbrt_cli stats --scene no-such-scene)
set_tests_properties(cli.error_unknown_scene PROPERTIES
  PASS_REGULAR_EXPRESSION "mbrt: error: unknown scene 'no-such-scene'.*translate")

# An OBJ keyframe sequence given as a glob (quoted on a shell command line).
add_test(NAME cli.stats_obj_sequence
         COMMAND mbrt_cli stats --scene ${PROJECT_SOURCE_DIR}/tests/data/keys/key_*.obj --accel brute --load-info)
set_tests_properties(cli.stats_obj_sequence PROPERTIES
  PASS_REGULAR_EXPRESSION "OBJ sequence: 2 keys")
add_test(NAME cli.error_bad_steps COMMAND mbrt_cli stats --scene ${MBRT_CLI_SCENE} --steps zero)
set_tests_properties(cli.error_bad_steps PROPERTIES
  PASS_REGULAR_EXPRESSION "--steps must be a number")
# `mbrt render`: the demo by default, heat maps, EXR, errors.
add_test(NAME cli.render_default_demo
         COMMAND mbrt_cli render --size 0.25 --width 32 --height 24 --spp 1 -o ${MBRT_CLI_OUT}/demo.png)
set_tests_properties(cli.render_default_demo PROPERTIES
  PASS_REGULAR_EXPRESSION "scene +demo.*render +[a-z-]+: 32x24, 1 spp.*Mrays/s.*wrote +.*demo.png")
add_test(NAME cli.render_positional_heat
         COMMAND mbrt_cli render demo --size 0.25 --accel bvh-segments --integrator heat-steps
                 --width 32 --height 24 --spp 1 --threads 1 -o ${MBRT_CLI_OUT}/heat.png)
set_tests_properties(cli.render_positional_heat PROPERTIES
  PASS_REGULAR_EXPRESSION "accel +bvh-segments.*heat +bvh-segments: nodes visited per primary ray: mean [0-9.]+.*colour bar 0 \\.\\.")
add_test(NAME cli.render_compare
         COMMAND mbrt_cli render hairball --size 0.002 --accel bvh-interp --compare bvh-segments
                 --integrator heat-isects --width 24 --height 24 --spp 1 -o ${MBRT_CLI_OUT}/compare.png)
set_tests_properties(cli.render_compare PROPERTIES
  PASS_REGULAR_EXPRESSION "heat +bvh-interp: intersection tests.*heat +bvh-segments: intersection tests.*wrote")
if(MBRT_WITH_OPENEXR)
  add_test(NAME cli.render_exr
           COMMAND mbrt_cli render --scene demo --size 0.25 --integrator ao --width 16 --height 12 --spp 1
                   -o ${MBRT_CLI_OUT}/demo.exr)
  set_tests_properties(cli.render_exr PROPERTIES PASS_REGULAR_EXPRESSION "wrote +.*demo.exr")
else()
  add_test(NAME cli.render_exr
           COMMAND mbrt_cli render --scene demo --size 0.25 --width 16 --height 12 -o ${MBRT_CLI_OUT}/demo.exr)
  set_tests_properties(cli.render_exr PROPERTIES PASS_REGULAR_EXPRESSION "EXR support is not built")
endif()
add_test(NAME cli.error_render_format COMMAND mbrt_cli render --scene demo -o ${MBRT_CLI_OUT}/demo.jpg)
set_tests_properties(cli.error_render_format PROPERTIES
  PASS_REGULAR_EXPRESSION "mbrt: error: cannot tell the image format of '.*demo.jpg': use a .png or .exr")
add_test(NAME cli.error_render_integrator COMMAND mbrt_cli render --scene demo --integrator nope)
set_tests_properties(cli.error_render_integrator PROPERTIES
  PASS_REGULAR_EXPRESSION "mbrt: error: unknown integrator 'nope' \\(available: normals, ao, path")
add_test(NAME cli.error_render_shutter COMMAND mbrt_cli render --scene demo --shutter 0.5,0.2)
set_tests_properties(cli.error_render_shutter PROPERTIES PASS_REGULAR_EXPRESSION "mbrt: error: .*shutter")
# `mbrt bench`: rays from a file, and a real scene by name when ../shared is there.
add_test(NAME cli.bench_rays_file_make
         COMMAND mbrt_cli trace --scene translate --size 0.005 --generate 2000 --rays ${MBRT_CLI_OUT}/bench_rays.bin)
add_test(NAME cli.bench_rays_file
         COMMAND mbrt_cli bench --quick --scene translate --size 0.005 --accel bvh-interp,stbvh --repeats 1
                 --frozen-times 2 --rays-file ${MBRT_CLI_OUT}/bench_rays.bin --svg ${MBRT_CLI_OUT}/bench.svg)
set_tests_properties(cli.bench_rays_file PROPERTIES DEPENDS cli.bench_rays_file_make
  PASS_REGULAR_EXPRESSION "translate \\([0-9]+ primitives, 2000 rays\\).*\\| stbvh \\|")
if(EXISTS "${PROJECT_SOURCE_DIR}/../shared/scenes/wooddoll_utah")
  add_test(NAME cli.bench_real_scene
           COMMAND mbrt_cli bench --quick --scene wooddoll --accel bvh-interp --repeats 1 --rays 16 --frozen-times 2)
  set_tests_properties(cli.bench_real_scene PROPERTIES
    PASS_REGULAR_EXPRESSION "wooddoll \\(6658 primitives")
endif()

# Absurd render sizes and sample counts are refused with a message (exit 2).
add_test(NAME cli.error_render_width COMMAND mbrt_cli render --scene ${MBRT_CLI_SCENE} --width 100000 -o ${MBRT_CLI_OUT}/w.png)
set_tests_properties(cli.error_render_width PROPERTIES PASS_REGULAR_EXPRESSION "--width: Value 100000 not in range")
add_test(NAME cli.error_render_height COMMAND mbrt_cli render --scene ${MBRT_CLI_SCENE} --height 0 -o ${MBRT_CLI_OUT}/h.png)
set_tests_properties(cli.error_render_height PROPERTIES PASS_REGULAR_EXPRESSION "--height: Value 0 not in range")
add_test(NAME cli.error_render_spp COMMAND mbrt_cli render --scene ${MBRT_CLI_SCENE} --spp -3 -o ${MBRT_CLI_OUT}/s.png)
set_tests_properties(cli.error_render_spp PROPERTIES PASS_REGULAR_EXPRESSION "--spp: Value -3 not in range")
add_test(NAME cli.error_render_spp_huge COMMAND mbrt_cli render --scene ${MBRT_CLI_SCENE} --spp 1e12 -o ${MBRT_CLI_OUT}/s.png)
set_tests_properties(cli.error_render_spp_huge PROPERTIES PASS_REGULAR_EXPRESSION "mbrt: error: .*--spp")
add_test(NAME cli.error_render_total COMMAND mbrt_cli render --scene ${MBRT_CLI_SCENE} --width 16384 --height 16384 --spp 65536 -o ${MBRT_CLI_OUT}/t.png)
set_tests_properties(cli.error_render_total PROPERTIES PASS_REGULAR_EXPRESSION "mbrt: error: render: width x height x spp")

# The fuzzy kd-tree's cluster picture (its paper's Fig. 1), a sharp instant of
# the shutter, and their usage errors.
add_test(NAME cli.render_clusters
         COMMAND mbrt_cli render skinned --size 0.05 --accel fuzzykd --integrator clusters --camera-shutter 0.5,0.5
                 --width 24 --height 24 --spp 1 -o ${MBRT_CLI_OUT}/clusters.png)
set_tests_properties(cli.render_clusters PROPERTIES PASS_REGULAR_EXPRESSION "wrote +.*clusters.png")
add_test(NAME cli.error_render_clusters_accel
         COMMAND mbrt_cli render skinned --size 0.05 --accel bvh-interp --integrator clusters -o ${MBRT_CLI_OUT}/c.png)
set_tests_properties(cli.error_render_clusters_accel PROPERTIES PASS_REGULAR_EXPRESSION "mbrt: error: .*fuzzykd")
add_test(NAME cli.error_render_camera_shutter
         COMMAND mbrt_cli render demo --camera-shutter 0.7,0.2 -o ${MBRT_CLI_OUT}/c.png)
set_tests_properties(cli.error_render_camera_shutter PROPERTIES PASS_REGULAR_EXPRESSION "mbrt: error: .*camera-shutter")
include(${CMAKE_CURRENT_LIST_DIR}/cli_bench_tests.cmake)
