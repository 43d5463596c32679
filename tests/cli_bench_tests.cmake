# `mbrt bench` from the command line: every option validated (exit 2 for a
# usage error, before any work), the outputs written, no terminal control
# codes in a log, and --scaling at tiny sizes. Each test checks the exit code
# (tests/cli_bench_run.cmake), not only the text.
set(MBRT_BENCH_RUN ${PROJECT_SOURCE_DIR}/tests/cli_bench_run.cmake)
set(MBRT_BENCH_OUT ${PROJECT_BINARY_DIR}/cli_test_output/bench)
file(MAKE_DIRECTORY ${MBRT_BENCH_OUT})

# mbrt_bench_test(NAME RC REGEX ARGS...): `mbrt bench ARGS` exits with RC and
# prints something matching REGEX.
function(mbrt_bench_test name rc regex)
  string(REPLACE ";" "|" args "${ARGN}")
  add_test(NAME cli.bench_${name}
           COMMAND ${CMAKE_COMMAND} "-DCMD=$<TARGET_FILE:mbrt_cli>|bench|${args}" -DRC=${rc} "-DREGEX=${regex}"
                   ${MBRT_BENCH_EXTRA} -P ${MBRT_BENCH_RUN})
endfunction()

# Usage errors: exit 2 with the option named.
mbrt_bench_test(rays_zero 2 "--rays" --rays 0)
mbrt_bench_test(rays_negative 2 "--rays" --rays -5)
mbrt_bench_test(repeats_zero 2 "--repeats" --repeats 0)
mbrt_bench_test(repeats_negative 2 "--repeats" --repeats -1)
mbrt_bench_test(budget_nan 2 "--budget.*finite" --budget nan)
mbrt_bench_test(budget_zero 2 "--budget" --budget 0)
mbrt_bench_test(size_negative 2 "--size" --size -1)
mbrt_bench_test(size_nan 2 "--size" --size nan)
mbrt_bench_test(frozen_times_zero 2 "--frozen-times" --frozen-times 0)
mbrt_bench_test(scene_empty 2 "--scene" --scene=)
mbrt_bench_test(scene_empty_item 2 "--scene: empty item" --scene translate,,rotate)
mbrt_bench_test(accel_bogus 2 "unknown accel 'bogus' \\(available: .*embree-robust" --accel bogus)
mbrt_bench_test(seed_negative 2 "--seed" --seed -1)
mbrt_bench_test(rays_file_two_scenes 2 "--rays-file needs exactly one --scene"
                --scene translate,rotate --rays-file ${MBRT_BENCH_OUT}/none.bin)
mbrt_bench_test(json_directory 2 "--json: .* is a directory" --json ${MBRT_BENCH_OUT})
mbrt_bench_test(scaling_sizes_bad 2 "--scaling-sizes: must be a finite number" --scaling --scaling-sizes 0.1,nan)
mbrt_bench_test(scaling_sizes_without_scaling 2 "--scaling-sizes needs --scaling" --scaling-sizes 0.1)

# A tiny run: every set with its hit rate, the geometric means, JSON and SVG
# written, and no control codes in what a log gets.
set(MBRT_BENCH_EXTRA -DNO_ESCAPES=1 "-DFILES=${MBRT_BENCH_OUT}/tiny.json={|${MBRT_BENCH_OUT}/tiny.svg=<svg")
mbrt_bench_test(tiny 0
  "Rays: primary [0-9]+ \\(hit [0-9.]+%\\), secondary [0-9]+ \\(hit [0-9.]+%\\).*shadow [0-9]+ \\(occluded [0-9.]+%\\), frozen [0-9]+ \\(hit [0-9.]+%\\).*\\| stbvh \\|.*Geometric mean over scenes"
  --quick --scene translate --size 0.005
  --accel bvh-interp,stbvh,frozen,embree,embree-robust,embree-static,embree-static-robust
  --repeats 1 --rays 24 --frozen-times 2 --json ${MBRT_BENCH_OUT}/tiny.json --svg ${MBRT_BENCH_OUT}/tiny.svg)

# --scaling at two tiny sizes: one row per size, and its chart.
set(MBRT_BENCH_EXTRA -DNO_ESCAPES=1 "-DFILES=${MBRT_BENCH_OUT}/scaling.svg=<svg|${MBRT_BENCH_OUT}/scaling.json={")
mbrt_bench_test(scaling_tiny 0
  "\\| translate \\| bvh-interp \\| 0.002 \\| [0-9]+ \\|.*\\| translate \\| bvh-interp \\| 0.004 \\|.*\\| hairball \\| bvh-interp \\| 0.002 \\|"
  --scaling --scaling-sizes 0.002,0.004 --accel bvh-interp --rays 16 --repeats 1
  --svg ${MBRT_BENCH_OUT}/scaling.svg --json ${MBRT_BENCH_OUT}/scaling.json)
set(MBRT_BENCH_EXTRA)
