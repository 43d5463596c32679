// Tiles rendered in parallel over TBB. Each pixel is finished by one task
// from its own random streams, so the image does not depend on the thread
// count; cancellation skips the tiles not yet started.
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <mutex>

#include "mbrt/render.h"
#include "render/film.h"
#include "render/integrator.h"

namespace mbrt {
namespace {

struct IntegratorName {
  IntegratorKind kind;
  std::string_view name;
};
constexpr IntegratorName kIntegrators[] = {{IntegratorKind::Normals, "normals"},
                                           {IntegratorKind::Ao, "ao"},
                                           {IntegratorKind::Path, "path"},
                                           {IntegratorKind::HeatSteps, "heat-steps"},
                                           {IntegratorKind::HeatIsects, "heat-isects"},
                                           {IntegratorKind::Clusters, "clusters"}};

// The camera ray of one sample; consumes the sampler's first five dimensions.
Ray cameraSample(const RenderCamera& camera, const RenderOptions& o, int x, int y, int s, renderer::Sampler& smp) {
  const uint64_t pixel = uint64_t(y) * uint64_t(o.width) + uint64_t(x);
  const float rotation = toUnitFloat(mix64(renderer::pixelKey(o.seed, pixel) ^ 0x7469'6d65ull));
  const float px = float(x) + smp.next(), py = float(y) + smp.next();
  const float lu = smp.next(), lv = smp.next();
  const float u = renderer::stratified(s, o.spp, smp.next(), rotation);
  return camera.generate(px, py, lu, lv, u);
}

void checkOptions(const RenderOptions& o) {
  auto bad = [](const std::string& what) { throw Error("render: " + what); };
  if (o.width < 1 || o.height < 1 || o.width > 65536 || o.height > 65536)
    bad("image size must be in [1, 65536] x [1, 65536]");
  if (o.spp < 1) bad("samples per pixel must be at least 1");
  // Beyond this the render would run for days: refused rather than started.
  constexpr uint64_t kMaxCameraSamples = uint64_t(1) << 40;
  if (uint64_t(o.width) * uint64_t(o.height) * uint64_t(o.spp) > kMaxCameraSamples)
    bad("width x height x spp = " + std::to_string(uint64_t(o.width) * uint64_t(o.height) * uint64_t(o.spp)) +
        " camera samples is more than the limit of 2^40");
  if (o.tileSize < 1) bad("tile size must be at least 1");
  if (o.aoSamples < 1) bad("ambient occlusion needs at least 1 ray per sample");
  if (o.maxDepth < 0) bad("path depth must be >= 0");
  if (!(o.aoDistance >= 0.0f)) bad("ambient occlusion distance must be >= 0");
  if (!(o.heatMax >= 0.0f)) bad("heat map scale must be >= 0");
}

}  // namespace

std::string_view toString(IntegratorKind kind) {
  for (const auto& i : kIntegrators)
    if (i.kind == kind) return i.name;
  return "unknown";
}

std::optional<IntegratorKind> parseIntegratorKind(std::string_view name) {
  for (const auto& i : kIntegrators)
    if (i.name == name) return i.kind;
  return std::nullopt;
}

std::string integratorKindList() {
  std::string s;
  for (const auto& i : kIntegrators) s += (s.empty() ? "" : ", ") + std::string(i.name);
  return s;
}

Ray primaryRay(const RenderCamera& camera, const RenderOptions& options, int x, int y, int s) {
  renderer::Sampler smp(options.seed, uint64_t(y) * uint64_t(options.width) + uint64_t(x), uint32_t(s));
  return cameraSample(camera, options, x, y, s, smp);
}

RenderResult render(const SceneDescription& scene, const Accel& accel, const RenderOptions& o,
                    const std::atomic<bool>* cancel, const ProgressCallback& progress) {
  checkOptions(o);
  if (!scene.scene) throw Error("render: the scene description has no scene");
  validateSurfaces(scene);
  const auto start = std::chrono::steady_clock::now();
  const RenderCamera camera(scene, o.width, o.height, o.shutterOpen, o.shutterClose);

  const Box3f bounds = sceneBounds(*scene.scene);
  float diagonal = bounds.empty() ? 1.0f : length(bounds.size());
  if (!(diagonal > 0.0f) || !std::isfinite(diagonal)) diagonal = 1.0f;
  renderer::Context ctx{scene, accel, o};
  ctx.aoDistance = o.aoDistance > 0.0f ? o.aoDistance : 0.05f * diagonal;
  ctx.epsilon = 1e-4f * diagonal;

  using TraceFn = renderer::SampleResult (*)(const renderer::Context&, const Ray&, renderer::Sampler&);
  TraceFn trace = renderer::traceAo;
  switch (o.integrator) {
    case IntegratorKind::Normals: trace = renderer::traceNormals; break;
    case IntegratorKind::Ao: trace = renderer::traceAo; break;
    case IntegratorKind::Path: trace = renderer::tracePath; break;
    case IntegratorKind::HeatSteps:
    case IntegratorKind::HeatIsects: trace = renderer::traceHeat; break;
    case IntegratorKind::Clusters: trace = renderer::traceClusters; break;
  }
  if (o.integrator == IntegratorKind::Clusters && accel.options().kind != AccelKind::FuzzyKd &&
      accel.options().kind != AccelKind::Auto)
    throw Error("render: the clusters integrator needs the fuzzykd or auto structure, not " +
                std::string(toString(accel.options().kind)));
  const bool heat = isHeatMap(o.integrator);

  renderer::Film film(o.width, o.height, heat);
  const int tilesX = (o.width + o.tileSize - 1) / o.tileSize, tilesY = (o.height + o.tileSize - 1) / o.tileSize;
  const size_t tilesAll = size_t(tilesX) * size_t(tilesY);
  const size_t tileBegin = std::min(o.tileBegin, tilesAll), tileEnd = std::clamp(o.tileEnd, tileBegin, tilesAll);
  const size_t tilesTotal = tileEnd - tileBegin;
  std::atomic<size_t> tilesDone{0};
  std::atomic<uint64_t> rays{0};
  std::mutex progressMutex;
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };

  tbb::parallel_for(
      tbb::blocked_range<size_t>(tileBegin, tileEnd, 1),
      [&](const tbb::blocked_range<size_t>& range) {
        for (size_t tile = range.begin(); tile != range.end(); ++tile) {
          if (cancel && cancel->load(std::memory_order_relaxed)) return;
          const int x0 = int(tile % size_t(tilesX)) * o.tileSize, y0 = int(tile / size_t(tilesX)) * o.tileSize;
          const int x1 = std::min(o.width, x0 + o.tileSize), y1 = std::min(o.height, y0 + o.tileSize);
          uint64_t tileRays = 0;
          for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
              const uint64_t pixel = uint64_t(y) * uint64_t(o.width) + uint64_t(x);
              Vec3f sum;
              double valueSum = 0.0;
              for (int s = 0; s < o.spp; ++s) {
                renderer::Sampler smp(o.seed, pixel, uint32_t(s));
                const Ray ray = cameraSample(camera, o, x, y, s, smp);
                const renderer::SampleResult r = trace(ctx, ray, smp);
                sum += r.color;
                valueSum += r.value;
                tileRays += r.rays;
              }
              const float inv = 1.0f / float(o.spp);
              if (heat)
                film.setValue(x, y, float(valueSum * double(inv)));
              else
                film.setColor(x, y, sum * inv);
            }
          const uint64_t raysNow = rays.fetch_add(tileRays) + tileRays;
          const size_t doneNow = tilesDone.fetch_add(1) + 1;
          if (progress) {
            std::lock_guard lock(progressMutex);
            progress(RenderProgress{doneNow, tilesTotal, raysNow, seconds()});
          }
        }
      },
      tbb::simple_partitioner());

  RenderResult out;
  film.develop(out, o.heatMax, o.colorBar);
  out.tilesDone = tilesDone.load();
  out.tilesTotal = tilesTotal;
  out.complete = out.tilesDone == tilesTotal;
  out.rays = rays.load();
  out.seconds = seconds();
  return out;
}

}  // namespace mbrt
