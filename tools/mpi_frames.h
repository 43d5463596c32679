// Frames over MPI ranks (built with -DMBRT_MPI=ON, started by mpirun): every
// rank loads the scene itself; rank 0 hands out one frame at a time to the
// rank that asks for the next (dynamic load balancing), renders frames
// itself on a second thread, and writes every file, so that the files are
// byte-for-byte those of a one-process run. A rank whose frame fails gets
// no more work; the job exits 1 naming the frames not written, and a rerun
// with --resume renders them.
#pragma once

#include <tbb/task_arena.h>

#include <atomic>
#include <cstdint>
#include <vector>

#include "frames.h"

namespace mbrt::tools {

// MPI_Init when this build has MPI and the process was started by mpirun
// (OMPI_COMM_WORLD_SIZE or PMI_SIZE set); MPI_Finalize at the end.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
};

// 1 without MPI or outside mpirun.
int mpiWorldSize();
int mpiRank();

void runFramesMpi(const FrameJob& job, const std::vector<int64_t>& frames, const FrameOutput& out);

// One picture over the ranks: every rank has loaded the scene and built
// `accel`; rank 0 hands out rows of tiles (RenderOptions::tileBegin/End) to
// the rank that asks and assembles them (its own thread renders rows too).
// Returns the whole picture on rank 0 (pixels equal to a one-process
// render), an empty result on the others. UsageError for heat maps.
RenderResult renderPictureMpi(const SceneDescription& scene, const Accel& accel, const RenderOptions& options,
                              tbb::task_arena& arena, const std::atomic<bool>* cancel);

}  // namespace mbrt::tools
