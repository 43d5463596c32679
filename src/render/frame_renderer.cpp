// FrameRenderer (mbrt/frame_renderer.h): sample, update, render, per frame.
#include "mbrt/frame_renderer.h"

#include <chrono>

namespace mbrt {

FrameRenderer::FrameRenderer(Animation& animation, FrameRenderOptions options, const std::atomic<bool>* cancel)
    : animation_(animation),
      options_(std::move(options)),
      cancel_(cancel),
      updater_(options_.policy, options_.rebuildFactor) {
  animation_.frames(options_.clock);  // checks the clock
  if (!options_.builder) {
    const BuildOptions build = updater_.buildOptions(options_.build);
    options_.builder = [build](const Scene& scene) { return Accel::build(scene, build); };
  }
  arena_ = options_.threads > 0 ? std::make_unique<tbb::task_arena>(options_.threads)
                                : std::make_unique<tbb::task_arena>();
}

FrameRenderer::~FrameRenderer() = default;

RenderResult FrameRenderer::render(int64_t frame, FrameRecord& record) {
  record = FrameRecord{};
  record.frame = frame;
  const auto start = std::chrono::steady_clock::now();
  animation_.checkFrame(frame, options_.clock);
  SceneDescription* scene = nullptr;
  arena_->execute([&] { scene = &animation_.frame(frame, options_.clock); });
  if (options_.camera) options_.camera(scene->camera);
  record.sceneSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  arena_->execute([&] { record.update = updater_.update(accel_, *scene->scene, options_.builder); });
  RenderResult result;
  arena_->execute([&] { result = mbrt::render(*scene, *accel_, options_.render, cancel_); });
  record.renderSeconds = result.seconds;
  record.rays = result.rays;
  record.complete = result.complete;
  return result;
}

}  // namespace mbrt
