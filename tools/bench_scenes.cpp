#include "bench_scenes.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "mbrt/io/loaders.h"

namespace mbrt::tools {
namespace {

namespace fs = std::filesystem;

struct RealScene {
  const char* name;
  const char* path;    // below the shared scenes folder
  const char* motion;  // procedural motion of static meshes, or ""
  double shutterSeconds;  // glTF shutter [0, s]; 0: the loader's default
};

// CesiumMan walks for 2 s: one second of it makes real motion blur. Sponza
// and the bunny are static: they get a camera-shake-like and a turning motion.
constexpr RealScene kRealScenes[] = {
    {"wooddoll", "wooddoll_utah", "", 0.0},
    {"cesiumman", "cesium_man/CesiumMan.glb", "", 1.0},
    {"sponza", "sponza_dabrovic/sponza.obj", "translate:0.3,0.1,0;rotate:4:0,1,0", 0.0},
    {"bunny", "stanford_bunny/bun_zipper.ply", "rotate:120:0,1,0", 0.0},
};

std::optional<fs::path> existingDir(const fs::path& p) {
  std::error_code ec;
  if (fs::is_directory(p, ec)) return fs::canonical(p, ec);
  return std::nullopt;
}

}  // namespace

std::vector<std::string> realBenchSceneNames() {
  std::vector<std::string> names;
  for (const RealScene& s : kRealScenes) names.push_back(s.name);
  return names;
}

std::optional<std::string> sharedScenesDir() {
  if (const char* env = std::getenv("MBRT_SHARED_DIR"))
    if (auto d = existingDir(fs::path(env) / "scenes")) return d->string();
  if (auto d = existingDir(fs::path("..") / "shared" / "scenes")) return d->string();
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec)
    for (fs::path dir = exe.parent_path(); !dir.empty() && dir != dir.root_path(); dir = dir.parent_path())
      if (auto d = existingDir(dir.parent_path() / "shared" / "scenes")) return d->string();
  return std::nullopt;
}

ProceduralScene loadRealBenchScene(const std::string& name) {
  for (const RealScene& s : kRealScenes) {
    if (name != s.name) continue;
    const auto dir = sharedScenesDir();
    if (!dir) throw Error("scene '" + name + "' needs ../shared/scenes (or $MBRT_SHARED_DIR), which is absent");
    LoadOptions o;
    o.motion = s.motion;
    if (s.shutterSeconds > 0) {
      o.gltf.shutterOpen = 0.0;
      o.gltf.shutterClose = s.shutterSeconds;
    }
    SceneDescription d = loadSceneSpec((fs::path(*dir) / s.path).string(), o);
    return {name, d.scene, d.camera.keys.front()};
  }
  throw Error("unknown real scene '" + name + "'");
}

}  // namespace mbrt::tools
