// `mbrt render`: a minimal primary-ray renderer with motion blur (every
// sample at its own time). The real renderer comes later; this one shows
// that a scene and a structure work.
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "camera.h"
#include "commands.h"
#include "mbrt/image.h"
#include "scene_loading.h"

namespace mbrt::tools {
namespace {

struct RenderArgs {
  SceneArgs scene;
  AccelArgs accel;
  std::string out = "mbrt.png";
  int width = 640;
  int height = 360;
  int spp = 16;
};

Vec3f baseColor(uint32_t geomID, uint32_t instID) {
  Rng rng(0x5eed, geomID, instID);
  return {0.35f + 0.55f * rng.uniform(), 0.35f + 0.55f * rng.uniform(), 0.35f + 0.55f * rng.uniform()};
}

Vec3f sky(Vec3f dir) {
  const float t = std::clamp(0.5f * (dir.y + 1.0f), 0.0f, 1.0f);
  return lerp(Vec3f(0.9f, 0.9f, 0.88f), Vec3f(0.35f, 0.55f, 0.95f), t);
}

Vec3f shade(const Ray& ray, const Hit& hit) {
  if (!hit.valid()) return sky(ray.dir);
  Vec3f n = Vec3f(0, 1, 0);
  if (dot(hit.Ng, hit.Ng) > 0.0f) n = normalize(hit.Ng);
  if (dot(n, ray.dir) > 0.0f) n = -n;  // face the viewer
  const Vec3f light = normalize(Vec3f(0.4f, 1.0f, 0.5f));
  const float headlight = std::max(0.0f, -dot(n, ray.dir));
  const float key = std::max(0.0f, dot(n, light));
  const Vec3f base = baseColor(hit.instID != kInvalidId ? hit.instID : hit.geomID, 0);
  return base * (0.1f + 0.45f * headlight + 0.55f * key);
}

void run(const RenderArgs& args) {
  // Fail before rendering rather than after.
  const std::filesystem::path parent = std::filesystem::path(args.out).parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw Error("cannot write '" + args.out + "': no directory '" + parent.string() + "'");
  const LoadedScene loaded = loadScene(args.scene);
  auto accel = buildAccel(*loaded.scene, args.accel, defaultAccelKind());
  const AccelStats built = accel->stats();
  std::printf("scene   %s\naccel   %s, built in %.3f s\n", describeScene(loaded).c_str(), built.kind.c_str(),
              built.buildSeconds);

  const int w = args.width, h = args.height, spp = args.spp;
  Image image(w, h);
  const PinholeCamera camera(loaded.camera.keys.front(), float(w) / float(h));
  const size_t raysPerRow = size_t(w) * size_t(spp);
  const int rowsPerChunk = int(std::max<size_t>(1, (size_t(1) << 18) / raysPerRow));
  std::vector<Ray> rays(raysPerRow * size_t(std::min(rowsPerChunk, h)));
  std::vector<Hit> hits(rays.size());

  double traceSeconds = 0.0;
  const auto start = std::chrono::steady_clock::now();
  for (int y0 = 0; y0 < h; y0 += rowsPerChunk) {
    const int y1 = std::min(h, y0 + rowsPerChunk);
    const size_t n = size_t(y1 - y0) * raysPerRow;
    // Per pixel: jittered positions, times stratified over [0,1].
    tbb::parallel_for(y0, y1, [&](int y) {
      for (int x = 0; x < w; ++x) {
        Rng rng(args.scene.seed, uint64_t(y) * uint64_t(w) + uint64_t(x));
        Ray* out = &rays[(size_t(y - y0) * size_t(w) + size_t(x)) * size_t(spp)];
        for (int s = 0; s < spp; ++s) {
          const float px = (float(x) + rng.uniform()) / float(w);
          const float py = (float(y) + rng.uniform()) / float(h);
          const float time = std::min(1.0f, (float(s) + rng.uniform()) / float(spp));
          out[s] = camera.ray(px, py, time);
        }
      }
    });
    const auto t0 = std::chrono::steady_clock::now();
    accel->intersect(std::span<const Ray>(rays.data(), n), std::span<Hit>(hits.data(), n));
    traceSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    tbb::parallel_for(y0, y1, [&](int y) {
      for (int x = 0; x < w; ++x) {
        const size_t first = (size_t(y - y0) * size_t(w) + size_t(x)) * size_t(spp);
        Vec3f sum;
        for (int s = 0; s < spp; ++s) sum += shade(rays[first + size_t(s)], hits[first + size_t(s)]);
        sum *= 1.0f / float(spp);
        image.at(x, y) = {sum.x, sum.y, sum.z};
      }
    });
  }
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writePng(args.out, image);

  const double numRays = double(w) * double(h) * double(spp);
  std::printf("render  %dx%d, %d spp: %.0f rays in %.3f s (tracing %.3f s, %.3f Mrays/s)\n", w, h, spp, numRays,
              total, traceSeconds, traceSeconds > 0 ? numRays / traceSeconds * 1e-6 : 0.0);
  std::printf("wrote   %s\n", args.out.c_str());
}

}  // namespace

void registerRenderCommand(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  auto* cmd = app.add_subcommand("render", "Render a motion-blurred picture of a scene (primary rays only) to PNG");
  addSceneOptions(*cmd, args->scene);
  addAccelOptions(*cmd, args->accel, std::string(toString(defaultAccelKind())));
  cmd->add_option("--out,-o", args->out, "PNG file to write")->capture_default_str();
  cmd->add_option("--width", args->width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
  cmd->add_option("--height", args->height, "Image height in pixels")
      ->check(CLI::Range(1, 16384))
      ->capture_default_str();
  cmd->add_option("--spp", args->spp, "Samples per pixel, each at its own time")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->callback([args] { run(*args); });
}

}  // namespace mbrt::tools
