#include "scene_loading.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "mbrt/io.h"

namespace mbrt::tools {
namespace {

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

bool endsWithObj(const std::string& s) {
  if (s.size() < 4) return false;
  std::string ext = s.substr(s.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext == ".obj";
}

// Looks at the scene's vertices at every step to frame it.
Box3f sceneBounds(const Scene& scene) {
  Box3f box;
  for (uint32_t g = 0; g < scene.numGeometries(); ++g) {
    const Geometry& geom = scene.geometry(g);
    if (geom.type() == GeometryType::Instance) continue;
    for (uint32_t s = 0; s < geom.numSteps(); ++s)
      for (size_t i = 0; i < geom.vertices(s).count; ++i) box.extend(geom.vertexAtStep(s, uint32_t(i)));
  }
  return box;
}

CameraSpec frameForObj(const Box3f& box) {
  CameraSpec cam;
  if (box.empty()) return cam;
  const Vec3f c = box.center();
  const float radius = std::max(0.5f * length(box.size()), 1e-6f);
  const float half = 0.5f * cam.verticalFovDegrees * 3.14159265f / 180.0f;
  const float dist = 1.1f * radius / std::sin(half);
  cam.target = c;
  cam.eye = c + normalize(Vec3f(0.35f, 0.3f, 1.0f)) * dist;
  cam.up = {0, 1, 0};
  return cam;
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
                 "Built-in scene (" + joinNames(proceduralSceneNames()) + ") or a path to a .obj file")
      ->required();
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
  LoadedScene out;
  std::error_code ec;
  const bool isFile = std::filesystem::is_regular_file(args.scene, ec);
  if (endsWithObj(args.scene) || isFile) {
    if (!endsWithObj(args.scene))
      throw UsageError("scene file '" + args.scene + "' is not a .obj file (only OBJ files are read for now)");
    out.name = args.scene;
    out.scene = loadObjScene(args.scene);
    out.camera.keys = {frameForObj(sceneBounds(*out.scene))};
    return out;
  }
  const auto names = proceduralSceneNames();
  if (std::find(names.begin(), names.end(), args.scene) == names.end())
    throw UsageError("unknown scene '" + args.scene + "': not a built-in scene (" + joinNames(names) +
                     ") nor a .obj file");
  ProceduralScene p = makeProceduralScene(args.scene, args.size, args.seed);
  out.name = p.name;
  out.scene = std::move(p.scene);
  out.camera.keys = {p.camera};
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
