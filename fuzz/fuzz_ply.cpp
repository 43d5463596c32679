// libFuzzer target: a PLY file (ascii or binary), then the scene.
#include "fuzz_common.h"
#include "mbrt/io/mesh_files.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = mbrt::fuzz::writeScratch("in.ply", data, size);
  try {
    auto scene = mbrt::loadPlyScene(path);
    mbrt::fuzz::exercise(*scene);
  } catch (const mbrt::Error&) {
  }
  return 0;
}
