// Shared by the libFuzzer targets: a private scratch folder for loaders that
// read files by path, and what to do with a loaded scene (validate it and
// build a structure over it, so that what a loader lets through is checked
// by the rest of the library too).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "mbrt/accel.h"
#include "mbrt/scene.h"

namespace mbrt::fuzz {

inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("mbrt-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d;
  }();
  return dir;
}

inline std::string writeScratch(const std::string& name, const uint8_t* data, size_t size) {
  const std::string path = (scratchDir() / name).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size) std::fwrite(data, 1, size, f);
  std::fclose(f);
  return path;
}

// Scenes up to this many primitives are built and traced: enough for every
// loader path (instances, segments, steps), small enough for ~10^6
// executions per target.
constexpr size_t kMaxBuiltPrimitives = 2000;

// Loaded scenes must validate (or throw mbrt::Error) and, when small, build.
inline void exercise(const Scene& scene) {
  try {
    scene.validate();
  } catch (const Error&) {
    return;
  }
  if (scene.numPrimitives() > kMaxBuiltPrimitives) return;
  BuildOptions o;
  o.kind = AccelKind::BvhInterp;
  auto accel = Accel::build(scene, o);
  Ray r;
  r.org = {0.1f, 0.2f, -10.0f};
  r.dir = {0.01f, 0.02f, 1.0f};
  r.time = 0.5f;
  Hit h;
  accel->intersect(r, h);
}

}  // namespace mbrt::fuzz
