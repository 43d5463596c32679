#include "frame_render.h"

#include <cstdio>

namespace mbrt::tools {

void CameraOverrides::apply(Camera& camera) const {
  for (CameraSpec& key : camera.keys) {
    if (eye) key.eye = *eye;
    if (target) key.target = *target;
    if (up) key.up = *up;
    if (fov) key.verticalFovDegrees = *fov;
    const Vec3f view = key.target - key.eye;
    if (!(length(view) > 0.0f))
      throw UsageError("the camera's eye and target are the same point: --eye and --target must differ");
    if (!(length(cross(normalize(view), key.up)) > 1e-6f * length(key.up)))
      throw UsageError("the camera's up direction is zero or along the view (--up must not point at the target)");
  }
  if (aperture) camera.apertureRadius = *aperture;
  if (focus) camera.focusDistance = *focus;
}

SequenceRenderer::SequenceRenderer(const FrameJob& job, const std::atomic<bool>* cancel) : clock_(job.clock) {
  SceneArgs args = job.scene;
  args.shutter.clear();  // every frame has its own
  const LoadOptions load = loadOptions(args);
  if (!canAnimate(args.scene))
    throw UsageError("--frames applies to glTF clips, OBJ keyframe sequences, built-in scenes and meshes, not to "
                     "the JSON scene file '" + args.scene + "'");
  AnimationOptions o;
  o.clip = load.gltf.clip;
  o.steps = load.gltf.steps;
  o.keysPerSecond = args.fps;
  o.motion = load.motion;
  o.size = load.size;
  o.seed = load.seed;
  o.stage = job.stage;
  LoadReport report;
  animation_ = std::make_unique<Animation>(args.scene, o, args.verbose ? &report : nullptr);
  for (const std::string& line : report.lines) std::fprintf(stderr, "mbrt:   %s\n", line.c_str());

  FrameRenderOptions f;
  f.render = job.options;
  f.clock = job.clock;
  f.policy = job.policy;
  f.rebuildFactor = job.rebuildFactor;
  f.threads = job.threads;
  AccelArgs accel = job.accel;
  accel.updates = job.policy;
  f.builder = [accel](const Scene& scene) { return buildAccel(scene, accel, false); };
  f.camera = [camera = job.camera](Camera& c) { camera.apply(c); };
  renderer_ = std::make_unique<FrameRenderer>(*animation_, std::move(f), cancel);
}

void SequenceRenderer::checkFrame(int64_t frame) const {
  try {
    animation_->checkFrame(frame, clock_);
  } catch (const Error& e) {
    throw UsageError(std::string("--frames: ") + e.what());
  }
}

}  // namespace mbrt::tools
