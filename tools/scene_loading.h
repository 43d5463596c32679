// Options shared by the subcommands: which scene (--scene, --size, --seed)
// and which structure (--accel, --branching, --leaf-size, --time), and the
// code that turns them into a Scene and an Accel.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <stdexcept>
#include <string>

#include "mbrt/accel.h"
#include "mbrt/scene_description.h"
#include "mbrt/scenes.h"

namespace mbrt::tools {

// A mistake in the command line found after parsing: exit code 2 like
// CLI11's own parse errors (mbrt::Error gives 1).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SceneArgs {
  // A built-in scene's name; a .obj, .ply, .gltf, .glb or .json file; a
  // folder or a quoted glob of OBJ keyframes (docs/input.md).
  std::string scene;
  double size = 1.0;
  uint64_t seed = 1;
  std::string clip;     // glTF animation clip (name or index)
  std::string shutter;  // "A,B" in seconds of the clip (glTF, JSON scenes)
  std::string steps = "auto";  // N or auto
  double fps = 24.0;
  std::string motion;   // procedural motion of a static mesh
  bool verbose = false; // print what the loader chose (per-geometry steps)
};

struct AccelArgs {
  std::string accel;  // empty: the command's default
  int branching = 8;
  int leafSize = 8;
  float time = 0.5f;  // build time of `frozen`
};

// What --scene names: geometry, camera, materials, lights.
using LoadedScene = SceneDescription;

void addSceneOptions(CLI::App& cmd, SceneArgs& args);
// defaultKind is named in the help; AccelArgs::accel stays empty when the
// user gives no --accel.
void addAccelOptions(CLI::App& cmd, AccelArgs& args, const std::string& defaultKind);

// "brute, bvh-interp, ..." (the kinds this build can construct).
std::string accelKindList();
// bvh-interp when this build has it, otherwise brute.
AccelKind defaultAccelKind();

// Throws UsageError for an unknown scene name or bad options, Error for a
// bad file.
LoadedScene loadScene(const SceneArgs& args);

// Builds with the kind given (UsageError when unknown), or with
// `defaultKind` when none was given; a default that turns out not to be
// built in falls back to brute with a note on stderr.
std::unique_ptr<Accel> buildAccel(const Scene& scene, const AccelArgs& args, AccelKind defaultKind);

// Scene summary for messages: "demo: 3 geometries, 1234 primitives, up to 32 segments".
std::string describeScene(const LoadedScene& scene);

}  // namespace mbrt::tools
