# Errors and hostile inputs of the `mbrt` command (included by
# cli_tests.cmake, which defines mbrt_cli_test): each gets a message and the
# documented exit status (2 usage error, 1 failure, 130/143 stopped by a
# signal), never a crash, a hang or a silent wrong answer; see
# docs/robustness.md's catalogue.
set(S ${MBRT_CLI_SCENE})

# ---- usage errors: exit 2 --------------------------------------------------
mbrt_cli_test(cli.error_no_subcommand CODE 2 OUT "^mbrt: error: ")
set(stats_args stats ${S})
set(trace_args trace ${S} --rays ${O}/rays_unused.bin --hits ${O}/hits_unused.bin)
set(render_args render ${S} -o ${O}/unused.png)
foreach(cmd stats trace render)
  mbrt_cli_test(cli.error_bad_accel_${cmd} CODE 2
    OUT "mbrt: error: .*unknown accel kind 'nope' \\(available: brute"
    ARGS ${${cmd}_args} --accel nope)
endforeach()
mbrt_cli_test(cli.error_render_compare_kind CODE 2 OUT "unknown accel kind 'nope' for --compare"
  ARGS render ${S} --compare nope -o ${O}/unused.png)
mbrt_cli_test(cli.error_unknown_scene CODE 2 OUT "mbrt: error: unknown scene 'no-such-scene'.*translate"
  ARGS stats --scene no-such-scene)
mbrt_cli_test(cli.error_no_scene CODE 2 OUT "mbrt: error: no scene given" ARGS stats)
mbrt_cli_test(cli.error_empty_scene CODE 2 OUT "mbrt: error: --scene" ARGS stats --scene=)
mbrt_cli_test(cli.error_empty_positional_scene CODE 2 OUT "mbrt: error: the scene name is empty"
  SHELL "exec \"$MBRT\" stats ''")
mbrt_cli_test(cli.error_two_scenes CODE 2 OUT "two scenes given" ARGS stats translate --scene rotate)
mbrt_cli_test(cli.error_bad_steps CODE 2 OUT "--steps must be a number" ARGS stats ${O}/any.gltf --steps zero)
mbrt_cli_test(cli.error_size_negative CODE 2 OUT "--size: must be a number in \\(0, " ARGS stats translate --size -1)
mbrt_cli_test(cli.error_size_nan CODE 2 OUT "--size: must be a number in" ARGS stats translate --size nan)
mbrt_cli_test(cli.error_seed_negative CODE 2 OUT "--seed: must be a whole number" ARGS stats translate --seed -1)
mbrt_cli_test(cli.error_seed_too_big CODE 2 OUT "--seed: must be a whole number"
  ARGS stats translate --seed 18446744073709551616)
mbrt_cli_test(cli.trace_seed_largest
  CHECK "rays ${O}/seed_rays.bin 10"
  ARGS trace ${S} --seed 18446744073709551615 --generate 10 --rays ${O}/seed_rays.bin)
mbrt_cli_test(cli.error_threads_huge CODE 2 OUT "--threads: Value 1000000 not in range 0 to [0-9]+"
  ARGS render ${S} --threads 1000000 -o ${O}/unused.png)
mbrt_cli_test(cli.error_exposure_nan CODE 2 OUT "--exposure: must be a number in \\[-64, 64\\], got 'nan'"
  ABSENT ${O}/exposure.png ARGS render ${S} --exposure nan -o ${O}/exposure.png)
mbrt_cli_test(cli.error_aperture_nan CODE 2 OUT "--aperture: must be a number" ARGS render ${S} --aperture nan)
mbrt_cli_test(cli.error_fps_inf CODE 2 OUT "--fps: must be a number" ARGS stats x.gltf --fps inf)
mbrt_cli_test(cli.error_memory_budget_bad CODE 2 OUT "--memory-budget: must be a whole number of bytes"
  ARGS stats ${S} --memory-budget lots)
# A sign or a count past 2^64 - 1 bytes is refused, not wrapped around.
mbrt_cli_test(cli.error_memory_budget_negative CODE 2 OUT "--memory-budget: must be a whole number of bytes"
  ARGS stats ${S} --memory-budget -5)
mbrt_cli_test(cli.error_memory_budget_overflow CODE 2 OUT "got '16777216TiB': more than 2\\^64 - 1 bytes"
  ARGS stats ${S} --memory-budget 16777216TiB)
mbrt_cli_test(cli.error_generate_huge CODE 2 OUT "--generate: Value 200000000 not in range 1 to 119304647"
  ARGS trace ${S} --generate 200000000 --rays ${O}/unused.bin)
# Options that do not apply to the input are refused, not ignored.
mbrt_cli_test(cli.error_motion_gltf CODE 2 OUT "--motion applies to static .obj and .ply meshes.*a glTF file"
  ARGS stats ${O}/any.gltf --motion rotate:90)
mbrt_cli_test(cli.error_motion_builtin CODE 2 OUT "--motion applies to static .obj and .ply meshes"
  ARGS render translate --motion rotate:90 -o ${O}/unused.png)
mbrt_cli_test(cli.error_clip_obj CODE 2 OUT "--clip applies to glTF and JSON scene files, not to .*cube.obj"
  ARGS stats ${S} --clip 0)
mbrt_cli_test(cli.error_shutter_obj CODE 2 OUT "--shutter applies to glTF and JSON scene files"
  ARGS trace ${S} --shutter 0,1 --generate 10 --rays ${O}/unused.bin)
mbrt_cli_test(cli.error_size_obj CODE 2 OUT "--size applies to built-in scenes" ARGS stats ${S} --size 2)
mbrt_cli_test(cli.error_seed_stats_obj CODE 2 OUT "--seed applies to built-in scenes" ARGS stats ${S} --seed 3)
mbrt_cli_test(cli.error_accel_without_tracing CODE 2 OUT "--accel applies when rays are traced"
  ARGS trace ${S} --generate 10 --rays ${O}/unused.bin --accel bvh-interp)
mbrt_cli_test(cli.error_steps_sequence CODE 2 OUT "--steps applies to glTF"
  ARGS stats ${MBRT_CLI_DATA}/keys --steps 4)
# The procedural motion's steps are capped (rotate:2e8 would need 2e7 copies of the mesh).
mbrt_cli_test(cli.error_motion_steps_cap CODE 2
  OUT "--motion: motion 'rotate:2e8': rotating by 2e8 degrees needs 20000001 steps.*more than the limit of 1024"
  NO_OUT "^scene" ARGS stats --scene ${S} --motion rotate:2e8)
mbrt_cli_test(cli.stats_motion_at_cap OUT "1024 time steps at most" ARGS stats ${S} --motion rotate:10230 --accel brute)
mbrt_cli_test(cli.error_hits_are_rays CODE 2 OUT "--hits and --rays name the same file"
  SETUP "rm -rf ${O}/same && mkdir ${O}/same && printf '' > ${O}/same/r.bin"
  AFTER "test -f ${O}/same/r.bin && test ! -s ${O}/same/r.bin"
  ARGS trace ${S} --rays ${O}/same/r.bin --hits ${O}/same/../same/r.bin)
mbrt_cli_test(cli.error_output_is_scene CODE 2 OUT "--out and the scene name the same file"
  SETUP "cp ${S} ${O}/scene_copy.png"
  CHECK "same ${S} ${O}/scene_copy.png"
  ARGS render ${O}/scene_copy.png -o ${O}/scene_copy.png)
mbrt_cli_test(cli.error_render_format CODE 2 OUT "cannot tell the image format of '.*demo.jpg': use a .png or .exr"
  ARGS render --scene demo -o ${O}/demo.jpg)
mbrt_cli_test(cli.error_render_integrator CODE 2 OUT "unknown integrator 'nope' \\(available: normals, ao, path"
  ARGS render --scene demo --integrator nope)
mbrt_cli_test(cli.error_render_shutter CODE 2 OUT "mbrt: error: .*shutter" ARGS render --scene demo --shutter 0.5,0.2)
mbrt_cli_test(cli.error_render_width CODE 2 OUT "--width: Value 100000 not in range"
  ARGS render ${S} --width 100000 -o ${O}/w.png)
mbrt_cli_test(cli.error_render_height CODE 2 OUT "--height: Value 0 not in range" ARGS render ${S} --height 0 -o ${O}/h.png)
mbrt_cli_test(cli.error_render_spp CODE 2 OUT "--spp: Value -3 not in range" ARGS render ${S} --spp -3 -o ${O}/s.png)
mbrt_cli_test(cli.error_render_spp_huge CODE 2 OUT "mbrt: error: .*--spp" ARGS render ${S} --spp 1e12 -o ${O}/s.png)
mbrt_cli_test(cli.error_render_total CODE 2 OUT "--width x --height x --spp = [0-9]+ camera samples is more than"
  NO_OUT "^scene" ARGS render ${S} --width 16384 --height 16384 --spp 65536 -o ${O}/t.png)
mbrt_cli_test(cli.error_render_clusters_accel CODE 2 OUT "mbrt: error: .*fuzzykd.*auto"
  ARGS render skinned --size 0.05 --accel bvh-interp --integrator clusters -o ${O}/c.png)
mbrt_cli_test(cli.error_render_camera_shutter CODE 2 OUT "mbrt: error: .*camera-shutter"
  ARGS render demo --camera-shutter 0.7,0.2 -o ${O}/c.png)

# ---- failures: exit 1 ------------------------------------------------------
mbrt_cli_test(cli.error_bad_ray_file CODE 1 OUT "mbrt: error: .*bad_rays.bin: size 26 bytes is not a multiple of 36"
  SETUP "rm -f ${O}/bad_hits.bin" ABSENT ${O}/bad_hits.bin
  ARGS trace --scene ${S} --accel brute --rays ${O}/bad_rays.bin --hits ${O}/bad_hits.bin)
mbrt_cli_test(cli.error_missing_scene CODE 1 OUT "mbrt: error: cannot open '.*missing.obj'"
  ARGS stats --scene ${O}/missing.obj --accel brute)
mbrt_cli_test(cli.error_light_negative CODE 1 OUT "'light radiance' values must be in \\[0, 1e6\\], got \\[1.0,-2.0,1.0\\]"
  ARGS render ${MBRT_CLI_DATA}/negative_light.json -o ${O}/unused.png)
set(stats_args stats translate --size 0.005)
set(trace_args trace translate --size 0.005 --generate 10 --rays ${O}/budget_rays.bin --hits ${O}/budget_hits.bin)
set(render_args render translate --size 0.005 -o ${O}/budget.png)
foreach(cmd stats trace render)
  mbrt_cli_test(cli.error_memory_budget_${cmd} CODE 1 OUT "memory budget of 1024 bytes exceeded"
    SETUP "rm -f ${O}/budget.png ${O}/budget_hits.bin" ABSENT ${O}/budget.png ${O}/budget_hits.bin
    ARGS ${${cmd}_args} --accel bvh-interp --memory-budget 1KiB)
endforeach()
mbrt_cli_test(cli.stats_memory_budget OUT "^kind +bvh-interp" ARGS stats translate --size 0.005 --accel bvh-interp --memory-budget 64MiB)

# Inputs that are not regular files are refused at once (a FIFO would block, /dev/zero never ends).
foreach(ext obj ply json)
  mbrt_cli_test(cli.error_fifo_${ext} CODE 1 TIMEOUT 20 OUT "cannot read '.*fifo.${ext}': it is a FIFO"
    SETUP "rm -f ${O}/fifo.${ext} && mkfifo ${O}/fifo.${ext}"
    ARGS stats ${O}/fifo.${ext} --accel brute)
endforeach()
mbrt_cli_test(cli.error_fifo_rays CODE 1 TIMEOUT 20 OUT "cannot read '.*fifo_rays.bin': it is a FIFO"
  SETUP "rm -f ${O}/fifo_rays.bin && mkfifo ${O}/fifo_rays.bin"
  ARGS trace ${S} --accel brute --rays ${O}/fifo_rays.bin --hits ${O}/fifo_hits.bin)
mbrt_cli_test(cli.error_dev_zero_obj CODE 1 TIMEOUT 20 OUT "cannot read '.*zero.obj': it is a device"
  SETUP "ln -sfn /dev/zero ${O}/zero.obj" ARGS stats ${O}/zero.obj --accel brute)
mbrt_cli_test(cli.error_dev_zero_rays CODE 1 TIMEOUT 20 OUT "cannot read '/dev/zero': it is a device"
  ARGS trace ${S} --accel brute --rays /dev/zero --hits ${O}/zero_hits.bin)

# Outputs that cannot be written are found before the work (NO_OUT "^scene":
# nothing was loaded), and a symlink or an old file survives.
mbrt_cli_test(cli.error_output_proc CODE 1 OUT "cannot write '/proc/x.png': cannot create a file in '/proc'"
  NO_OUT "^scene" ARGS render ${S} -o /proc/x.png)
mbrt_cli_test(cli.error_output_folder CODE 1 OUT "cannot write '.*folder.png': '.*folder.png' is a folder"
  SETUP "mkdir -p ${O}/folder.png" NO_OUT "^scene" ARGS render ${S} -o ${O}/folder.png)
mbrt_cli_test(cli.error_output_device CODE 1 OUT "cannot write '.*full.png': '/dev/full' is a device"
  SETUP "ln -sfn /dev/full ${O}/full.png" NO_OUT "^scene" AFTER "test -L ${O}/full.png"
  ARGS render ${S} -o ${O}/full.png)
mbrt_cli_test(cli.error_output_no_folder CODE 1 OUT "cannot write '.*no_such_folder/x.png': no folder"
  NO_OUT "^scene" ARGS render ${S} -o ${O}/no_such_folder/x.png)
mbrt_cli_test(cli.error_hits_output_proc CODE 1 OUT "cannot write '/proc/hits.bin'" NO_OUT "^scene"
  FIXTURES_REQUIRED cli_rays ARGS trace ${S} --rays ${O}/rays.bin --hits /proc/hits.bin)
mbrt_cli_test(cli.render_through_symlink
  SETUP "rm -rf ${O}/link && mkdir ${O}/link && printf old > ${O}/link/target.png && ln -s target.png ${O}/link/link.png"
  CHECK "image ${O}/link/target.png 8 8" AFTER "test -L ${O}/link/link.png" NO_TEMP ${O}/link
  ARGS render ${S} --width 8 --height 8 --spp 1 -o ${O}/link/link.png)
# A write that fails half way (the file size limit: EFBIG, as a full disk
# gives ENOSPC) leaves the old file and no temporary file.
mbrt_cli_test(cli.error_write_fails_keeps_old CODE 1 OUT "cannot write '.*old.png': File too large"
  SETUP "rm -rf ${O}/wf && mkdir ${O}/wf && printf old > ${O}/wf/old.png"
  AFTER "test \"$(cat ${O}/wf/old.png)\" = old" NO_TEMP ${O}/wf
  SHELL "trap '' XFSZ && ulimit -f 1 && exec \"$MBRT\" render ${S} --width 256 --height 256 --spp 1 --integrator normals -o ${O}/wf/old.png")
mbrt_cli_test(cli.error_ray_write_fails_keeps_old CODE 1 OUT "cannot write '.*old_rays.bin': File too large"
  SETUP "rm -rf ${O}/wr && mkdir ${O}/wr && printf old > ${O}/wr/old_rays.bin"
  AFTER "test \"$(cat ${O}/wr/old_rays.bin)\" = old" NO_TEMP ${O}/wr
  SHELL "trap '' XFSZ && ulimit -f 1 && exec \"$MBRT\" trace ${S} --generate 1000 --rays ${O}/wr/old_rays.bin")

# ---- signals: the partial picture is written, exit 130 (SIGINT) / 143 (SIGTERM)
foreach(sig INT TERM)
  if(sig STREQUAL INT)
    set(code 130)
  else()
    set(code 143)
  endif()
  # Sent once the first progress line is out (a tenth of the tiles done), so
  # that at least one tile is rendered however slow the build (sanitizers).
  mbrt_cli_test(cli.render_sig${sig} PLAIN CODE ${code} TIMEOUT 120
    SETUP "rm -rf ${O}/sig${sig} && mkdir ${O}/sig${sig}"
    SIGNAL ${sig} "^mbrt: +[0-9.]+%  "
    OUT "interrupted: [0-9]+ of [0-9]+ tiles rendered" "stopped by SIG${sig}: wrote the partial picture"
    CHECK "image ${O}/sig${sig}/partial.png 128 128" NO_TEMP ${O}/sig${sig}
    ARGS render demo --size 0.25 --width 128 --height 128 --spp 4096 --tile 4 --threads 1 --progress
         -o ${O}/sig${sig}/partial.png)
endforeach()

# ---- progress: plain lines when stderr is not a terminal --------------------
# Stopped (SIGINT) once the first progress line is out, however fast the machine.
mbrt_cli_test(cli.render_progress_plain PLAIN CODE 130 TIMEOUT 120
  SIGNAL INT "^mbrt: +[0-9.]+%  +[0-9.]+ Mrays/s"
  OUT "^mbrt: +[0-9.]+%  +[0-9.]+ Mrays/s  .* left$"
  ARGS render demo --size 0.25 --width 128 --height 128 --spp 4096 --tile 4 --threads 1 --progress -o ${O}/progress.png)
# A long build (stopped after 3 s by SIGINT, exit 130) shows a spinner on a
# terminal (a pseudo-terminal from script(1)) and nothing in a log.
mbrt_cli_test(cli.stats_spinner_on_terminal CODE 130 TIMEOUT 60 REQUIRE /usr/bin/script
  OUT "building fuzzykd . [0-9]+ s"
  SHELL "exec script -qefc \"timeout --preserve-status -s INT 3 $MBRT stats crowd --size 2 --accel fuzzykd\" /dev/null")
mbrt_cli_test(cli.stats_no_spinner_in_a_log CODE 130 TIMEOUT 60 PLAIN NO_OUT "building"
  SHELL "exec timeout --preserve-status -s INT 3 \"$MBRT\" stats crowd --size 2 --accel fuzzykd")
# Stopped during the build, before any tile: no black picture over an old one,
# and at once (this build alone takes over 10 s; the test's limit is 8 s).
mbrt_cli_test(cli.render_stopped_before_any_tile CODE 130 TIMEOUT 8
  SETUP "rm -f ${O}/untouched.png && printf old > ${O}/untouched.png"
  SIGNAL INT "^scene "
  OUT "stopped by SIGINT before any tile was rendered: nothing written"
  AFTER "test \"$(cat ${O}/untouched.png)\" = old"
  ARGS render crowd --size 2 --accel fuzzykd --width 16 --height 16 --spp 1 -o ${O}/untouched.png)
