// The benchmark engine behind `mbrt bench`: every structure on the same rays
// per scene, the papers' metrics (DESIGN.md, "How to measure"), hit
// agreement with brute and Embree, and the frozen-time bound (library
// mbrt::bench).
#pragma once

#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/scenes.h"

namespace mbrt::bench {

// One structure under test. The default wraps an Accel; tests inject others.
class Target {
 public:
  virtual ~Target() = default;
  // Closest hits, in parallel in the caller's TBB arena.
  virtual void trace(std::span<const Ray> rays, std::span<Hit> hits) const = 0;
  // Counted pass (DESIGN.md's traversal steps); false when the structure
  // has no counters (Embree).
  virtual bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters& c) const = 0;
  virtual AccelStats stats() const = 0;
};

// A structure to benchmark: its row name and how to build it over a scene.
struct Candidate {
  std::string name;
  std::function<std::unique_ptr<Target>(const Scene&)> build;
  bool frozen = false;  // one tree per frozen time; its row reports the frozen set
};

struct Options {
  std::vector<std::string> scenes;  // empty: the procedural suite
  std::vector<std::string> accels;  // empty: every available kind but brute
  double size = 1.0;                // scene size knob (1 = the defaults)
  int width = 512, height = 512;    // primary rays
  int frozenTimes = 16;             // K
  size_t bruteSample = 2000;        // rays checked against brute
  size_t countSample = 20000;       // rays of the counted pass (fewer when over countBudgetSeconds)
  int repeats = 3;                  // median of this many passes / builds
  double singleBuildSeconds = 3.0;  // builds slower than this are timed once
  // A structure whose passes over the whole ray set would take longer than
  // this (all repeats together) is timed on every k-th ray of the set, k
  // chosen to fit (at least minTimedRays); its row says how many were timed.
  double passBudgetSeconds = 20.0;
  size_t minTimedRays = 4096;
  // The counted passes (main and frozen set) of one structure get this long,
  // estimated from the timed probe; a slower structure is counted on an
  // evenly spread subset of the sample (at least minCountedRays).
  double countBudgetSeconds = 5.0;
  size_t minCountedRays = 500;
  uint64_t seed = 1;
  std::string commit = "unknown";
  std::FILE* progress = nullptr;    // a progress line (stderr), or none
  std::vector<Candidate> extra;     // more structures (tests inject wrong ones)
  // Rays of the main set, instead of generated ones (one scene only; the
  // frozen set is still generated).
  std::vector<Ray> rays;

  // --quick: small scenes and ray sets, the whole suite in minutes.
  void makeQuick();
};

struct FrozenSetResult {
  size_t rays = 0;
  size_t timedRays = 0;
  double mraysMt = 0.0;
  std::optional<double> stepsMean, isectsMean;
  size_t mismatches = 0;
};

struct Result {
  std::string scene, accel;
  size_t primitives = 0;
  double buildS = 0.0, buildMprims = 0.0;
  int builds = 0;  // how many builds the median is over
  size_t bytes = 0, peakBuildBytes = 0;
  std::optional<double> sah;
  std::optional<double> stepsMean, stepsMax, boxTestsMean, isectsMean;
  std::optional<uint64_t> isectsMax;
  size_t rays = 0;
  size_t timedRays = 0;  // rays of the timed passes (every k-th of `rays` when the budget cut it)
  size_t countedRays = 0;  // rays of the counted pass (the sample, thinned when over its budget)
  double mraysSt = 0.0, mraysMt = 0.0;
  size_t mismatches = 0;                   // vs brute (sample) + vs embree (all)
  size_t mismatchesBrute = 0, bruteChecked = 0;
  std::optional<size_t> mismatchesEmbree;  // when embree ran and this is not it
  FrozenSetResult frozenSet;
};

struct Report {
  std::string cpu, commit;
  int threads = 0;
  Options options;
  std::vector<Result> results;
  std::vector<std::string> notes;  // skipped structures or scenes, and why
};

// The candidates for options.accels (or all available kinds but brute).
std::vector<Candidate> defaultCandidates(const Options& options, std::vector<std::string>* notes = nullptr);

// Runs everything. Throws Error for unknown scene or accel names.
Report run(const Options& options);
// Same on given scenes (tests: tiny hand-made scenes).
Report run(const Options& options, const std::vector<ProceduralScene>& scenes);

std::string toMarkdown(const Report& report);
std::string toJson(const Report& report);
std::string toHtml(const Report& report);
// Every structure's rays/s (all threads) over Embree's, per scene, as one SVG.
std::string toRatioSvg(const Report& report);

// Rays for a scene (exposed for tests): primaries from the camera at random
// times, then one cosine bounce from each primary hit found by `reference`.
std::vector<Ray> makeRays(const ProceduralScene& scene, const Target& reference, int width, int height,
                          uint64_t seed, const std::vector<float>* snapTimes = nullptr);

// A candidate that builds an Accel of `kind`.
Candidate accelCandidate(AccelKind kind);

}  // namespace mbrt::bench
