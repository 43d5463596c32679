#include "scene_loading.h"

#include <tbb/info.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "mbrt/io/loaders.h"
#include "progress_bar.h"

namespace mbrt::tools {
namespace {

std::string joinNames(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// What kind of input a scene spec names, by its form (as loadSceneSpec
// dispatches).
enum class InputForm { BuiltIn, Mesh, Sequence, Gltf, SceneFile, Unknown };

InputForm formOf(const std::string& spec) {
  const auto names = proceduralSceneNames();
  std::error_code ec;
  if (std::find(names.begin(), names.end(), spec) != names.end() && !std::filesystem::exists(spec, ec))
    return InputForm::BuiltIn;
  if (isObjSequenceSpec(spec)) return InputForm::Sequence;
  std::string ext = std::filesystem::path(spec).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".obj" || ext == ".ply") return InputForm::Mesh;
  if (ext == ".gltf" || ext == ".glb") return InputForm::Gltf;
  if (ext == ".json") return InputForm::SceneFile;
  return InputForm::Unknown;
}

const char* formName(InputForm f) {
  switch (f) {
    case InputForm::BuiltIn: return "a built-in scene";
    case InputForm::Mesh: return "a static mesh";
    case InputForm::Sequence: return "an OBJ keyframe sequence";
    case InputForm::Gltf: return "a glTF file";
    case InputForm::SceneFile: return "a JSON scene file";
    case InputForm::Unknown: break;
  }
  return "an unknown kind of input";
}

bool given(const SceneArgs& args, const std::string& option) {
  return args.cmd && args.cmd->get_option_no_throw(option) && args.cmd->count(option) > 0;
}

// A decimal number from 0 to 2^64 - 1, nothing else (no sign, no
// exponent): CLI11 alone turns -1 and 2^64 into 2^64 - 1.
CLI::Validator seedValidator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        uint64_t v = 0;
        const char* end = value.data() + value.size();
        const auto [ptr, ec] = std::from_chars(value.data(), end, v);
        if (value.empty() || value[0] == '-' || value[0] == '+' || ec != std::errc() || ptr != end)
          return "must be a whole number from 0 to 18446744073709551615, got '" + value + "'";
        return {};
      },
      "UINT64", "Seed");
}

// "512MiB", "4g", "1000": a whole number of bytes with an optional binary
// unit (k, m, g, t; with or without "b" / "ib"), replaced by the byte count.
// Refuses signs, fractions and counts beyond 2^64 - 1 (CLI11's AsSizeValue
// wraps -5 and 2^64 around).
CLI::Validator byteCount() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        size_t digits = 0;
        while (digits < value.size() && std::isdigit(static_cast<unsigned char>(value[digits]))) ++digits;
        uint64_t n = 0;
        const auto [ptr, ec] = std::from_chars(value.data(), value.data() + digits, n);
        std::string unit = value.substr(digits);
        std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::tolower(c)); });
        static const std::pair<const char*, int> kUnits[] = {
            {"", 0},     {"b", 0},    {"k", 10},   {"kb", 10},  {"kib", 10}, {"m", 20},  {"mb", 20}, {"mib", 20},
            {"g", 30},   {"gb", 30},  {"gib", 30}, {"t", 40},   {"tb", 40},  {"tib", 40}};
        int shift = -1;
        for (const auto& [name, bits] : kUnits)
          if (unit == name) shift = bits;
        const std::string bad = "must be a whole number of bytes with an optional unit (KiB, MiB, GiB, TiB), got '" +
                                value + "'";
        if (digits == 0 || ec != std::errc() || ptr != value.data() + digits || shift < 0) return bad;
        if (shift > 0 && n > (UINT64_MAX >> shift)) return bad + ": more than 2^64 - 1 bytes";
        value = std::to_string(n << shift);
        return {};
      },
      "BYTES", "byte count");
}

}  // namespace

CLI::Validator finiteIn(double lo, double hi, bool openLow) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s%g, %g]", openLow ? "(" : "[", lo, hi);
  const std::string range = buf;
  return CLI::Validator(
      [lo, hi, openLow, range](std::string& value) -> std::string {
        double v = 0;
        std::istringstream in(value);
        if (!(in >> v) || !(in >> std::ws).eof() || !std::isfinite(v) || v > hi || (openLow ? v <= lo : v < lo))
          return "must be a number in " + range + ", got '" + value + "'";
        return {};
      },
      "NUMBER in " + range, "finite range");
}

std::string accelKindList() {
  std::string s;
  for (AccelKind k : availableAccelKinds()) s += (s.empty() ? "" : ", ") + std::string(toString(k));
  return s;
}

AccelKind defaultAccelKind() {
  const auto kinds = availableAccelKinds();
  return std::find(kinds.begin(), kinds.end(), kDefaultAccelKind) != kinds.end() ? kDefaultAccelKind
                                                                                 : AccelKind::Brute;
}

void addSceneOptions(CLI::App& cmd, SceneArgs& args) {
  args.cmd = &cmd;
  const std::string what = "Built-in scene (" + joinNames(proceduralSceneNames()) +
                           "), a .obj/.ply/.gltf/.glb/.json file, or a folder or quoted glob of OBJ keyframes";
  cmd.add_option("SCENE", args.positional, "The scene, as --scene");
  cmd.add_option("--scene", args.scene, what);
  cmd.add_option("--clip", args.clip, "glTF animation clip, by name or index (default: the first)");
  cmd.add_option("--shutter", args.shutter,
                 "Shutter A,B in seconds of the input's timeline: a glTF clip's seconds (default: its start, open "
                 "for 1/(2*fps) s), an OBJ sequence's key k at k/fps s, a built-in scene's or mesh's motion over "
                 "[0,1] s (default: all of it); A,A: a sharp frame");
  cmd.add_option("--steps", args.steps, "Time steps per moving glTF mesh/instance: N or auto")->capture_default_str();
  cmd.add_option("--fps", args.fps, "Frame rate: of --frames, of a glTF clip's default shutter, of an OBJ sequence's keys")
      ->check(finiteIn(0.0, 1e6, true))
      ->capture_default_str();
  cmd.add_option("--motion", args.motion,
                 "Procedural motion of a static .obj/.ply mesh, e.g. 'translate:0.5,0,0;rotate:90[:0,1,0]'");
  cmd.add_flag("--load-info", args.verbose, "Print what the scene loader chose (clip, shutter, steps per mesh)");
  cmd.add_option("--size", args.size, "Size factor of a built-in scene (1 = the default sizes)")
      ->check(finiteIn(0.0, 1e6, true))
      ->capture_default_str();
  cmd.add_option("--seed", args.seed, "Seed of a built-in scene and of random rays")
      ->check(seedValidator())
      ->capture_default_str();
}

void addAccelOptions(CLI::App& cmd, AccelArgs& args) {
  const std::string defaultKind(toString(defaultAccelKind()));
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
      ->check(finiteIn(0.0, 1.0))
      ->capture_default_str();
  cmd.add_option("--memory-budget", args.memoryBudget,
                 "Memory the build may use, e.g. 512MiB or 4GiB (0: unlimited); a build that needs more fails")
      ->transform(byteCount())
      ->capture_default_str();
}

void addThreadsOption(CLI::App& cmd, int& threads) {
  const int cores = tbb::info::default_concurrency();
  cmd.add_option("--threads", threads, "Worker threads, 1 to " + std::to_string(cores) + " (0: all cores)")
      ->check(CLI::Range(0, cores))
      ->capture_default_str();
}

void resolveScene(SceneArgs& args) {
  const bool positional = given(args, "SCENE"), option = given(args, "--scene");
  if (positional && option && args.positional != args.scene)
    throw UsageError("two scenes given: '" + args.positional + "' and --scene '" + args.scene + "'");
  if (positional) args.scene = args.positional;
  if (!positional && !option) {
    if (args.defaultScene.empty())
      throw UsageError("no scene given: name one as SCENE or with --scene (a built-in scene: " +
                       joinNames(proceduralSceneNames()) + "; a file, a folder or a glob)");
    args.scene = args.defaultScene;
  }
  if (args.scene.empty())
    throw UsageError("the scene name is empty (a built-in scene: " + joinNames(proceduralSceneNames()) +
                     "; a file, a folder or a glob)");
  // Options that would be ignored for this input are refused.
  const InputForm form = formOf(args.scene);
  auto refuse = [&](const std::string& option, const std::string& appliesTo) {
    if (given(args, option))
      throw UsageError(option + " applies to " + appliesTo + ", not to '" + args.scene + "' (" + formName(form) +
                       ")");
  };
  if (form != InputForm::Gltf && form != InputForm::SceneFile) {
    const std::string clocked = "glTF and JSON scene files";
    refuse("--clip", clocked);
    if (!args.fpsForAnyInput) refuse("--fps", clocked);
    refuse("--steps", clocked);
    if (!args.shutterForAnyInput) refuse("--shutter", clocked + " (seconds of the clip)");
  }
  if (form != InputForm::Mesh)
    refuse("--motion", "static .obj and .ply meshes (in a JSON scene file, use an object's \"motion\")");
  if (form != InputForm::BuiltIn && form != InputForm::SceneFile)
    refuse("--size", "built-in scenes (also inside a JSON scene file)");
  if (!args.seedForAnyInput && form != InputForm::BuiltIn && form != InputForm::SceneFile)
    refuse("--seed", "built-in scenes here (this command makes no random rays)");
}

bool isGltfFile(const std::string& spec) { return formOf(spec) == InputForm::Gltf; }

LoadOptions loadOptions(SceneArgs& args) {
  resolveScene(args);
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
  if (!args.motion.empty()) {
    try {
      parseProceduralMotion(args.motion);  // bad specs fail before loading
    } catch (const Error& e) {
      throw UsageError(std::string("--motion: ") + e.what());
    }
  }

  const auto names = proceduralSceneNames();
  std::error_code ec;
  const bool known = std::find(names.begin(), names.end(), args.scene) != names.end() ||
                     std::filesystem::exists(args.scene, ec) || isObjSequenceSpec(args.scene) ||
                     args.scene.find('/') != std::string::npos || args.scene.find('.') != std::string::npos;
  if (!known)
    throw UsageError("unknown scene '" + args.scene + "': not a built-in scene (" + joinNames(names) +
                     ") nor a file, folder or glob");
  return opt;
}

LoadedScene loadScene(SceneArgs& args, LoadReport* reportOut) {
  const LoadOptions opt = loadOptions(args);
  LoadReport report;
  const auto start = std::chrono::steady_clock::now();
  LoadedScene out = loadSceneSpec(args.scene, opt, &report);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (args.verbose) {
    std::fprintf(stderr, "mbrt: loaded %s in %.3f s\n", args.scene.c_str(), seconds);
    for (const std::string& line : report.lines) std::fprintf(stderr, "mbrt:   %s\n", line.c_str());
  }
  if (reportOut) *reportOut = std::move(report);
  return out;
}

std::string accelKindName(const AccelArgs& args) {
  return args.accel.empty() ? std::string(toString(defaultAccelKind())) : args.accel;
}

std::unique_ptr<Accel> buildAccel(const Scene& scene, const AccelArgs& args, bool progress) {
  BuildOptions opt;
  opt.branching = args.branching;
  opt.maxLeafSize = args.leafSize;
  opt.frozenTime = args.time;
  opt.memoryBudget = args.memoryBudget;
  const std::string name = accelKindName(args);
  const auto kind = parseAccelKind(name);
  if (!kind) throw UsageError("unknown accel kind '" + name + "' (available: " + accelKindList() + ")");
  opt.kind = *kind;
  if (args.updates) opt = AccelUpdater(*args.updates).buildOptions(opt);
  BuildSpinner spinner(progress, "building " + name);
  if (!args.accel.empty() || opt.kind == AccelKind::Brute) return Accel::build(scene, opt);
  try {
    return Accel::build(scene, opt);
  } catch (const Error& e) {
    // The scene is fine when brute builds it: then the default kind was the problem.
    opt.kind = AccelKind::Brute;
    auto accel = Accel::build(scene, opt);
    spinner.stop();
    std::fprintf(stderr, "mbrt: note: default accel '%s' failed (%s); using brute\n", name.c_str(), e.what());
    return accel;
  }
}

std::string describeScene(const LoadedScene& s) {
  return s.name + ": " + std::to_string(s.scene->numGeometries()) + " geometries, " +
         std::to_string(s.scene->numPrimitives()) + " primitives, " + std::to_string(s.scene->maxSegments() + 1) +
         " time steps at most";
}

}  // namespace mbrt::tools
