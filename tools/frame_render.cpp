#include "frame_render.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "mbrt/io/loaders.h"

namespace mbrt::tools {
namespace {

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

}  // namespace

std::optional<UpdatePolicy> parseUpdatePolicy(const std::string& name) {
  if (name == "refit") return UpdatePolicy::Refit;
  if (name == "rebuild") return UpdatePolicy::Rebuild;
  if (name == "auto") return UpdatePolicy::Auto;
  return std::nullopt;
}

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

FrameRenderer::FrameRenderer(const FrameJob& job, const std::atomic<bool>* cancel)
    : job_(job), cancel_(cancel), source_(job.scene) {
  arena_ = job.threads > 0 ? std::make_unique<tbb::task_arena>(job.threads) : std::make_unique<tbb::task_arena>();
}

FrameRenderer::~FrameRenderer() = default;

void FrameRenderer::checkFrame(int64_t frame) const {
  const Timeline& t = source_.timeline();
  const double open = job_.clock.openAt(frame), close = job_.clock.closeAt(frame);
  const double eps = 1e-6 * std::max(1.0, std::fabs(t.end));
  if (frame >= 0 && open >= t.start - eps && close <= t.end + eps) return;
  const double length = job_.clock.closeAt(0) - job_.clock.openAt(0);
  const double first = std::max(0.0, std::ceil(t.start * job_.clock.fps - 1e-6));
  const double last = std::floor((t.end - length) * job_.clock.fps + 1e-6);
  std::string allowed = last >= first ? "frames " + number(first) + " to " + number(last) + " at " +
                                            number(job_.clock.fps) + " fps with a " +
                                            number(job_.clock.shutterAngleDegrees) + " degree shutter"
                                      : "no whole frame at " + number(job_.clock.fps) + " fps";
  throw UsageError("--frames: frame " + std::to_string(frame) + "'s shutter [" + number(open) + ", " + number(close) +
                   "] s lies outside the timeline of '" + job_.scene.scene + "' (" + t.what + ", " + number(t.start) +
                   " to " + number(t.end) + " s): " + allowed);
}

RenderResult FrameRenderer::render(int64_t frame, FrameRecord& record) {
  record = FrameRecord{};
  record.frame = frame;
  auto start = std::chrono::steady_clock::now();
  SceneDescription next = source_.sceneOver(job_.clock.openAt(frame), job_.clock.closeAt(frame));
  job_.camera.apply(next.camera);
  if (job_.stage) {
    // Placed once from the timeline's first instant (the same on every MPI
    // rank, whatever frame it renders first), so the ground does not move.
    if (!stageBox_) {
      const Timeline& t = source_.timeline();
      stageBox_ = sceneBounds(*source_.sceneOver(t.start, t.start).scene);
    }
    addStage(next, &*stageBox_);
  }
  record.sceneSeconds = since(start);
  update(std::move(next), record);
  RenderResult result;
  arena_->execute([&] { result = mbrt::render(current_, *accel_, job_.options, cancel_); });
  record.renderSeconds = result.seconds;
  record.rays = result.rays;
  record.complete = result.complete;
  return result;
}

void FrameRenderer::build(FrameRecord& record, const std::string& why) {
  const auto start = std::chrono::steady_clock::now();
  accel_.reset();
  arena_->execute([&] { accel_ = buildAccel(*current_.scene, job_.accel, false); });
  if (job_.policy == UpdatePolicy::Auto) lastBuildSah_ = record.sah = accel_->stats().sahCost;
  record.updateSeconds = since(start);
  record.update = why;
}

void FrameRenderer::update(SceneDescription next, FrameRecord& record) {
  if (!accel_ || !sameLayout(*current_.scene, *next.scene)) {
    const bool first = !accel_;
    accel_.reset();  // before the scene it was built over goes
    current_ = std::move(next);
    vertexOwner_.reset();
    build(record, first ? "build" : "rebuild (new layout)");
    return;
  }
  const std::shared_ptr<Scene> scene = current_.scene;
  adoptVertices(*scene, *next.scene);
  current_ = std::move(next);  // this frame's camera, materials and lights
  vertexOwner_ = std::move(current_.scene);
  current_.scene = scene;

  const auto start = std::chrono::steady_clock::now();
  if (job_.policy == UpdatePolicy::Rebuild) {
    arena_->execute([&] { accel_->rebuild(); });
    record.update = "rebuild";
  } else {
    arena_->execute([&] { record.refitted = accel_->refit(); });
    record.update = accel_->lastUpdate();
    if (record.refitted && job_.policy == UpdatePolicy::Auto) {
      record.sah = accel_->stats().sahCost;
      const double growth = lastBuildSah_ > 0.0 ? record.sah / lastBuildSah_ : 1.0;
      if (growth > job_.rebuildFactor) {
        arena_->execute([&] { accel_->rebuild(); });
        lastBuildSah_ = record.sah = accel_->stats().sahCost;
        record.refitted = false;
        char buf[64];
        std::snprintf(buf, sizeof buf, "rebuild (SAH x%.2f)", growth);
        record.update = buf;
      }
    } else if (job_.policy == UpdatePolicy::Auto) {
      lastBuildSah_ = record.sah = accel_->stats().sahCost;
    }
  }
  record.updateSeconds = since(start);
}

}  // namespace mbrt::tools
