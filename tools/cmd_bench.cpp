// `mbrt bench`: every structure on the same rays, next to Embree and the
// frozen-time bound (issue 4). The engine is src/bench/.
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "mbrt/bench.h"
#include "bench_scenes.h"
#include "commands.h"
#include "mbrt/ray_file.h"
#include "mbrt/loaders.h"

namespace mbrt::tools {
namespace {

std::vector<std::string> splitList(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
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

struct BenchArgs {
  std::string scenes, accels, json, html, svg;
  bool quick = false;
  double size = 0.0;
  int rays = 0;
  int frozenTimes = 0;
  int repeats = 0;
  double budget = 0.0;
  std::string rayFile;
  uint64_t seed = 1;
};

}  // namespace

void registerBenchCommand(CLI::App& app) {
  auto args = std::make_shared<BenchArgs>();
  auto* cmd = app.add_subcommand("bench", "Benchmark every structure, Embree and the frozen bound on the same rays");
  cmd->add_option("--scene", args->scenes, "Comma-separated scenes: built-in names or files/globs as --scene elsewhere (default: the procedural suite)");
  cmd->add_option("--accel", args->accels, "Comma-separated accel kinds (default: all available but brute)");
  cmd->add_flag("--quick", args->quick, "Small scenes and ray sets: the whole suite in a few minutes");
  cmd->add_option("--size", args->size, "Scene size knob (1 = the default sizes)");
  cmd->add_option("--rays", args->rays, "Primary rays per side (default 512, --quick 128)");
  cmd->add_option("--frozen-times", args->frozenTimes, "K, the frozen times (default 16, --quick 8)");
  cmd->add_option("--repeats", args->repeats, "Median of this many builds and passes (default 3)");
  cmd->add_option("--seed", args->seed, "Scene and ray seed");
  cmd->add_option("--rays-file", args->rayFile,
                  "Trace these rays (mbrt trace format) as the main set of the one scene given");
  cmd->add_option("--budget", args->budget,
                  "Seconds all timed passes of one structure over one ray set may take (default 20, --quick 5; "
                  "its counted passes get a quarter of it); slower structures are timed and counted on "
                  "every k-th ray");
  cmd->add_option("--json", args->json, "Write every figure as JSON to this file");
  cmd->add_option("--html", args->html, "Write an HTML report with SVG bar charts to this file");
  cmd->add_option("--svg", args->svg, "Write one SVG chart of rays/s relative to Embree, every scene, to this file");
  cmd->callback([args] {
    bench::Options o;
    if (args->quick) o.makeQuick();
    if (args->size > 0) o.size = args->size;
    if (args->rays > 0) o.width = o.height = args->rays;
    if (args->frozenTimes > 0) o.frozenTimes = args->frozenTimes;
    if (args->repeats > 0) o.repeats = args->repeats;
    if (args->budget > 0) {
      o.passBudgetSeconds = args->budget;
      o.countBudgetSeconds = args->budget / 4.0;
    }
    o.seed = args->seed;
    o.scenes = splitList(args->scenes);
    o.accels = splitList(args->accels);
    o.commit = gitCommit();
    o.progress = stderr;
    if (!args->rayFile.empty()) o.rays = readRays(args->rayFile);
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
    const bench::Report report = bench::run(o, scenes);
    std::cout << bench::toMarkdown(report);
    auto write = [](const std::string& path, const std::string& text) {
      std::ofstream f(path);
      f << text;
      if (!f) throw Error("could not write " + path);
    };
    if (!args->json.empty()) write(args->json, bench::toJson(report));
    if (!args->html.empty()) write(args->html, bench::toHtml(report));
    if (!args->svg.empty()) write(args->svg, bench::toRatioSvg(report));
  });
}

}  // namespace mbrt::tools
