// Every structure agrees with the brute-force oracle on every suite scene,
// at random times and at times 0, 1 and every step boundary, for closest and
// any hit. `frozen` is checked only at its build time.
#include <gtest/gtest.h>

#include "mixed_scene.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

struct Case {
  std::string scene;
  AccelKind kind;
};

// Test listings (and CTest names) print "crowd / stbvh", not the bytes.
void PrintTo(const Case& c, std::ostream* os) { *os << c.scene << " / " << toString(c.kind); }

std::vector<Case> allCases() {
  std::vector<Case> cases;
  for (const std::string& scene : proceduralSceneNames())
    for (AccelKind kind : availableAccelKinds())
      // Embree's round linear curves are cones whose cross-section radius
      // varies linearly, not the hull of the end spheres that mbrt (and the
      // issue) define: scenes with segments differ slightly, so Embree is
      // compared on the triangle scenes here and on segments of equal radii
      // in test_embree.cpp. On `ribbons` (thin ribbons whose edges the
      // rays graze) Embree's own test misses hits that brute finds: it is
      // judged against the float64 reference in test_embree_reference.cpp.
      if (kind != AccelKind::Brute &&
          !(kind == AccelKind::Embree && (scene == "hair" || scene == "demo" || scene == "ribbons")))
        cases.push_back({scene, kind});
  return cases;
}

class Oracle : public ::testing::TestWithParam<Case> {};

// Small sizes: a few thousand primitives, so brute stays fast.
double testSize(const std::string& scene) {
  if (scene == "crowd") return 0.004;
  if (scene == "demo") return 1.0;
  if (scene == "slide" || scene == "ribbons") return 0.1;  // 2k triangles
  return 0.006;
}

TEST_P(Oracle, AgreesWithBruteForce) {
  const Case& c = GetParam();
  const ProceduralScene ps = makeProceduralScene(c.scene, testSize(c.scene), 5);
  BuildOptions bo;
  bo.kind = AccelKind::Brute;
  auto oracle = Accel::build(*ps.scene, bo);
  for (int branching : {2, 8}) {
    if (branching == 2 && c.kind != AccelKind::BvhInterp) continue;
    BuildOptions to;
    to.kind = c.kind;
    to.branching = branching;
    std::vector<Ray> rays;
    if (c.kind == AccelKind::Frozen) {
      for (float t : {0.0f, 0.5f, 1.0f}) {
        to.frozenTime = t;
        auto tested = Accel::build(*ps.scene, to);
                const std::vector<Ray> atT = test::oracleRays(ps, 1500, 0, uint64_t(t * 100) + 1, t);
        const auto rep = test::compareWithOracle(*oracle, *tested, atT);
        EXPECT_EQ(rep.wrong, 0u) << c.scene << " frozen@" << t << ": " << rep.firstFailure;
        EXPECT_EQ(rep.anyWrong, 0u) << c.scene << " frozen@" << t;
        EXPECT_GT(rep.hits, rep.rays / 4) << "too few hits to mean anything";
      }
      continue;
    }
    auto tested = Accel::build(*ps.scene, to);
    rays = test::oracleRays(ps, 3000, 60, 7);
    if (c.kind == AccelKind::Embree) {
      // Embree treats the ends of a partial time range with a small slack
      // (docs/design.md): compare away from them.
      std::vector<float> ends;
      for (uint32_t id = 0; id < ps.scene->numGeometries(); ++id) {
        const TimeRange r = ps.scene->geometry(id).timeRange();
        if (r.lo > 0.0f) ends.push_back(r.lo);
        if (r.hi < 1.0f) ends.push_back(r.hi);
      }
      std::erase_if(rays, [&](const Ray& ray) {
        return std::any_of(ends.begin(), ends.end(), [&](float e) { return std::fabs(ray.time - e) < 1e-3f; });
      });
    }
    const auto rep =
        test::compareWithOracle(*oracle, *tested, rays, c.kind == AccelKind::Embree ? 2e-4f : 1e-5f);
    EXPECT_EQ(rep.wrong, 0u) << c.scene << " " << toString(c.kind) << " width " << branching << ": "
                             << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << c.scene << " " << toString(c.kind) << " width " << branching;
    EXPECT_GT(rep.hits, rep.rays / 4) << "too few hits to mean anything";
    RecordProperty("ties", std::to_string(rep.ties));
  }
}

std::string caseName(const ::testing::TestParamInfo<Case>& info) {
  std::string n = info.param.scene + "_" + std::string(toString(info.param.kind));
  for (char& ch : n)
    if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
  return n;
}

INSTANTIATE_TEST_SUITE_P(Suite, Oracle, ::testing::ValuesIn(allCases()), caseName);

}  // namespace

namespace {

TEST(OracleMixed, EveryKindAgreesOnMeshesSegmentsAndNestedInstances) {
  const ProceduralScene ps = test::mixedScene();
  BuildOptions bo;
  bo.kind = AccelKind::Brute;
  auto oracle = Accel::build(*ps.scene, bo);
  const std::vector<Ray> rays = test::oracleRays(ps, 4000, 40, 3);
  const test::OracleAnswers expected = test::oracleAnswers(*oracle, rays);  // once for the 21 structures
  for (AccelKind kind : availableAccelKinds()) {
    // Embree has its own test (its time-range slack needs care at range ends).
    if (kind == AccelKind::Brute || kind == AccelKind::Frozen || kind == AccelKind::Embree) continue;
    for (int branching : {2, 4, 8}) {
      BuildOptions to;
      to.kind = kind;
      to.branching = branching;
      auto tested = Accel::build(*ps.scene, to);
      const auto rep = test::compareWithOracleHits(expected, *tested, rays);
      EXPECT_EQ(rep.wrong, 0u) << toString(kind) << " width " << branching << ": " << rep.firstFailure;
      EXPECT_EQ(rep.anyWrong, 0u) << toString(kind) << " width " << branching;
      EXPECT_GT(rep.hits, rep.rays / 5);
    }
  }
}

}  // namespace
