#include "scene_loading.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <chrono>
#include <sstream>

#include "mbrt/loaders.h"

namespace mbrt::tools {
namespace {

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::string accelKindList() {
  std::string s;
  for (AccelKind k : availableAccelKinds()) s += (s.empty() ? "" : ", ") + std::string(toString(k));
  return s;
}

AccelKind defaultAccelKind() {
  const auto kinds = availableAccelKinds();
  return std::find(kinds.begin(), kinds.end(), AccelKind::BvhInterp) != kinds.end() ? AccelKind::BvhInterp
                                                                                     : AccelKind::Brute;
}

void addSceneOptions(CLI::App& cmd, SceneArgs& args) {
  cmd.add_option("--scene", args.scene,
                 "Built-in scene (" + joinNames(proceduralSceneNames()) +
                     "), a .obj/.ply/.gltf/.glb/.json file, or a folder or quoted glob of OBJ keyframes")
      ->required();
  cmd.add_option("--clip", args.clip, "glTF animation clip, by name or index (default: the first)");
  cmd.add_option("--shutter", args.shutter,
                 "Shutter A,B in seconds of the glTF clip (default: its start, open for 1/(2*fps) s); A,A: a sharp frame");
  cmd.add_option("--steps", args.steps, "Time steps per moving glTF mesh/instance: N or auto")->capture_default_str();
  cmd.add_option("--fps", args.fps, "Frame rate for the default shutter (180 degrees)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd.add_option("--motion", args.motion,
                 "Procedural motion of a static .obj/.ply mesh, e.g. 'translate:0.5,0,0;rotate:90[:0,1,0]'");
  cmd.add_flag("--load-info", args.verbose, "Print what the scene loader chose (clip, shutter, steps per mesh)");
  cmd.add_option("--size", args.size, "Size factor of a built-in scene (1 = the default sizes)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd.add_option("--seed", args.seed, "Seed of a built-in scene and of random rays")->capture_default_str();
}

void addAccelOptions(CLI::App& cmd, AccelArgs& args, const std::string& defaultKind) {
  CLI::Validator known(
      [](std::string& value) -> std::string {
        const auto kind = parseAccelKind(value);
        const auto kinds = availableAccelKinds();
        if (!kind || std::find(kinds.begin(), kinds.end(), *kind) == kinds.end())
          return "unknown accel kind '" + value + "' (available: " + accelKindList() + ")";
        return {};
      },
      "KIND", "AccelKind");
  cmd.add_option("--accel", args.accel, "Acceleration structure: " + accelKindList() + " (default " + defaultKind + ")")
      ->check(known);
  cmd.add_option("--branching", args.branching, "BVH node width")
      ->check(CLI::IsMember({2, 4, 8}))
      ->capture_default_str();
  cmd.add_option("--leaf-size", args.leafSize, "Most primitives per leaf")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd.add_option("--time", args.time, "Build time of the `frozen` kind, in [0,1]")
      ->check(CLI::Range(0.0f, 1.0f))
      ->capture_default_str();
}

LoadedScene loadScene(const SceneArgs& args) {
  LoadOptions opt;
  opt.size = args.size;
  opt.seed = args.seed;
  opt.motion = args.motion;
  opt.gltf.clip = args.clip;
  opt.gltf.fps = args.fps;
  if (!args.shutter.empty()) {
    std::stringstream ss(args.shutter);
    double a = 0, b = 0;
    char comma = 0;
    if (!(ss >> a >> comma >> b) || comma != ',' || !ss.eof() || !std::isfinite(a) || !std::isfinite(b) || b < a)
      throw UsageError("--shutter must be A,B with A <= B (seconds), got '" + args.shutter + "'");
    opt.gltf.shutterOpen = a;
    opt.gltf.shutterClose = b;
  }
  if (args.steps != "auto") {
    char* end = nullptr;
    const long n = std::strtol(args.steps.c_str(), &end, 10);
    if (args.steps.empty() || *end != '\0' || n < 1 || n > 1024)
      throw UsageError("--steps must be a number from 1 to 1024 or 'auto', got '" + args.steps + "'");
    opt.gltf.steps.steps = uint32_t(n);
  }
  if (!args.motion.empty()) parseProceduralMotion(args.motion);  // bad specs fail before loading

  const auto names = proceduralSceneNames();
  std::error_code ec;
  const bool known = std::find(names.begin(), names.end(), args.scene) != names.end() ||
                     std::filesystem::exists(args.scene, ec) || isObjSequenceSpec(args.scene) ||
                     args.scene.find('/') != std::string::npos || args.scene.find('.') != std::string::npos;
  if (!known)
    throw UsageError("unknown scene '" + args.scene + "': not a built-in scene (" + joinNames(names) +
                     ") nor a file, folder or glob");
  LoadReport report;
  const auto start = std::chrono::steady_clock::now();
  LoadedScene out = loadSceneSpec(args.scene, opt, &report);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.verbose) {
    std::fprintf(stderr, "mbrt: loaded %s in %.3f s\n", args.scene.c_str(), seconds);
    for (const std::string& line : report.lines) std::fprintf(stderr, "mbrt:   %s\n", line.c_str());
  }
  return out;
}

std::unique_ptr<Accel> buildAccel(const Scene& scene, const AccelArgs& args, AccelKind defaultKind) {
  BuildOptions opt;
  opt.branching = args.branching;
  opt.maxLeafSize = args.leafSize;
  opt.frozenTime = args.time;
  if (!args.accel.empty()) {
    const auto kind = parseAccelKind(args.accel);
    if (!kind) throw UsageError("unknown accel kind '" + args.accel + "' (available: " + accelKindList() + ")");
    opt.kind = *kind;
    return Accel::build(scene, opt);
  }
  opt.kind = defaultKind;
  if (defaultKind == AccelKind::Brute) return Accel::build(scene, opt);
  try {
    return Accel::build(scene, opt);
  } catch (const Error& e) {
    // The scene is fine when brute builds it: then the default kind was the problem.
    opt.kind = AccelKind::Brute;
    auto accel = Accel::build(scene, opt);
    std::fprintf(stderr, "mbrt: note: default accel '%s' failed (%s); using brute\n",
                 std::string(toString(defaultKind)).c_str(), e.what());
    return accel;
  }
}

std::string describeScene(const LoadedScene& s) {
  return s.name + ": " + std::to_string(s.scene->numGeometries()) + " geometries, " +
         std::to_string(s.scene->numPrimitives()) + " primitives, " + std::to_string(s.scene->maxSegments() + 1) +
         " time steps at most";
}

}  // namespace mbrt::tools
