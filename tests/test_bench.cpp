// The benchmark engine end to end on tiny scenes: its JSON has the issue's
// keys, and hit disagreements are reported, not hidden.
#include <gtest/gtest.h>

#include <algorithm>

#include "mbrt/bench.h"

using namespace mbrt;

namespace {

ProceduralScene tinyScene() {
  ProceduralScene ps;
  ps.name = "tiny";
  ps.scene = std::make_shared<Scene>();
  // A moving grid of 2x8x8 triangles facing the camera, plus a segment.
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> steps(2);
  const int n = 8;
  for (int k = 0; k < 2; ++k)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x)
        steps[k].push_back({float(x) / n - 0.5f + 0.1f * float(k), float(y) / n - 0.5f, 0.05f * float(x % 2)});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const uint32_t a = uint32_t(y * (n + 1) + x), b = a + 1, c = a + uint32_t(n + 1), d = c + 1;
      tris.push_back({a, b, d});
      tris.push_back({a, d, c});
    }
  ps.scene->addTriangleMesh(tris, steps);
  ps.scene->addSegments({{0, 1}}, {{{-0.4f, 0, 0.3f}, {0.4f, 0.2f, 0.3f}}, {{-0.4f, 0.1f, 0.3f}, {0.4f, 0.3f, 0.3f}}},
                        {0.03f, 0.03f});
  ps.camera = frameBox(Box3f({-0.6f, -0.6f, -0.1f}, {0.6f, 0.6f, 0.4f}));
  return ps;
}

bench::Options tinyOptions() {
  bench::Options o;
  o.width = o.height = 24;
  o.repeats = 1;
  o.bruteSample = 300;
  o.countSample = 300;
  o.frozenTimes = 4;
  // Whatever this build has of the structures the bench is about.
  for (const char* name : {"bvh-interp", "frozen", "embree"}) {
    const auto kinds = availableAccelKinds();
    if (std::find(kinds.begin(), kinds.end(), *parseAccelKind(name)) != kinds.end()) o.accels.push_back(name);
  }
  if (o.accels.empty()) o.accels = {"brute"};
  return o;
}

// A structure that answers with brute's hits, but drops every third hit.
class Dropper final : public bench::Target {
 public:
  explicit Dropper(const Scene& s) {
    BuildOptions o;
    o.kind = AccelKind::Brute;
    accel_ = Accel::build(s, o);
  }
  void trace(std::span<const Ray> rays, std::span<Hit> hits) const override {
    accel_->intersect(rays, hits);
    for (size_t i = 0; i < rays.size(); i += 3) hits[i] = Hit();
  }
  bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters&) const override {
    trace(rays, hits);
    return false;
  }
  AccelStats stats() const override { return accel_->stats(); }

 private:
  std::unique_ptr<Accel> accel_;
};

}  // namespace

TEST(Bench, RunsEndToEndAndWritesTheJsonKeys) {
  const bench::Report report = bench::run(tinyOptions(), {tinyScene()});
  ASSERT_FALSE(report.results.empty());
  for (const bench::Result& r : report.results) {
    EXPECT_EQ(r.mismatches, 0u) << r.accel;
    EXPECT_GT(r.rays, 24u * 24u) << "primaries and bounces";
    EXPECT_GT(r.mraysMt, 0.0);
    EXPECT_EQ(r.primitives, 129u);
  }
  const std::string json = bench::toJson(report);
  for (const char* key : {"machine", "cpu", "threads", "commit", "results", "scene", "accel", "primitives",
                          "build_s", "build_mprims", "bytes", "peak_build_bytes", "sah", "steps_mean",
                          "box_tests_mean", "isects_mean", "isects_max", "rays", "mrays_st", "mrays_mt",
                          "mismatches", "frozen_set"})
    EXPECT_NE(json.find("\"" + std::string(key) + "\":"), std::string::npos) << key;
  // Balanced braces and brackets outside strings: a tiny well-formedness check.
  int braces = 0, brackets = 0;
  bool inString = false;
  for (size_t i = 0; i < json.size(); ++i) {
    const char c = json[i];
    if (inString) {
      if (c == '\\') ++i;
      else if (c == '"') inString = false;
      continue;
    }
    if (c == '"') inString = true;
    braces += c == '{' ? 1 : c == '}' ? -1 : 0;
    brackets += c == '[' ? 1 : c == ']' ? -1 : 0;
    ASSERT_GE(braces, 0);
    ASSERT_GE(brackets, 0);
  }
  EXPECT_EQ(braces, 0);
  EXPECT_EQ(brackets, 0);
  EXPECT_FALSE(inString);
  EXPECT_NE(bench::toMarkdown(report).find("| accel |"), std::string::npos);
  EXPECT_NE(bench::toHtml(report).find("<svg"), std::string::npos);
  const std::string svg = bench::toRatioSvg(report);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("bvh-interp"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST(Bench, AWrongStructureRaisesTheMismatchCount) {
  bench::Options o = tinyOptions();
  o.extra.push_back({"dropper", [](const Scene& s) { return std::make_unique<Dropper>(s); }, false});
  const bench::Report report = bench::run(o, {tinyScene()});
  const bench::Result* dropper = nullptr;
  for (const bench::Result& r : report.results) {
    if (r.accel == "dropper") dropper = &r;
    else EXPECT_EQ(r.mismatches, 0u) << r.accel;
  }
  ASSERT_NE(dropper, nullptr);
  EXPECT_GT(dropper->mismatchesBrute, 10u);
  EXPECT_GT(dropper->frozenSet.mismatches, 10u);
#ifdef MBRT_HAVE_EMBREE
  ASSERT_TRUE(dropper->mismatchesEmbree.has_value());
  EXPECT_GT(*dropper->mismatchesEmbree, 10u);
#endif
  EXPECT_FALSE(dropper->stepsMean.has_value()) << "no counters: n/a";
}

TEST(Bench, RunsOnAProceduralScene) {
  bench::Options o = tinyOptions();
  o.scenes = {"demo"};
  o.size = 0.02;
  const bench::Report report = bench::run(o);
  ASSERT_FALSE(report.results.empty());
  EXPECT_EQ(report.results[0].scene, "demo");
  EXPECT_EQ(report.results[0].mismatches, 0u);
}

TEST(Bench, ASlowCountedPassIsThinnedToItsBudget) {
  bench::Options o = tinyOptions();
  o.accels = {"bvh-interp"};
  o.countSample = 300;
  bench::Report full = bench::run(o, {tinyScene()});
  ASSERT_EQ(full.results.size(), 1u);
  EXPECT_EQ(full.results[0].countedRays, 300u) << "a fast structure is counted on the whole sample";

  o.countBudgetSeconds = 1e-12;  // nothing fits: down to the minimum
  o.minCountedRays = 50;
  const bench::Report thin = bench::run(o, {tinyScene()});
  ASSERT_EQ(thin.results.size(), 1u);
  const bench::Result& r = thin.results[0];
  EXPECT_GE(r.countedRays, 50u);
  EXPECT_LT(r.countedRays, 300u);
  ASSERT_TRUE(r.stepsMean.has_value());
  EXPECT_GT(*r.stepsMean, 0.0);
  EXPECT_NE(bench::toMarkdown(thin).find("counters are over"), std::string::npos);
}
