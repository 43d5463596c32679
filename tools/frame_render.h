// The command's frame sequences on the library's (mbrt/frame_renderer.h):
// the job's input as an Animation, rendered by a FrameRenderer that builds
// with the command's structure options (buildAccel) and points the user's
// camera (--eye, --target, ...).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>

#include "mbrt/frame_renderer.h"
#include "scene_loading.h"

namespace mbrt::tools {

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

class SequenceRenderer {
 public:
  // Loads the input once. UsageError for JSON scene files and bad options.
  SequenceRenderer(const FrameJob& job, const std::atomic<bool>* cancel);

  const Timeline& timeline() const { return animation_->timeline(); }
  // Throws UsageError naming the frames the timeline allows when frame f's
  // shutter lies outside it.
  void checkFrame(int64_t frame) const;
  // Renders frame f (frames in any order; the structure follows the scene
  // from the last frame rendered).
  RenderResult render(int64_t frame, FrameRecord& record) { return renderer_->render(frame, record); }

 private:
  FrameClock clock_;
  std::unique_ptr<Animation> animation_;
  std::unique_ptr<FrameRenderer> renderer_;
};

}  // namespace mbrt::tools
