// One frame of a sequence after another: the scene over the frame's shutter,
// updated in place when its layout stays (the same geometries and steps) and
// the structure refitted or rebuilt by the update policy, then rendered.
#pragma once

#include <tbb/task_arena.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "frame_source.h"
#include "mbrt/render.h"
#include "scene_loading.h"

namespace mbrt::tools {

// --update: how the structure follows the scene from frame to frame.
//   refit    Accel::refit (bounds only, the topology of the last build) where
//            the kind can refit (bvh-interp, msbvh), a rebuild elsewhere;
//   rebuild  a new build every frame;
//   auto     refit while the SAH cost stays within `rebuildFactor` times the
//            cost of the last rebuild, rebuild once it grows past it.
enum class UpdatePolicy { Refit, Rebuild, Auto };
std::optional<UpdatePolicy> parseUpdatePolicy(const std::string& name);

// Frame f's shutter: open at f / fps seconds, for angle / 360 of a frame.
struct FrameClock {
  double fps = 24.0;
  double shutterAngleDegrees = 180.0;
  double openAt(int64_t frame) const { return double(frame) / fps; }
  double closeAt(int64_t frame) const { return openAt(frame) + shutterAngleDegrees / 360.0 / fps; }
};

// A user's camera: --eye, --target, --up, --fov override the input's
// camera at every key; --aperture, --focus its lens.
struct CameraOverrides {
  std::optional<Vec3f> eye, target, up;
  std::optional<float> fov, aperture, focus;
  // Throws UsageError when the camera is degenerate (eye at the target, up
  // along the view).
  void apply(Camera& camera) const;
};

struct FrameJob {
  SceneArgs scene;
  AccelArgs accel;
  RenderOptions options;  // checked; the shutter part is the camera's
  CameraOverrides camera;
  FrameClock clock;
  UpdatePolicy policy = UpdatePolicy::Auto;
  double rebuildFactor = 1.5;
  int threads = 0;
  bool stage = true;  // a loaded model stands on a ground plane (addStage), the same in every frame
};

// What happened to one frame, for the per-frame line and the summary.
struct FrameRecord {
  int64_t frame = 0;
  double sceneSeconds = 0.0;   // sampling the scene over the shutter
  double updateSeconds = 0.0;  // the structure: build, refit or rebuild (with the SAH check of `auto`)
  double renderSeconds = 0.0;
  std::string update;          // "build", "refit", "rebuild", "rebuild (SAH x1.62)", ...
  bool refitted = false;
  double sah = 0.0;            // after the update (auto only; 0 otherwise)
  uint64_t rays = 0;
  bool complete = true;        // false when stopped by a signal
};

class FrameRenderer {
 public:
  // Loads what the frames share (FrameSource). `cancel` stops a render.
  FrameRenderer(const FrameJob& job, const std::atomic<bool>* cancel);
  ~FrameRenderer();

  const Timeline& timeline() const { return source_.timeline(); }
  // Throws UsageError naming the frames the timeline allows when frame f's
  // shutter lies outside it.
  void checkFrame(int64_t frame) const;
  // Renders frame f (frames in any order; the structure follows the scene
  // from the last frame rendered).
  RenderResult render(int64_t frame, FrameRecord& record);

 private:
  void update(SceneDescription next, FrameRecord& record);
  void build(FrameRecord& record, const std::string& why);

  FrameJob job_;
  const std::atomic<bool>* cancel_;
  FrameSource source_;
  std::unique_ptr<tbb::task_arena> arena_;
  SceneDescription current_;          // its scene is the one the structure was built over
  std::shared_ptr<Scene> vertexOwner_;  // owns the vertices current_ points at
  std::unique_ptr<Accel> accel_;
  double lastBuildSah_ = 0.0;
  std::optional<Box3f> stageBox_;  // the model's bounds at the timeline's start: where the stage stands
};

}  // namespace mbrt::tools
