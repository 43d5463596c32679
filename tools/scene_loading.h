// Options shared by the subcommands: which scene (--scene, --size, --seed)
// and which structure (--accel, --branching, --leaf-size, --time), and the
// code that turns them into a Scene and an Accel.
#pragma once

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "mbrt/accel.h"
#include "mbrt/accel_update.h"
#include "mbrt/io/gltf.h"
#include "mbrt/io/loaders.h"
#include "mbrt/io/scene_description.h"
#include "mbrt/scenes.h"

namespace mbrt::tools {

// A mistake in the command line found after parsing: exit code 2 like
// CLI11's own parse errors (mbrt::Error gives 1).
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The structure every subcommand builds when no --accel is given: `auto`
// picks one per object (docs/auto.md). buildAccel falls back to brute, with
// a note, when this build lacks it.
constexpr AccelKind kDefaultAccelKind = AccelKind::Auto;

// The end of a command that finished its output but must not report
// success: interrupted by SIGINT (130) or SIGTERM (143) after writing what
// it had. main() returns `code`; the message is already printed.
class ExitStatus : public std::exception {
 public:
  explicit ExitStatus(int code) : code_(code) {}
  int code() const { return code_; }
  const char* what() const noexcept override { return "exit status"; }

 private:
  int code_;
};

// A number in [lo, hi] (or (lo, hi] with openLow), never NaN or infinite:
// CLI11's Range and PositiveNumber let NaN through.
CLI::Validator finiteIn(double lo, double hi, bool openLow = false);

struct SceneArgs {
  // A built-in scene's name; a .obj, .ply, .gltf, .glb or .json file; a
  // folder or a quoted glob of OBJ keyframes (docs/input.md). Given as the
  // positional SCENE or as --scene.
  std::string scene;
  std::string positional;
  std::string defaultScene;  // when neither is given; empty: a scene is required
  double size = 1.0;
  uint64_t seed = 1;
  std::string clip;     // glTF animation clip (name or index)
  std::string shutter;  // "A,B" in seconds of the input's timeline (mbrt/io/animation.h)
  std::string steps = "auto";  // N or auto
  double fps = 24.0;
  std::string motion;   // procedural motion of a static mesh
  bool verbose = false; // print what the loader chose (per-geometry steps)
  // The command reads --shutter itself for inputs without a clock (render:
  // the part of the normalized shutter), so it is not refused for them.
  bool shutterForAnyInput = false;
  // The command uses --seed whatever the input (random rays or samples).
  bool seedForAnyInput = false;
  // The command uses --fps whatever the input (the clock of frames; OBJ
  // sequences' keys at k / fps s).
  bool fpsForAnyInput = false;
  const CLI::App* cmd = nullptr;  // to tell which options were given
};

struct AccelArgs {
  std::string accel;  // empty: kDefaultAccelKind
  int branching = 8;
  int leafSize = 8;
  float time = 0.5f;  // build time of `frozen`
  size_t memoryBudget = 0;  // bytes, 0: unlimited
  // Not an option: the policy that will update the accel (--frames), whose
  // AccelUpdater::buildOptions the build takes.
  std::optional<UpdatePolicy> updates;
};

// What --scene names: geometry, camera, materials, lights.
using LoadedScene = SceneDescription;

// The positional SCENE and --scene, --size, --seed, --clip, ...
void addSceneOptions(CLI::App& cmd, SceneArgs& args);
// --accel (empty when not given), --branching, --leaf-size, --time,
// --memory-budget.
void addAccelOptions(CLI::App& cmd, AccelArgs& args);
// --threads N: 1 to the cores TBB sees, 0 for all.
void addThreadsOption(CLI::App& cmd, int& threads);

// Settles which scene is meant (SCENE or --scene, else the default) and
// refuses options that do not apply to that input (--motion on glTF, --clip
// on OBJ, ...) with a UsageError. Cheap: run before any work.
void resolveScene(SceneArgs& args);

// "brute, bvh-interp, ..." (the kinds this build can construct).
std::string accelKindList();
// kDefaultAccelKind when this build has it, otherwise brute.
AccelKind defaultAccelKind();

// The loader's options of the scene options: runs resolveScene first;
// UsageError for an unknown scene name and bad --shutter, --steps, --motion.
LoadOptions loadOptions(SceneArgs& args);
// Whether `spec` names a glTF file (not a folder or glob).
bool isGltfFile(const std::string& spec);

// Throws UsageError for an unknown scene name or bad options, Error for a
// bad file. Runs resolveScene first. `report`: what the loader chose.
LoadedScene loadScene(SceneArgs& args, LoadReport* report = nullptr);

// Builds with the kind given (UsageError when unknown), or with
// defaultAccelKind() when none was given; a default that fails falls back
// to brute with a note on stderr. `progress`: a note and a spinner on stderr
// while a build takes more than a second, when stderr is a terminal.
std::unique_ptr<Accel> buildAccel(const Scene& scene, const AccelArgs& args, bool progress = false);

// The name of the kind buildAccel uses for `args` ("stbvh", ...).
std::string accelKindName(const AccelArgs& args);

// Scene summary for messages: "demo: 3 geometries, 1234 primitives, up to 32 segments".
std::string describeScene(const LoadedScene& scene);

}  // namespace mbrt::tools
