// libFuzzer target: a glTF file, .glb when it starts with the binary magic
// "glTF", else .gltf (JSON; buffers as data: URIs), then the scene.
#include <cstring>

#include "fuzz_common.h"
#include "mbrt/io/gltf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const bool glb = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = mbrt::fuzz::writeScratch(glb ? "in.glb" : "in.gltf", data, size);
  try {
    mbrt::GltfOptions o;
    o.steps.maxSteps = 5;  // keep executions fast
    const mbrt::SceneDescription d = mbrt::loadGltf(path, o);
    if (d.scene) mbrt::fuzz::exercise(*d.scene);
  } catch (const mbrt::Error&) {
  }
  return 0;
}
