// libFuzzer target: a JSON scene file. Next to it in the scratch folder lie
// a small OBJ and a small PLY (tri.obj, tri.ply) that objects may name.
// Inputs naming a built-in procedural scene ("scene": ...) are skipped: a
// large "size" is a legitimate request for a large scene, not bad input.
#include <string_view>

#include "fuzz_common.h"
#include "mbrt/io/loaders.h"

namespace {
void writeAssets() {
  static const bool done = [] {
    const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\n";
    mbrt::fuzz::writeScratch("tri.obj", reinterpret_cast<const uint8_t*>(obj.data()), obj.size());
    const std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    mbrt::fuzz::writeScratch("tri.ply", reinterpret_cast<const uint8_t*>(ply.data()), ply.size());
    return true;
  }();
  (void)done;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  writeAssets();
  if (std::string_view(reinterpret_cast<const char*>(data), size).find("scene") != std::string_view::npos) return 0;
  const std::string path = mbrt::fuzz::writeScratch("in.json", data, size);
  try {
    const mbrt::SceneDescription d = mbrt::loadSceneFile(path);
    if (d.scene) mbrt::fuzz::exercise(*d.scene);
  } catch (const mbrt::Error&) {
  }
  return 0;
}
