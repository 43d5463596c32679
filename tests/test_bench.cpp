// The benchmark engine end to end on tiny scenes: every ray set is there
// with a hit rate that matches its rays, the JSON has the keys, the
// geometric means follow from the rows, hit disagreements are reported, not
// hidden, and --scaling gives one row per size.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

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

bool hasEmbree();

bench::Options tinyOptions() {
  bench::Options o;
  o.width = o.height = 24;
  o.repeats = 1;
  o.bruteSample = 300;
  o.countSample = 300;
  o.frozenTimes = 4;
  // Whatever this build has of the structures the bench is about.
  for (const char* name : {"bvh-interp", "frozen"}) o.accels.push_back(name);
  if (hasEmbree())
    for (const char* name : {"embree", "embree-robust", "embree-static", "embree-static-robust"})
      o.accels.push_back(name);
  return o;
}

bool hasEmbree() {
  const auto kinds = availableAccelKinds();
  return std::find(kinds.begin(), kinds.end(), AccelKind::Embree) != kinds.end();
}

// Brute's answers on a set: hits (or occluded rays) counted.
double bruteRate(const Scene& scene, const std::vector<Ray>& rays, bool occlusion) {
  BuildOptions o;
  o.kind = AccelKind::Brute;
  auto brute = Accel::build(scene, o);
  size_t n = 0;
  for (const Ray& r : rays) {
    Hit h;
    n += occlusion ? brute->occluded(r) : brute->intersect(r, h);
  }
  return rays.empty() ? 0.0 : double(n) / double(rays.size());
}

// An Accel as a bench target, without counters.
class AccelOnly final : public bench::Target {
 public:
  AccelOnly(const Scene& s, AccelKind kind) {
    BuildOptions o;
    o.kind = kind;
    a_ = Accel::build(s, o);
  }
  void trace(std::span<const Ray> r, std::span<Hit> h) const override { a_->intersect(r, h); }
  void occluded(std::span<const Ray> r, std::span<uint8_t> o) const override { a_->occluded(r, o); }
  bool traceCounted(std::span<const Ray>, std::span<Hit>, TraversalCounters&) const override { return false; }
  AccelStats stats() const override { return a_->stats(); }

 private:
  std::unique_ptr<Accel> a_;
};

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
  void occluded(std::span<const Ray> rays, std::span<uint8_t> occ) const override {
    accel_->occluded(rays, occ);
    for (size_t i = 0; i < rays.size(); i += 3) occ[i] = 0;
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
  ASSERT_EQ(report.scenes.size(), 1u);
  for (const bench::Result& r : report.results) {
    // mbrt agrees with brute on every set; Embree's disagreements (edges
    // in its default mode, capsules at the step times) are counted, and few.
    size_t bruteMismatches = 0;
    for (const bench::SetResult& f : r.sets) bruteMismatches += f.mismatchesBrute;
    if (r.peer)
      EXPECT_LE(bruteMismatches, 4u) << r.accel;
    else
      EXPECT_EQ(bruteMismatches, 0u) << r.accel;
    EXPECT_EQ(r.primitives, 129u);
    for (bench::RaySet s : bench::kAllRaySets) {
      const bench::SetResult& f = r.set(s);
      // Motion rows trace every set; frozen rows the frozen set only.
      EXPECT_EQ(f.traced, !r.frozen || s == bench::RaySet::Frozen) << r.accel << " " << bench::toString(s);
      if (!f.traced) continue;
      EXPECT_EQ(f.rays, report.scenes[0].sets[size_t(s)].rays);
      EXPECT_GT(f.mraysMt, 0.0) << r.accel << " " << bench::toString(s);
      EXPECT_GT(f.bruteChecked, 0u);
    }
    EXPECT_EQ(r.set(r.mainSet()).mraysSt > 0.0, true) << "the main set is timed on one thread too";
  }
  const std::string json = bench::toJson(report);
  for (const char* key : {"machine", "cpu", "threads", "commit", "scenes", "hit_rate", "bounces", "inward",
                          "results", "scene", "accel", "primitives", "build_s", "build_mprims", "bytes",
                          "peak_build_bytes", "sah", "steps_mean", "box_tests_mean", "isects_mean", "isects_max",
                          "sets", "primary", "secondary", "shadow", "frozen", "rays", "mrays_st", "mrays_mt",
                          "mismatches", "geomeans"})
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
  const std::string md = bench::toMarkdown(report);
  EXPECT_NE(md.find("| accel |"), std::string::npos);
  EXPECT_NE(md.find("secondary Mrays/s mt"), std::string::npos);
  EXPECT_NE(md.find("Rays: primary "), std::string::npos);
  EXPECT_NE(bench::toHtml(report).find("<svg"), std::string::npos);
  const std::string svg = bench::toRatioSvg(report);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("bvh-interp"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  if (hasEmbree()) {
    EXPECT_NE(md.find("Geometric mean over scenes"), std::string::npos);
    EXPECT_NE(md.find("| secondary (headline) |"), std::string::npos);
  }
}

TEST(Bench, EverySetIsThereWithItsHitRate) {
  const ProceduralScene ps = tinyScene();
  const bench::Report report = bench::run(tinyOptions(), {ps});
  ASSERT_EQ(report.scenes.size(), 1u);
  const bench::SceneInfo& info = report.scenes[0];
  EXPECT_EQ(info.primitives, 129u);

  // The same sets again, to count their hits with brute.
  const AccelOnly brute(*ps.scene, AccelKind::Brute);
  const bench::Options o = tinyOptions();
  std::vector<float> times;
  for (int k = 0; k < o.frozenTimes; ++k) times.push_back(float(k) / float(o.frozenTimes - 1));
  const bench::RaySets sets = bench::makeRaySets(ps, brute, o.width, o.height, o.seed, times);

  const size_t n = size_t(o.width) * size_t(o.height);
  EXPECT_EQ(info.sets[size_t(bench::RaySet::Primary)].rays, n);
  for (bench::RaySet s : bench::kAllRaySets) {
    const bench::SetInfo& si = info.sets[size_t(s)];
    EXPECT_GT(si.rays, 0u) << bench::toString(s);
    EXPECT_GE(si.hitRate, 0.0);
    EXPECT_LE(si.hitRate, 1.0);
  }
  // The secondary set: a bounce from every primary hit (at least n/2), and
  // n/2 rays from around the scene.
  const double primaryRate = bruteRate(*ps.scene, sets[bench::RaySet::Primary], false);
  const size_t primaryHits = size_t(std::lround(primaryRate * double(n)));
  EXPECT_EQ(sets.bounces, std::max(primaryHits, n / 2));
  EXPECT_EQ(sets.inward, n / 2);
  EXPECT_EQ(sets[bench::RaySet::Secondary].size(), sets.bounces + sets.inward);
  EXPECT_GT(bruteRate(*ps.scene, sets[bench::RaySet::Secondary], false), primaryRate)
      << "the secondary set mostly hits, the camera mostly sees sky here";
  // Every frozen-set ray sits on a frozen time, the rays grouped by time
  // (each frozen tree traces its rays in one run), every time present.
  for (const Ray& r : sets[bench::RaySet::Frozen])
    EXPECT_NE(std::find(times.begin(), times.end(), r.time), times.end());
  const std::vector<Ray>& frozen = sets[bench::RaySet::Frozen];
  EXPECT_TRUE(std::is_sorted(frozen.begin(), frozen.end(), [](const Ray& a, const Ray& b) { return a.time < b.time; }));
  for (float t : times)
    EXPECT_NE(std::find_if(frozen.begin(), frozen.end(), [t](const Ray& r) { return r.time == t; }), frozen.end())
        << "time " << t;
  // The incoherent set: n rays aimed at points of the primitives at their
  // own times, so that nearly all hit whatever the camera sees; with a
  // time, every ray is at it; the same rays for the same seed.
  const std::vector<Ray>& incoherent = sets[bench::RaySet::Incoherent];
  EXPECT_EQ(incoherent.size(), n);
  EXPECT_GT(bruteRate(*ps.scene, incoherent, false), 0.9);
  EXPECT_GT(bruteRate(*ps.scene, incoherent, false), primaryRate);
  for (const Ray& r : incoherent) EXPECT_TRUE(r.time >= 0.0f && r.time <= 1.0f && isValidRay(r));
  const std::vector<Ray> atHalf = bench::incoherentRays(*ps.scene, 200, 3, 0.5f);
  EXPECT_EQ(atHalf.size(), 200u);
  for (const Ray& r : atHalf) EXPECT_EQ(r.time, 0.5f);
  EXPECT_EQ(bench::incoherentRays(*ps.scene, 50, 3)[7].org, bench::incoherentRays(*ps.scene, 50, 3)[7].org);
  EXPECT_NE(bench::incoherentRays(*ps.scene, 50, 3)[7].org, bench::incoherentRays(*ps.scene, 50, 4)[7].org);
}

TEST(Bench, TheReportedHitRatesAreTheRaysHitRates) {
  // Recount a run's sets with brute: the rates printed are those of the rays
  // traced (the reference may differ from brute on an edge ray or two).
  const ProceduralScene ps = tinyScene();
  bench::Options o = tinyOptions();
  const bench::Report report = bench::run(o, {ps});
  ASSERT_EQ(report.scenes.size(), 1u);
  const AccelOnly ref(*ps.scene, AccelKind::Stbvh);  // the bench's reference
  std::vector<float> times;
  for (int k = 0; k < o.frozenTimes; ++k) times.push_back(float(k) / float(o.frozenTimes - 1));
  const uint64_t seed = o.seed ^ [&] {
    uint64_t h = 1469598103934665603ull;
    for (char c : ps.name) h = (h ^ uint8_t(c)) * 1099511628211ull;
    return h;
  }();
  const bench::RaySets sets = bench::makeRaySets(ps, ref, o.width, o.height, seed, times);
  for (bench::RaySet s : bench::kAllRaySets) {
    ASSERT_EQ(sets[s].size(), report.scenes[0].sets[size_t(s)].rays) << bench::toString(s);
    EXPECT_NEAR(report.scenes[0].sets[size_t(s)].hitRate, bruteRate(*ps.scene, sets[s], bench::isOcclusion(s)),
                0.01)
        << bench::toString(s);
  }
}

TEST(Bench, GeometricMeansFollowFromTheRows) {
  // Two scenes, hand-made rows: the best mbrt kind per scene and set is the
  // fastest non-peer row (frozen rows only for the frozen set).
  bench::Report rep;
  auto row = [&](const std::string& scene, const std::string& accel, bool frozen, bool peer,
                 std::array<double, bench::kRaySets> mt) {  // incoherent: not traced
    bench::Result r;
    r.scene = scene;
    r.accel = accel;
    r.frozen = frozen;
    r.peer = peer;
    for (bench::RaySet s : bench::kAllRaySets) {
      if (mt[size_t(s)] <= 0) continue;
      r.set(s).traced = true;
      r.set(s).rays = 100;
      r.set(s).mraysMt = mt[size_t(s)];
    }
    rep.results.push_back(r);
  };
  for (const char* scene : {"a", "b"}) {
    bench::SceneInfo info;
    info.name = scene;
    rep.scenes.push_back(info);
  }
  // Scene a: best secondary is stbvh (4), embree 2, robust 1.
  row("a", "bvh-interp", false, false, {1, 3, 1, 1});
  row("a", "stbvh", false, false, {2, 4, 3, 1});
  row("a", "frozen", true, false, {0, 0, 0, 6});
  row("a", "embree", false, true, {1, 2, 2, 9});
  row("a", "embree-robust", false, true, {1, 1, 1, 9});
  row("a", "embree-static", true, true, {0, 0, 0, 3});
  row("a", "embree-static-robust", true, true, {0, 0, 0, 2});
  // Scene b: best secondary is bvh-interp (1), embree 4, robust 2; a peer
  // faster than everything does not count as mbrt's best.
  row("b", "bvh-interp", false, false, {8, 1, 1, 1});
  row("b", "stbvh", false, false, {4, 0.5, 2, 1});
  row("b", "frozen", true, false, {0, 0, 0, 2});
  row("b", "embree", false, true, {2, 4, 4, 9});
  row("b", "embree-robust", false, true, {1, 2, 1, 9});
  row("b", "embree-static", true, true, {0, 0, 0, 4});
  row("b", "embree-static-robust", true, true, {0, 0, 0, 8});

  ASSERT_NE(bench::bestMbrt(rep, "a", bench::RaySet::Secondary), nullptr);
  EXPECT_EQ(bench::bestMbrt(rep, "a", bench::RaySet::Secondary)->accel, "stbvh");
  EXPECT_EQ(bench::bestMbrt(rep, "b", bench::RaySet::Secondary)->accel, "bvh-interp");
  EXPECT_EQ(bench::bestMbrt(rep, "b", bench::RaySet::Frozen)->accel, "frozen");

  auto value = [&](bench::RaySet set, const std::string& peer) {
    for (const bench::Geomean& g : bench::geomeans(rep))
      if (g.set == set && g.peer == peer) {
        EXPECT_EQ(g.scenes, 2);
        return g.value;
      }
    ADD_FAILURE() << "no geomean for " << bench::toString(set) << " / " << peer;
    return 0.0;
  };
  EXPECT_NEAR(value(bench::RaySet::Secondary, "embree"), std::sqrt((4.0 / 2) * (1.0 / 4)), 1e-12);
  EXPECT_NEAR(value(bench::RaySet::Secondary, "embree-robust"), std::sqrt((4.0 / 1) * (1.0 / 2)), 1e-12);
  EXPECT_NEAR(value(bench::RaySet::Primary, "embree"), std::sqrt((2.0 / 1) * (8.0 / 2)), 1e-12);
  EXPECT_NEAR(value(bench::RaySet::Shadow, "embree-robust"), std::sqrt((3.0 / 1) * (2.0 / 1)), 1e-12);
  EXPECT_NEAR(value(bench::RaySet::Frozen, "embree-static"), std::sqrt((6.0 / 3) * (2.0 / 4)), 1e-12);
  EXPECT_NEAR(value(bench::RaySet::Frozen, "embree-static-robust"), std::sqrt((6.0 / 2) * (2.0 / 8)), 1e-12);
  for (const bench::Geomean& g : bench::geomeans(rep))
    EXPECT_FALSE(g.set == bench::RaySet::Frozen && g.peer != "embree-static" && g.peer != "embree-static-robust")
        << "frozen goes with the static peers only";
  const std::string md = bench::toMarkdown(rep);
  EXPECT_NE(md.find("| secondary (headline) | 0.707 | 1.41 | – | – | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| frozen (`frozen`) | – | – | 1 | 0.866 | 2 |"), std::string::npos) << md;
  EXPECT_NE(md.find("| 6 | 2 | 3 | – | – | 0/0 brute |"), std::string::npos)
      << "scene a's frozen row: its frozen set, ÷ embree-static and ÷ embree-static-robust, no incoherent set: " << md;
}

TEST(Bench, AWrongStructureRaisesTheMismatchCount) {
  bench::Options o = tinyOptions();
  o.extra.push_back({"dropper", [](const Scene& s) { return std::make_unique<Dropper>(s); }, false, false});
  const bench::Report report = bench::run(o, {tinyScene()});
  const bench::Result* dropper = nullptr;
  for (const bench::Result& r : report.results) {
    if (r.accel == "dropper") dropper = &r;
    else if (!r.peer)
      for (const bench::SetResult& f : r.sets) EXPECT_EQ(f.mismatchesBrute, 0u) << r.accel;
  }
  ASSERT_NE(dropper, nullptr);
  for (bench::RaySet s : bench::kAllRaySets) {
    EXPECT_GT(dropper->set(s).mismatchesBrute, 10u) << bench::toString(s);
    if (hasEmbree()) {
      ASSERT_TRUE(dropper->set(s).mismatchesEmbree.has_value());
      EXPECT_GT(*dropper->set(s).mismatchesEmbree, 10u) << bench::toString(s);
    }
  }
  EXPECT_FALSE(dropper->stepsMean.has_value()) << "no counters: n/a";
}

TEST(Bench, RunsOnAProceduralScene) {
  bench::Options o = tinyOptions();
  o.scenes = {"demo"};
  o.size = 0.02;
  const bench::Report report = bench::run(o);
  ASSERT_FALSE(report.results.empty());
  EXPECT_EQ(report.results[0].scene, "demo");
  EXPECT_EQ(report.results[0].mismatches(), 0u);
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

TEST(Bench, ScalingGivesOneRowPerSizeAndStructure) {
  bench::ScalingOptions so;
  so.scenes = {"translate"};
  so.sizes = {0.002, 0.008};
  so.accels = {"bvh-interp"};
  if (hasEmbree()) so.accels.push_back("embree");
  so.bench = tinyOptions();
  so.bench.accels.clear();
  const bench::ScalingReport rep = bench::runScaling(so);
  ASSERT_EQ(rep.rows.size(), 2 * so.accels.size());
  for (size_t i = 0; i < rep.rows.size(); i += 2) {
    const bench::ScalingRow &a = rep.rows[i], &b = rep.rows[i + 1];
    EXPECT_EQ(a.accel, b.accel);
    EXPECT_EQ(a.size, 0.002);
    EXPECT_EQ(b.size, 0.008);
    EXPECT_LT(a.primitives, b.primitives) << "a bigger size has more primitives";
    EXPECT_GT(a.bytes, 0u);
    EXPECT_GT(a.mraysMt, 0.0);
  }
  const std::string md = bench::toMarkdown(rep);
  EXPECT_NE(md.find("| translate | bvh-interp | 0.002 |"), std::string::npos) << md;
  const std::string svg = bench::toSvg(rep);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("<polyline"), std::string::npos);
  EXPECT_NE(bench::toJson(rep).find("\"mrays_mt\":"), std::string::npos);
}

TEST(Bench, FarOriginRaysGoThroughEmbreeModes) {
  // Rays from beyond Embree's FLT_LARGE (1.844e18) as the secondary set:
  // Embree would abort on them. The bench runs them through every mode; mbrt
  // agrees with brute, Embree's misses (its own precision far out on moving
  // geometry, from 1e17 on) are counted, not hidden.
  if (!hasEmbree()) GTEST_SKIP() << "mbrt was built without Embree";
  bench::Options o = tinyOptions();
  o.accels = {"bvh-interp", "embree", "embree-robust"};
  for (int i = 0; i < 64; ++i) {
    Ray r;
    r.org = {-0.35f + 0.1f * float(i % 8), -0.35f + 0.1f * float(i / 8), 3e18f};
    r.dir = {0.0f, 0.0f, -1.0f};  // straight at the grid
    r.time = float(i) / 63.0f;
    o.rays.push_back(r);
  }
  const bench::Report report = bench::run(o, {tinyScene()});
  ASSERT_EQ(report.results.size(), 3u);
  for (const bench::Result& r : report.results) {
    const bench::SetResult& s = r.set(bench::RaySet::Secondary);
    EXPECT_EQ(s.rays, 64u);
    EXPECT_EQ(s.bruteChecked, 64u);
    if (!r.peer) EXPECT_EQ(s.mismatchesBrute, 0u) << r.accel;
  }
  EXPECT_EQ(report.scenes[0].sets[size_t(bench::RaySet::Secondary)].hitRate, 1.0) << "every ray hits the grid";
}

TEST(Bench, EmbreeStaticIsTheSceneAtTheFrozenTime) {
  // Embree's static mode over a moving mesh, a segment and an instance with
  // three keys: what brute sees at the frozen time.
  if (!hasEmbree()) GTEST_SKIP() << "mbrt was built without Embree";
  ProceduralScene ps = tinyScene();
  auto child = std::make_shared<Scene>();
  child->addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {0.3f, 0, 0}, {0, 0.3f, 0}}});
  ps.scene->addInstance(child, {Affine3f::translate({-0.4f, 0.1f, 0.35f}), Affine3f::translate({0.1f, 0.1f, 0.35f}),
                                Affine3f::translate({0.1f, -0.4f, 0.35f})});
  for (const auto mode : {BuildOptions::EmbreeMode::Static, BuildOptions::EmbreeMode::StaticRobust}) {
    for (const float t : {0.0f, 0.3f, 0.5f, 1.0f}) {
      BuildOptions eo;
      eo.kind = AccelKind::Embree;
      eo.embreeMode = mode;
      eo.frozenTime = t;
      auto embree = Accel::build(*ps.scene, eo);
      BuildOptions bo;
      bo.kind = AccelKind::Brute;
      auto brute = Accel::build(*ps.scene, bo);
      size_t hits = 0, wrong = 0;
      for (int i = 0; i < 40 * 40; ++i) {
        Ray r;
        r.org = {-0.6f + 1.2f * float(i % 40) / 39.0f, -0.6f + 1.2f * float(i / 40) / 39.0f, 2.0f};
        r.dir = {0.01f, 0.02f, -1.0f};
        Ray atT = r;
        atT.time = t;
        r.time = 1.0f - t;  // a static scene: the ray's own time does not matter
        Hit a, b;
        const bool ha = embree->intersect(r, a), hb = brute->intersect(atT, b);
        hits += hb;
        wrong += ha != hb || (hb && std::fabs(a.t - b.t) > 1e-4f);
      }
      EXPECT_GT(hits, 200u);
      if (mode == BuildOptions::EmbreeMode::StaticRobust)
        EXPECT_EQ(wrong, 0u) << "time " << t << ": the robust static BVH is watertight";
      else
        EXPECT_LE(wrong, 3u) << "time " << t << ": rays slip through shared edges in Embree's default flags at most";
    }
  }
}
