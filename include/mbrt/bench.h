// The benchmark engine behind `mbrt bench`: every structure on the same ray
// sets per scene (primary, secondary, shadow, and the secondary rays at the
// frozen times), the papers' metrics (docs/design.md, "How we measure"), hit
// agreement with brute and Embree, Embree in its default, robust and static
// modes, and the geometric means of the best mbrt kind over each Embree mode.
// Library mbrt::bench; used by tools/cmd_bench.cpp and the tests.
#pragma once

#include <array>
#include <cstdio>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/scenes.h"

namespace mbrt::bench {

// The ray sets of a scene. Secondary is the headline: what a renderer traces
// most (diffuse bounces from every primary hit, and rays from around the
// scene into its bounds). Shadow rays go through `occluded`. Frozen is the
// secondary set built from primaries at the frozen times (each ray sits on
// one), the set `frozen`, `embree-static` and `embree-static-robust` trace.
// Incoherent rays come from all around the scene at points of its
// primitives (incoherentRays): nearly all hit, none shares a path with the
// next, and none depends on a camera (the kernel's cost of a visit).
enum class RaySet { Primary, Secondary, Shadow, Frozen, Incoherent };
constexpr int kRaySets = 5;
constexpr std::array<RaySet, kRaySets> kAllRaySets{RaySet::Primary, RaySet::Secondary, RaySet::Shadow, RaySet::Frozen,
                                                   RaySet::Incoherent};
std::string_view toString(RaySet set);
constexpr bool isOcclusion(RaySet set) { return set == RaySet::Shadow; }

// One structure under test. The default wraps an Accel; tests inject others.
class Target {
 public:
  virtual ~Target() = default;
  // Closest hits / any hits, in parallel in the caller's TBB arena.
  virtual void trace(std::span<const Ray> rays, std::span<Hit> hits) const = 0;
  virtual void occluded(std::span<const Ray> rays, std::span<uint8_t> occluded) const = 0;
  // Counted pass (docs/design.md's work per ray); false when the structure
  // has no counters (Embree).
  virtual bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters& c) const = 0;
  virtual AccelStats stats() const = 0;
};

// A structure to benchmark: its row name and how to build it over a scene.
struct Candidate {
  std::string name;
  std::function<std::unique_ptr<Target>(const Scene&)> build;
  bool frozen = false;  // one structure per frozen time: its row traces the frozen set only
  bool peer = false;    // an Embree mode, not an mbrt kind (the geometric means' denominators)
};

struct Options {
  std::vector<std::string> scenes;  // empty: the procedural suite
  std::vector<std::string> accels;  // empty: every available kind but brute, Embree in its three modes
  double size = 1.0;                // scene size knob (1 = the defaults)
  int width = 512, height = 512;    // primary rays; the other sets have as many rays
  int frozenTimes = 16;             // K
  size_t bruteSample = 2000;        // rays of each set checked against brute
  size_t countSample = 20000;       // rays of the counted pass (fewer when over countBudgetSeconds)
  int repeats = 3;                  // median of this many passes / builds
  double singleBuildSeconds = 3.0;  // builds slower than this are timed once
  // A structure whose passes over one ray set would take longer than this
  // (all repeats together) is timed on every k-th ray of the set, k chosen
  // to fit (at least minTimedRays); its row says how many were timed.
  double passBudgetSeconds = 20.0;
  size_t minTimedRays = 4096;
  // The counted pass of one structure gets this long, estimated from the
  // timed probe; a slower structure is counted on an evenly spread subset
  // of the sample (at least minCountedRays).
  double countBudgetSeconds = 5.0;
  size_t minCountedRays = 500;
  // Only the secondary set, on all threads (`--scaling`: cost against size).
  bool secondaryOnly = false;
  uint64_t seed = 1;
  std::string commit = "unknown";
  std::FILE* progress = nullptr;    // progress messages (stderr), or none
  bool progressTerminal = false;    // progress overwrites one line (a terminal); else one line per structure
  std::vector<Candidate> extra;     // more structures (tests inject wrong ones)
  // Rays of the secondary set, instead of generated ones (one scene only;
  // the other sets are still generated).
  std::vector<Ray> rays;

  // --quick: small scenes and ray sets, the whole suite in minutes.
  void makeQuick();
};

// What a scene's sets are: their size and hit rate (the reference
// structure's: closest hits, or occluded rays for the shadow set).
struct SetInfo {
  size_t rays = 0;
  double hitRate = 0.0;
};
struct SceneInfo {
  std::string name;
  size_t primitives = 0;
  std::array<SetInfo, kRaySets> sets;
  size_t bounces = 0, inward = 0;  // the secondary set's two parts
};

// One structure on one set.
struct SetResult {
  bool traced = false;
  size_t rays = 0;
  size_t timedRays = 0;  // every k-th of `rays` when the budget cut it
  double mraysSt = 0.0, mraysMt = 0.0;  // st: 0 where not timed on one thread
  size_t mismatchesBrute = 0, bruteChecked = 0;
  std::optional<size_t> mismatchesEmbree;  // vs embree-robust on every ray both traced
};

struct Result {
  std::string scene, accel;
  bool frozen = false, peer = false;  // as the Candidate
  size_t primitives = 0;
  double buildS = 0.0, buildMprims = 0.0;
  int builds = 0;  // how many builds the median is over
  size_t bytes = 0, peakBuildBytes = 0;
  std::optional<double> sah;
  // Counters over the row's main set: secondary, or frozen for frozen rows.
  std::optional<double> stepsMean, stepsMax, boxTestsMean, isectsMean;
  std::optional<uint64_t> isectsMax;
  size_t countedRays = 0;  // rays of the counted pass (the sample, thinned when over its budget)
  std::array<SetResult, kRaySets> sets;

  const SetResult& set(RaySet s) const { return sets[size_t(s)]; }
  SetResult& set(RaySet s) { return sets[size_t(s)]; }
  RaySet mainSet() const { return frozen ? RaySet::Frozen : RaySet::Secondary; }
  size_t mismatches() const;  // over every set, vs brute and embree-robust
};

// The geometric mean over scenes of (best mbrt kind ÷ peer) on one set's
// rays/s (all threads). For the frozen set the numerator is `frozen`.
struct Geomean {
  RaySet set;
  std::string peer;
  double value = 0.0;
  int scenes = 0;  // scenes where both ran
};

struct Report {
  std::string cpu, commit;
  int threads = 0;
  Options options;
  std::vector<SceneInfo> scenes;
  std::vector<Result> results;
  std::vector<std::string> notes;  // skipped structures or scenes, and why
};

// Bench row names --accel takes: the kind names, "embree" (Embree's
// defaults), "embree-robust", "embree-static" and "embree-static-robust".
std::vector<std::string> candidateNames();
// The candidates for options.accels (or the default list). Throws Error for
// an unknown name.
std::vector<Candidate> defaultCandidates(const Options& options, std::vector<std::string>* notes = nullptr);
// A candidate that builds an Accel of `kind`.
Candidate accelCandidate(AccelKind kind, BuildOptions::EmbreeMode mode = BuildOptions::EmbreeMode::Default);

// Runs everything. Throws Error for unknown scene or accel names.
Report run(const Options& options);
// Same on given scenes (tests: tiny hand-made scenes).
Report run(const Options& options, const std::vector<ProceduralScene>& scenes);

// The best mbrt row of a scene on a set (fastest on all threads; not a peer,
// not a frozen row unless the set is Frozen), or none.
// singleKinds: leave out `auto`, which combines kinds.
const Result* bestMbrt(const Report& report, const std::string& scene, RaySet set, bool singleKinds = false);
// Per set, per peer that ran: primary/secondary/shadow over embree and
// embree-robust, frozen over embree-static and embree-static-robust.
std::vector<Geomean> geomeans(const Report& report);

std::string toMarkdown(const Report& report);
std::string toJson(const Report& report);
std::string toHtml(const Report& report);
// Every structure's secondary rays/s (all threads) over Embree's, per scene, as one SVG.
std::string toRatioSvg(const Report& report);

// The ray sets of a scene (exposed for tests), from the camera at random
// times; `reference` finds the primary hits the secondary and shadow rays
// start from. `secondary`, when given, replaces the generated secondary set.
struct RaySets {
  std::array<std::vector<Ray>, kRaySets> sets;
  size_t bounces = 0, inward = 0;
  const std::vector<Ray>& operator[](RaySet s) const { return sets[size_t(s)]; }
};
RaySets makeRaySets(const ProceduralScene& scene, const Target& reference, int width, int height, uint64_t seed,
                    const std::vector<float>& frozenTimes, bool secondaryOnly = false);

// n incoherent rays from all around `scene` (a sphere of its bounds'
// diagonal) towards points on its primitives at random times: nearly all
// hit, none shares a path with the next (src/bench/incoherent_rays.cpp).
// With `time`, every ray is at that time (a static tree's rays).
// Deterministic for a seed.
std::vector<Ray> incoherentRays(const Scene& scene, size_t n, uint64_t seed, std::optional<float> time = {});

// `mbrt bench --scaling`: scenes at several sizes, each structure's build
// time, memory and secondary rays/s against the primitive count.
struct ScalingOptions {
  std::vector<std::string> scenes{"translate", "hairball"};
  std::vector<double> sizes{0.1, 1.0, 10.0};
  std::vector<std::string> accels;  // empty: every BVH kind and embree
  Options bench;                    // rays, repeats, budgets
};
struct ScalingRow {
  std::string scene, accel;
  double size = 0.0;
  size_t primitives = 0;
  double buildS = 0.0;
  size_t bytes = 0;
  double mraysMt = 0.0;  // secondary set, all threads
};
struct ScalingReport {
  std::string cpu, commit;
  int threads = 0;
  std::vector<ScalingRow> rows;
  std::vector<std::string> notes;
};
std::vector<std::string> scalingDefaultAccels();
ScalingReport runScaling(const ScalingOptions& options);
std::string toMarkdown(const ScalingReport& report);
std::string toJson(const ScalingReport& report);
std::string toSvg(const ScalingReport& report);

}  // namespace mbrt::bench
