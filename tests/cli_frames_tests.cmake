# Tests of `mbrt render --frames`, `mbrt info`, the camera options and MPI
# (included by cli_tests.cmake, which defines mbrt_cli_test and O). Every
# test writes into a folder of its own under ${O}/frames_*.
set(F ${O}/frames)
set(CESIUM ${PROJECT_SOURCE_DIR}/../shared/scenes/cesium_man/CesiumMan.glb)
set(KEYS ${MBRT_CLI_DATA}/keys)
set(SMALL --width 16 --height 12 --spp 1 --integrator normals)
string(REPLACE ";" " " SMALL_S "${SMALL}")  # for SHELL lines

# ---- a sequence: one file per frame, a line per frame, the summary ---------
mbrt_cli_test(cli.frames_builtin
  SETUP "rm -rf ${F}_builtin && mkdir -p ${F}_builtin"
  OUT "^frames +4 of skinned" "^frame +3 .*sk_0003.png$" "^summary 4 frames rendered, 0 skipped"
  CHECK "image ${F}_builtin/sk_0000.png 16 12 nonblack" "image ${F}_builtin/sk_0003.png 16 12 nonblack"
  ABSENT ${F}_builtin/sk_0004.png
  NO_TEMP ${F}_builtin
  ARGS render skinned --size 0.02 --frames 0:3 ${SMALL} -o ${F}_builtin/sk_%04d.png)
mbrt_cli_test(cli.frames_step_exr
  SETUP "rm -rf ${F}_step && mkdir -p ${F}_step"
  OUT "^summary 3 frames rendered"
  CHECK "image ${F}_step/f_2.exr 16 12 nonblack" "image ${F}_step/f_10.exr 16 12 nonblack"
  EXISTS ${F}_step/f_6.exr
  ABSENT ${F}_step/f_3.exr
  ARGS render demo --size 0.1 --frames 2:10:4 ${SMALL} -o ${F}_step/f_%d.exr)

# Frame f's shutter opens at f/fps for 180 degrees of a frame: frame 5 of a
# glTF clip at 24 fps is the picture of --shutter [5/24, 5.5/24] s, byte for
# byte; an OBJ sequence's frame 0 at 4 fps is its keys over [0, 0.125] s
# (key k at k/4 s), a built-in scene's frame 6 its motion over [0.25, 0.2708] s
# (sliced onto new steps: equal within the ties tolerance).
mbrt_cli_test(cli.frames_timing_gltf
  REQUIRE ${CESIUM}
  SETUP "rm -rf ${F}_gltf && mkdir -p ${F}_gltf"
  CHECK "same ${F}_gltf/c_0005.png ${F}_gltf/one.png"
  SHELL "$MBRT render ${CESIUM} --frames 5 ${SMALL_S} -o ${F}_gltf/c_%04d.png && $MBRT render ${CESIUM} --shutter 0.20833333333333334,0.22916666666666669 ${SMALL_S} -o ${F}_gltf/one.png")
mbrt_cli_test(cli.frames_timing_sequence
  SETUP "rm -rf ${F}_seq && mkdir -p ${F}_seq"
  OUT "2 keys at 4 fps"
  CHECK "close ${F}_seq/k_0.png ${F}_seq/one.png"
  SHELL "$MBRT render ${KEYS} --fps 4 --frames 0 --width 24 --height 16 --spp 4 --integrator normals --no-stage -o ${F}_seq/k_%d.png && $MBRT render ${KEYS} --fps 4 --shutter 0,0.125 --width 24 --height 16 --spp 4 --integrator normals --no-stage -o ${F}_seq/one.png && ! $MBRT render ${KEYS} --fps 4 --shutter 0.5,0.75 -o ${F}_seq/late.png")
mbrt_cli_test(cli.frames_timing_builtin
  SETUP "rm -rf ${F}_time && mkdir -p ${F}_time"
  CHECK "close ${F}_time/s_6.png ${F}_time/one.png"
  SHELL "$MBRT render skinned --size 0.02 --frames 6 --update rebuild --width 32 --height 24 --spp 2 --integrator normals -o ${F}_time/s_%d.png && $MBRT render skinned --size 0.02 --shutter 0.25,0.2708333333333333 --width 32 --height 24 --spp 2 --integrator normals -o ${F}_time/one.png")

# --resume renders only the frames whose file is missing.
mbrt_cli_test(cli.frames_resume
  SETUP "rm -rf ${F}_resume && mkdir -p ${F}_resume"
  OUT "^summary 1 frames rendered, 3 skipped" "^frame +2 "
  NO_OUT "^frame +[013] "
  CHECK "image ${F}_resume/r_0002.png 16 12 nonblack"
  SHELL "$MBRT render skinned --size 0.02 --frames 0:3 ${SMALL_S} -o ${F}_resume/r_%04d.png >/dev/null && rm ${F}_resume/r_0002.png && $MBRT render skinned --size 0.02 --frames 0:3 ${SMALL_S} --resume -o ${F}_resume/r_%04d.png")

# Refit and rebuild give the same pictures (within the ties tolerance).
foreach(kind bvh-interp msbvh)
  mbrt_cli_test(cli.frames_refit_${kind}
    SETUP "rm -rf ${F}_${kind} && mkdir -p ${F}_${kind}"
    OUT "^frame +2 .* refit "
    CHECK "close ${F}_${kind}/a_1.png ${F}_${kind}/b_1.png" "close ${F}_${kind}/a_3.png ${F}_${kind}/b_3.png"
    SHELL "$MBRT render skinned --size 0.03 --accel ${kind} --frames 0:3 --update rebuild --width 32 --height 24 --spp 2 --integrator ao -o ${F}_${kind}/b_%d.png >/dev/null && $MBRT render skinned --size 0.03 --accel ${kind} --frames 0:3 --update refit --width 32 --height 24 --spp 2 --integrator ao -o ${F}_${kind}/a_%d.png")
endforeach()
mbrt_cli_test(cli.frames_auto_kind_without_refit
  SETUP "rm -rf ${F}_stbvh && mkdir -p ${F}_stbvh"
  OUT "^frame +1 .*rebuild \\(kind cannot refit\\)"
  EXISTS ${F}_stbvh/s_1.png
  ARGS render skinned --size 0.02 --accel stbvh --frames 0:1 ${SMALL} -o ${F}_stbvh/s_%d.png)

# auto refits its parts and prints what it did on each frame's line.
mbrt_cli_test(cli.frames_auto_refits
  SETUP "rm -rf ${F}_auto && mkdir -p ${F}_auto"
  OUT "^frame +2 .* refit: .*(keys|refitted)"
  EXISTS ${F}_auto/s_2.png
  ARGS render skinned --size 0.02 --accel auto --frames 0:2 ${SMALL} -o ${F}_auto/s_%d.png)

# Ctrl-C: the frame in progress is not written (no temporary file, no
# truncated image); --resume renders what is missing.
mbrt_cli_test(cli.frames_interrupt
  SETUP "rm -rf ${F}_int && mkdir -p ${F}_int"
  CODE 130
  SIGNAL INT "^frame +0 "
  OUT "stopped by SIGINT: frames not written: .*--resume"
  CHECK "image ${F}_int/i_0000.png 64 48 nonblack"
  NO_TEMP ${F}_int
  AFTER "${PROJECT_BINARY_DIR}/mbrt render skinned --size 0.02 --frames 0:5 --width 64 --height 48 --spp 1 --integrator normals --resume -o ${F}_int/i_%04d.png && test -s ${F}_int/i_0005.png"
  ARGS render skinned --size 0.02 --frames 0:5 --width 64 --height 48 --spp 64 --integrator ao -o ${F}_int/i_%04d.png)

# MP4 through ffmpeg, or a message that it is skipped.
mbrt_cli_test(cli.frames_mp4
  SETUP "rm -rf ${F}_mp4 && mkdir -p ${F}_mp4"
  OUT "(^wrote +.*walk.mp4 \\(4 frames|^mp4 +skipped: ffmpeg is not installed)"
  SHELL "$MBRT render skinned --size 0.02 --frames 0:3 ${SMALL_S} -o ${F}_mp4/m_%04d.png --mp4 ${F}_mp4/walk.mp4 && (command -v ffmpeg >/dev/null || test ! -e ${F}_mp4/walk.mp4)")

# ---- bad input: a clear message, nothing written ---------------------------
mbrt_cli_test(cli.frames_error_outside CODE 2
  SETUP "rm -rf ${F}_bad && mkdir -p ${F}_bad"
  OUT "frame 24's shutter .* lies outside the timeline of 'skinned' .*frames 0 to 23 at 24 fps"
  ABSENT ${F}_bad/o_0020.png
  ARGS render skinned --size 0.02 --frames 20:30 ${SMALL} -o ${F}_bad/o_%04d.png)
mbrt_cli_test(cli.frames_error_outside_clip CODE 2 REQUIRE ${CESIUM}
  OUT "lies outside the timeline of .*clip 0"
  ARGS render ${CESIUM} --frames 0:500 ${SMALL} -o ${F}_bad/c_%04d.png)
mbrt_cli_test(cli.frames_error_pattern CODE 2
  OUT "-o '.*/x.png' has no %d for the frame number, but --frames gives 4 frames"
  ABSENT ${F}_bad/x.png
  ARGS render skinned --size 0.02 --frames 0:3 ${SMALL} -o ${F}_bad/x.png)
mbrt_cli_test(cli.frames_error_pattern_conversion CODE 2 OUT "only %d, %4d or %04d"
  ARGS render skinned --size 0.02 --frames 0:3 ${SMALL} -o ${F}_bad/x_%s.png)
mbrt_cli_test(cli.frames_error_folder CODE 1 OUT "mbrt: error: .*no_such_folder"
  ABSENT ${F}_bad/no_such_folder
  ARGS render skinned --size 0.02 --frames 0:3 ${SMALL} -o ${F}_bad/no_such_folder/f_%04d.png)
mbrt_cli_test(cli.frames_error_spec CODE 2 OUT "--frames must be A:B\\[:STEP\\]"
  ARGS render skinned --frames 5:2 -o ${F}_bad/s_%d.png)
mbrt_cli_test(cli.frames_error_resume_alone CODE 2 OUT "--resume applies to a sequence"
  ARGS render skinned --resume -o ${F}_bad/r.png)
mbrt_cli_test(cli.frames_error_json CODE 2 OUT "--frames applies to glTF clips"
  ARGS render ${MBRT_CLI_DATA}/cube_scene.json --frames 0:1 ${SMALL} -o ${F}_bad/j_%d.png)

# ---- the camera a user steers -----------------------------------------------
mbrt_cli_test(cli.render_camera
  SETUP "rm -rf ${F}_cam && mkdir -p ${F}_cam"
  CHECK "image ${F}_cam/cam.png 16 12 nonblack"
  ARGS render ${MBRT_CLI_SCENE} --eye 3,2,4 --target 0,0,0 --up 0,1,0 --fov 35 ${SMALL} -o ${F}_cam/cam.png)
mbrt_cli_test(cli.render_camera_error CODE 2 OUT "eye and target are the same point"
  ARGS render ${MBRT_CLI_SCENE} --eye 1,1,1 --target 1,1,1 ${SMALL} -o ${F}_bad/cam.png)

# ---- mbrt info ---------------------------------------------------------------
mbrt_cli_test(cli.info_sequence OUT "^keys +2, at 24 fps" "^  geometry 0: triangles, 2 primitives, 2 steps" "^bounds "
  "^camera +1 key"
  ARGS info ${KEYS})
mbrt_cli_test(cli.info_gltf REQUIRE ${CESIUM}
  OUT "^  clip 0 '.*': 0 to [0-9.]+ s, [0-9]+ channels" "^  mesh 0 '.*skinned$" "^cameras +0" "^bounds "
  ARGS info ${CESIUM})

# ---- MPI: frames over ranks, byte for byte a one-process run ----------------
find_program(MBRT_MPIRUN mpirun)
if(MBRT_MPI AND MBRT_MPIRUN)
  set(MPIRUN "${MBRT_MPIRUN} --allow-run-as-root --oversubscribe --mca btl self,tcp --mca btl_tcp_if_include lo --mca oob_tcp_if_include lo")
  set(MPI_ARGS "skinned --size 0.03 --frames 0:5 --update rebuild --width 24 --height 16 --spp 2 --integrator ao --threads 1 --accel bvh-interp")
  mbrt_cli_test(cli.mpi_frames_equal
    SETUP "rm -rf ${F}_mpi && mkdir -p ${F}_mpi"
    OUT "over 2 MPI ranks" "^summary 6 frames rendered"
    CHECK "same ${F}_mpi/one_0000.png ${F}_mpi/two_0000.png" "same ${F}_mpi/one_0003.png ${F}_mpi/two_0003.png"
          "same ${F}_mpi/one_0005.png ${F}_mpi/two_0005.png"
    SHELL "$MBRT render ${MPI_ARGS} -o ${F}_mpi/one_%04d.png >/dev/null && ${MPIRUN} -n 2 $MBRT render ${MPI_ARGS} -o ${F}_mpi/two_%04d.png")
  mbrt_cli_test(cli.mpi_picture_equal
    SETUP "rm -rf ${F}_mpipic && mkdir -p ${F}_mpipic"
    CHECK "same ${F}_mpipic/one.png ${F}_mpipic/two.png"
    SHELL "$MBRT render demo --size 0.1 --width 40 --height 36 --spp 2 --integrator ao --threads 1 --tile 8 -o ${F}_mpipic/one.png >/dev/null && ${MPIRUN} -n 2 $MBRT render demo --size 0.1 --width 40 --height 36 --spp 2 --integrator ao --threads 1 --tile 8 -o ${F}_mpipic/two.png")
  # Rank 1 fails every build (a 1 KiB memory budget): the job names the
  # frame it did not write and exits 1; --resume completes the sequence.
  mbrt_cli_test(cli.mpi_frames_failure
    SETUP "rm -rf ${F}_mpifail && mkdir -p ${F}_mpifail"
    CODE 1
    OUT "rank 1, frame [0-9]+: .*budget" "frames not written: [0-9]+ \\(rerun with --resume\\)"
    AFTER "${PROJECT_BINARY_DIR}/mbrt render ${MPI_ARGS} --resume -o ${F}_mpifail/f_%04d.png | grep -q '^summary 1 frames rendered, 5 skipped' && test -s ${F}_mpifail/f_0005.png && test -s ${F}_mpifail/f_0000.png"
    SHELL "${MPIRUN} -n 1 $MBRT render ${MPI_ARGS} -o ${F}_mpifail/f_%04d.png : -n 1 $MBRT render ${MPI_ARGS} --memory-budget 1KiB -o ${F}_mpifail/f_%04d.png")
endif()
