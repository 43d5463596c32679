// `mbrt stats`: build a structure and print its statistics (a spinner on a
// terminal while a build takes more than a second).
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "scene_loading.h"

namespace mbrt::tools {
namespace {

struct StatsArgs {
  SceneArgs scene;
  AccelArgs accel;
  bool json = false;
};

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (unsigned char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out += char(c);
        }
    }
  }
  return out + "\"";
}

std::string humanBytes(size_t bytes) {
  char buf[64];
  if (bytes < 1024) std::snprintf(buf, sizeof(buf), "%zu B", bytes);
  else if (bytes < (size_t(1) << 20)) std::snprintf(buf, sizeof(buf), "%.1f KiB", bytes / 1024.0);
  else if (bytes < (size_t(1) << 30)) std::snprintf(buf, sizeof(buf), "%.1f MiB", bytes / 1048576.0);
  else std::snprintf(buf, sizeof(buf), "%.2f GiB", bytes / 1073741824.0);
  return buf;
}

void run(StatsArgs& args) {
  const LoadedScene loaded = loadScene(args.scene);
  auto accel = buildAccel(*loaded.scene, args.accel, /*progress=*/true);
  const AccelStats s = accel->stats();
  const BuildOptions& o = accel->options();
  if (args.json) {
    std::printf("{\n");
    std::printf("  \"scene\": %s,\n", jsonString(loaded.name).c_str());
    std::printf("  \"geometries\": %u,\n", loaded.scene->numGeometries());
    std::printf("  \"kind\": %s,\n", jsonString(s.kind).c_str());
    std::printf("  \"branching\": %d,\n  \"maxLeafSize\": %d,\n", o.branching, o.maxLeafSize);
    std::printf("  \"primitives\": %zu,\n", s.primitives);
    std::printf("  \"references\": %zu,\n", s.references);
    std::printf("  \"innerNodes\": %zu,\n", s.innerNodes);
    std::printf("  \"leafNodes\": %zu,\n", s.leafNodes);
    std::printf("  \"maxDepth\": %zu,\n", s.maxDepth);
    std::printf("  \"bytes\": %zu,\n", s.bytes);
    std::printf("  \"leafBlockBytes\": %zu,\n", s.leafBlockBytes);
    std::printf("  \"peakBuildBytes\": %zu,\n", s.peakBuildBytes);
    std::printf("  \"sahCost\": %.17g,\n", s.sahCost);
    std::printf("  \"buildSeconds\": %.9g,\n", s.buildSeconds);
    std::printf("  \"invalidRays\": %llu,\n", (unsigned long long)s.invalidRays);
    std::printf("  \"objects\": %s\n", jsonString(s.objects).c_str());
    std::printf("}\n");
    return;
  }
  std::printf("scene            %s\n", describeScene(loaded).c_str());
  std::printf("kind             %s (branching %d, leaf size %d", s.kind.c_str(), o.branching, o.maxLeafSize);
  if (o.kind == AccelKind::Frozen) std::printf(", time %g", o.frozenTime);
  std::printf(")\n");
  std::printf("primitives       %zu\n", s.primitives);
  std::printf("references       %zu\n", s.references);
  std::printf("inner nodes      %zu\n", s.innerNodes);
  std::printf("leaf nodes       %zu\n", s.leafNodes);
  std::printf("max depth        %zu\n", s.maxDepth);
  std::printf("memory           %zu bytes (%s)\n", s.bytes, humanBytes(s.bytes).c_str());
  if (s.leafBlockBytes)
    std::printf("  of which leaves %zu bytes (%s): triangles copied into the leaves\n", s.leafBlockBytes,
                humanBytes(s.leafBlockBytes).c_str());
  std::printf("peak build mem   %zu bytes (%s)\n", s.peakBuildBytes, humanBytes(s.peakBuildBytes).c_str());
  std::printf("SAH cost         %.6g\n", s.sahCost);
  std::printf("build time       %.6f s", s.buildSeconds);
  if (s.buildSeconds > 0) std::printf(" (%.3g Mprims/s)", s.primitives / s.buildSeconds * 1e-6);
  std::printf("\ninvalid rays     %llu\n", (unsigned long long)s.invalidRays);
  if (!s.objects.empty()) std::printf("%s", s.objects.c_str());  // auto: per object, what and why
}

}  // namespace

void registerStatsCommand(CLI::App& app) {
  auto args = std::make_shared<StatsArgs>();
  auto* cmd = app.add_subcommand("stats", "Build a structure over a scene and print its statistics");
  addSceneOptions(*cmd, args->scene);
  addAccelOptions(*cmd, args->accel);
  cmd->add_flag("--json", args->json, "Print JSON instead of text");
  cmd->callback([args] { run(*args); });
}

}  // namespace mbrt::tools
