// `mbrt bench`: every structure on the same ray sets, next to Embree in its
// default, robust and static modes, and the frozen-time bound; `--scaling`
// measures cost against scene size. The engine is src/bench/.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "mbrt/bench.h"
#include "bench_scenes.h"
#include "commands.h"
#include "mbrt/io/loaders.h"
#include "mbrt/io/ray_file.h"
#include "scene_loading.h"

namespace mbrt::tools {
namespace {

// Items of a comma-separated list; an empty item (", ,", or the empty
// string itself) is a usage error naming the option.
std::vector<std::string> splitList(const std::string& s, const char* option) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (item.empty()) throw UsageError(std::string(option) + ": empty item in '" + s + "'");
    out.push_back(item);
  }
  if (out.empty() || s.back() == ',') throw UsageError(std::string(option) + ": empty list '" + s + "'");
  return out;
}

std::string gitCommit() {
  std::string out;
  if (std::FILE* p = popen("git rev-parse --short HEAD 2>/dev/null", "r")) {
    char buf[64];
    while (std::fgets(buf, sizeof buf, p)) out += buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return out.empty() ? "unknown" : out;
}

// A finite number > 0 (CLI11's PositiveNumber lets "nan" through).
const CLI::Validator kFinitePositive(
    [](std::string& s) -> std::string {
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(s.c_str(), &end);
      if (s.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v) || !(v > 0))
        return "must be a finite number > 0, got '" + s + "'";
      return "";
    },
    "POSITIVE");

// Digits only, within uint64_t (CLI11 wraps "-1" to UINT64_MAX).
const CLI::Validator kUnsigned64(
    [](std::string& s) -> std::string {
      if (s.empty() || s.find_first_not_of("0123456789") != std::string::npos)
        return "must be an integer >= 0, got '" + s + "'";
      errno = 0;
      std::strtoull(s.c_str(), nullptr, 10);
      if (errno == ERANGE) return "must be below 2^64, got '" + s + "'";
      return "";
    },
    "UINT64");

struct BenchArgs {
  std::string scenes, accels, json, html, svg;
  bool quick = false, scaling = false;
  double size = 0.0;
  int rays = 0;
  int frozenTimes = 0;
  int repeats = 0;
  double budget = 0.0;
  std::string rayFile;
  std::string scalingSizes;
  uint64_t seed = 1;
};

// Fails before the work when an output cannot be created (no lost run).
void checkWritable(const std::string& path, const char* option) {
  if (path.empty()) return;
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw UsageError(std::string(option) + ": '" + path + "' is a directory");
  const bool existed = fs::exists(path, ec);
  { std::ofstream f(path, std::ios::app); if (!f) throw Error("cannot write " + path + " (" + option + ")"); }
  if (!existed) fs::remove(path, ec);
}

void writeFile(const std::string& path, const std::string& text) {
  if (path.empty()) return;
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    f.flush();
    if (!f) throw Error("could not write " + path);
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw Error("could not write " + path + ": " + ec.message());
}

std::vector<ProceduralScene> loadScenes(const bench::Options& o) {
  // The default suite: the procedural scenes, plus the real ones when
  // ../shared is present. Other names are files, sequences or JSON scene
  // files, loaded like --scene elsewhere.
  const auto builtIn = proceduralSceneNames();
  const auto real = realBenchSceneNames();
  std::vector<std::string> names = o.scenes;
  if (names.empty()) {
    names = builtIn;
    if (sharedScenesDir())
      names.insert(names.end(), real.begin(), real.end());
    else
      std::fprintf(stderr, "mbrt bench: ../shared/scenes is absent: real scenes skipped\n");
  }
  std::vector<ProceduralScene> scenes;
  for (const std::string& n : names) {
    if (std::find(builtIn.begin(), builtIn.end(), n) != builtIn.end()) {
      scenes.push_back(makeProceduralScene(n, o.size, o.seed));
    } else if (std::find(real.begin(), real.end(), n) != real.end()) {
      scenes.push_back(loadRealBenchScene(n));
    } else {
      LoadOptions lo;
      lo.size = o.size;
      lo.seed = o.seed;
      SceneDescription d = loadSceneSpec(n, lo);
      scenes.push_back({d.name, d.scene, d.camera.keys.front()});
    }
  }
  return scenes;
}

// The options as the engine takes them; every usage error is found here,
// before any work.
bench::Options benchOptions(const BenchArgs& a, const CLI::App& cmd) {
  bench::Options o;
  if (a.quick) o.makeQuick();
  if (cmd.count("--size")) o.size = a.size;
  if (cmd.count("--rays")) o.width = o.height = a.rays;
  if (cmd.count("--frozen-times")) o.frozenTimes = a.frozenTimes;
  if (cmd.count("--repeats")) o.repeats = a.repeats;
  if (cmd.count("--budget")) {
    o.passBudgetSeconds = a.budget;
    o.countBudgetSeconds = a.budget / 4.0;
  }
  o.seed = a.seed;
  if (cmd.count("--scene")) o.scenes = splitList(a.scenes, "--scene");
  if (cmd.count("--accel")) o.accels = splitList(a.accels, "--accel");
  const std::vector<std::string> known = bench::candidateNames();
  for (const std::string& n : o.accels)
    if (std::find(known.begin(), known.end(), n) == known.end()) {
      std::string list;
      for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
      throw UsageError("unknown accel '" + n + "' (available: " + list + ")");
    }
  if (!a.rayFile.empty() && o.scenes.size() != 1)
    throw UsageError("--rays-file needs exactly one --scene (the scene the rays were made for)");
  if (a.scaling && !a.rayFile.empty()) throw UsageError("--rays-file does not apply to --scaling");
  if (!a.scaling && cmd.count("--scaling-sizes")) throw UsageError("--scaling-sizes needs --scaling");
  if (a.scaling && !a.html.empty()) throw UsageError("--html does not apply to --scaling (use --svg)");
  checkWritable(a.json, "--json");
  checkWritable(a.html, "--html");
  checkWritable(a.svg, "--svg");
  o.commit = gitCommit();
  o.progress = stderr;
  o.progressTerminal = isatty(STDERR_FILENO) != 0;
  return o;
}

void runScaling(const BenchArgs& a, const CLI::App& cmd, const bench::Options& o) {
  bench::ScalingOptions so;
  so.bench = o;
  if (cmd.count("--scene")) so.scenes = o.scenes;
  so.accels = o.accels;
  if (cmd.count("--scaling-sizes")) {
    so.sizes.clear();
    for (std::string s : splitList(a.scalingSizes, "--scaling-sizes")) {
      const std::string bad = kFinitePositive(s);
      if (!bad.empty()) throw UsageError("--scaling-sizes: " + bad);
      so.sizes.push_back(std::strtod(s.c_str(), nullptr));
    }
  }
  for (const std::string& n : so.scenes) {
    const auto builtIn = proceduralSceneNames();
    if (std::find(builtIn.begin(), builtIn.end(), n) == builtIn.end())
      throw UsageError("--scaling takes built-in scenes only (they have a size knob), got '" + n + "'");
  }
  const bench::ScalingReport report = bench::runScaling(so);
  std::cout << bench::toMarkdown(report);
  writeFile(a.json, bench::toJson(report));
  writeFile(a.svg, bench::toSvg(report));
}

}  // namespace

void registerBenchCommand(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  auto* cmd = app.add_subcommand("bench", "Benchmark every structure, Embree and the frozen bound on the same rays");
  cmd->add_option("--scene", args->scenes, "Comma-separated scenes: built-in names or files/globs as --scene elsewhere (default: the procedural suite)");
  cmd->add_option("--accel", args->accels,
                  "Comma-separated rows: accel kinds, embree (Embree's defaults), embree-robust, embree-static, "
                  "embree-static-robust (default: all available but brute)");
  cmd->add_flag("--quick", args->quick, "Small scenes and ray sets: the whole suite in a few minutes");
  cmd->add_option("--size", args->size, "Scene size knob (1 = the default sizes)")
      ->check(kFinitePositive)
      ->check(CLI::Range(1e-6, 100.0));
  cmd->add_option("--rays", args->rays, "Primary rays per side (default 512, --quick 128)")->check(CLI::Range(1, 8192));
  cmd->add_option("--frozen-times", args->frozenTimes, "K, the frozen times (default 16, --quick 8)")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("--repeats", args->repeats, "Median of this many builds and passes (default 3)")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--seed", args->seed, "Scene and ray seed")->check(kUnsigned64);
  cmd->add_option("--rays-file", args->rayFile,
                  "Trace these rays (mbrt trace format) as the secondary set of the one scene given");
  cmd->add_option("--budget", args->budget,
                  "Seconds all timed passes of one structure over its main ray set may take (default 20, --quick 2; "
                  "the other sets and its counted pass a quarter of it each); slower structures are "
                  "timed and counted on every k-th ray")
      ->check(kFinitePositive);
  cmd->add_option("--json", args->json, "Write every figure as JSON to this file");
  cmd->add_option("--html", args->html, "Write an HTML report with SVG bar charts to this file");
  cmd->add_option("--svg", args->svg,
                  "Write one SVG chart (secondary rays/s relative to Embree; with --scaling: cost against size)");
  cmd->add_flag("--scaling", args->scaling,
                "Cost against size: translate and hairball (or --scene) at --scaling-sizes, every BVH kind and "
                "embree (or --accel): build time, memory and secondary rays/s");
  cmd->add_option("--scaling-sizes", args->scalingSizes, "Comma-separated sizes for --scaling (default 0.1,1,10)");
  cmd->callback([args, cmd] {
    const bench::Options o = benchOptions(*args, *cmd);
    if (args->scaling) return runScaling(*args, *cmd, o);
    bench::Options run = o;
    if (!args->rayFile.empty()) run.rays = readRays(args->rayFile);
    const bench::Report report = bench::run(run, loadScenes(run));
    std::cout << bench::toMarkdown(report);
    writeFile(args->json, bench::toJson(report));
    writeFile(args->html, bench::toHtml(report));
    writeFile(args->svg, bench::toRatioSvg(report));
  });
}

}  // namespace mbrt::tools
