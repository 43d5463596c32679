// `mbrt trace`: closest hits of a ray file, written as a hit file
// (mbrt/io/ray_file.h); `--generate N` writes a ray file of random camera rays.
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "rng.h"
#include "commands.h"
#include "mbrt/camera.h"
#include "mbrt/io/file_access.h"
#include "mbrt/io/ray_file.h"
#include "output_paths.h"
#include "scene_loading.h"

namespace mbrt::tools {
namespace {

struct TraceArgs {
  SceneArgs scene;
  AccelArgs accel;
  std::string rays;
  std::string hits;
  size_t generate = 0;
};

// Primary rays through random image points of a 16:9 view, random times.
std::vector<Ray> generateRays(const LoadedScene& scene, size_t count, uint64_t seed) {
  const PinholeCamera camera(scene.camera.keys.front(), 16.0f / 9.0f);
  std::vector<Ray> rays(count);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Rng rng(seed, i, 0x7261797347ull);
      const float x = rng.uniform(), y = rng.uniform(), t = rng.uniform();
      rays[i] = camera.ray(x, y, t);
    }
  });
  return rays;
}

// Every cheap check before loading and tracing: the options, and that the
// outputs can be written and overwrite no input.
void checkArgs(TraceArgs& args) {
  if (args.hits.empty() && args.generate == 0)
    throw UsageError("trace needs --hits FILE to trace --rays FILE (or --generate N to write a ray file)");
  args.scene.seedForAnyInput = args.generate > 0;  // the seed of the random rays
  resolveScene(args.scene);
  if (!args.hits.empty()) refuseSamePath("--hits", args.hits, "--rays", args.rays);
  if (!args.hits.empty()) refuseSamePath("--hits", args.hits, "the scene", args.scene.scene);
  if (args.generate > 0) refuseSamePath("--rays", args.rays, "the scene", args.scene.scene);
  if (args.generate > 0) io::checkOutputPath(args.rays);
  if (!args.hits.empty()) io::checkOutputPath(args.hits);
  if (args.hits.empty())  // --generate alone builds nothing
    for (const char* option : {"--accel", "--branching", "--leaf-size", "--time", "--memory-budget"})
      if (args.scene.cmd->count(option) > 0)
        throw UsageError(std::string(option) + " applies when rays are traced: give --hits FILE with --generate");
}

void run(TraceArgs& args) {
  checkArgs(args);
  std::vector<Ray> rays;
  if (args.generate == 0) rays = readRays(args.rays);  // a bad ray file fails before the scene loads
  const LoadedScene loaded = loadScene(args.scene);
  if (args.generate > 0) {
    rays = generateRays(loaded, args.generate, args.scene.seed);
    writeRays(args.rays, rays);
    std::printf("wrote %zu random camera rays to %s\n", rays.size(), args.rays.c_str());
    if (args.hits.empty()) return;
  }

  auto accel = buildAccel(*loaded.scene, args.accel, /*progress=*/true);
  const AccelStats built = accel->stats();
  std::printf("scene   %s\naccel   %s, built in %.3f s\n", describeScene(loaded).c_str(), built.kind.c_str(),
              built.buildSeconds);

  std::vector<Hit> hits(rays.size());
  const auto start = std::chrono::steady_clock::now();
  accel->intersect(rays, hits);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  writeHits(args.hits, std::span<const Hit>(hits));

  size_t hitCount = 0;
  for (const Hit& h : hits) hitCount += h.valid() ? 1 : 0;
  const uint64_t invalid = accel->stats().invalidRays - built.invalidRays;
  std::printf("rays    %zu: %zu hits, %zu misses, %llu invalid (counted as misses)\n", rays.size(), hitCount,
              rays.size() - hitCount - size_t(invalid), (unsigned long long)invalid);
  std::printf("time    %.4f s (%.3f Mrays/s)\n", seconds, seconds > 0 ? rays.size() / seconds * 1e-6 : 0.0);
  std::printf("wrote   %s\n", args.hits.c_str());
}

}  // namespace

void registerTraceCommand(CLI::App& app) {
  auto args = std::make_shared<TraceArgs>();
  auto* cmd = app.add_subcommand(
      "trace",
      "Trace a ray file and write the closest hits.\n"
      "Rays: little-endian float32 x9 per ray (ox oy oz dx dy dz tnear tfar time).\n"
      "Hits: float32 t (+inf on a miss), uint32 geometry id, uint32 primitive id (0xFFFFFFFF on a miss).");
  addSceneOptions(*cmd, args->scene);
  addAccelOptions(*cmd, args->accel);
  cmd->add_option("--rays", args->rays, "Ray file to read (or to write with --generate)")->required();
  cmd->add_option("--hits", args->hits, "Hit file to write");
  cmd->add_option("--generate", args->generate,
                  "Write N random camera rays with random times to --rays (and trace them when --hits is given)")
      ->check(CLI::Range(size_t(1), size_t(io::kMaxInputFileBytes / kRayRecordBytes)));  // a file mbrt reads back
  cmd->callback([args] { run(*args); });
}

}  // namespace mbrt::tools
