// libFuzzer target: one OBJ file (readObj from memory), then the scene.
#include <sstream>

#include "fuzz_common.h"
#include "mbrt/io/mesh_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    mbrt::ObjMesh mesh = mbrt::readObj(in, "fuzz.obj");
    mbrt::Scene scene;
    scene.addTriangleMesh(std::move(mesh.triangles), std::vector<std::vector<mbrt::Vec3f>>{std::move(mesh.positions)});
    mbrt::fuzz::exercise(scene);
  } catch (const mbrt::Error&) {
  }
  return 0;
}
