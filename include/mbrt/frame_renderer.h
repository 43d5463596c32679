// An Animation (mbrt/io/animation.h) rendered frame by frame: each frame's
// scene sampled over its shutter and updated in place, the structure
// following it by an update policy (mbrt/accel_update.h), then rendered
// (mbrt/render.h). What `mbrt render --frames` and its MPI ranks run.
#pragma once

#include <tbb/task_arena.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>

#include "mbrt/accel_update.h"
#include "mbrt/io/animation.h"
#include "mbrt/render.h"

namespace mbrt {

// What happened to one frame.
struct FrameRecord {
  int64_t frame = 0;
  double sceneSeconds = 0.0;   // sampling the scene over the frame's shutter
  AccelUpdate update;          // what the structure did, and its time
  double renderSeconds = 0.0;
  uint64_t rays = 0;
  bool complete = true;        // false when cancelled
};

struct FrameRenderOptions {
  RenderOptions render;  // its shutter part is the camera's, of every frame
  FrameClock clock;
  BuildOptions build;    // the structure (BuildOptions::kind)
  // How new structures are built; empty: Accel::build(scene, build), build
  // as AccelUpdater::buildOptions makes it for the policy.
  AccelUpdater::Builder builder;
  UpdatePolicy policy = UpdatePolicy::Auto;
  double rebuildFactor = 1.5;
  int threads = 0;       // worker threads of builds and renders; 0: all cores
  // Called on every frame's camera before it renders (a user's camera).
  std::function<void(Camera&)> camera;
};

class FrameRenderer {
 public:
  // `animation` must outlive the renderer; `cancel`, when it becomes true,
  // stops a render (the frame's result is then incomplete). Throws Error
  // for a bad clock or rebuild factor.
  FrameRenderer(Animation& animation, FrameRenderOptions options, const std::atomic<bool>* cancel = nullptr);
  ~FrameRenderer();

  // Renders frame f, in any order: the structure follows the scene from the
  // last frame rendered. Throws Error for a frame outside the timeline
  // (Animation::checkFrame) and for failed builds.
  RenderResult render(int64_t frame, FrameRecord& record);
  // The structure over the last frame rendered; null before the first.
  const Accel* accel() const { return accel_.get(); }

 private:
  Animation& animation_;
  FrameRenderOptions options_;
  const std::atomic<bool>* cancel_;
  AccelUpdater updater_;
  std::unique_ptr<tbb::task_arena> arena_;
  std::unique_ptr<Accel> accel_;
};

}  // namespace mbrt
