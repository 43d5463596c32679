// Every structure agrees with the brute-force oracle on every suite scene,
// at random times and at times 0, 1 and every step boundary, for closest and
// any hit. `frozen` is checked only at its build time.
#include <gtest/gtest.h>

#include "oracle.h"

using namespace mbrt;

namespace {

struct Case {
  std::string scene;
  AccelKind kind;
};

std::vector<Case> allCases() {
  std::vector<Case> cases;
  for (const std::string& scene : proceduralSceneNames())
    for (AccelKind kind : availableAccelKinds())
      if (kind != AccelKind::Brute) cases.push_back({scene, kind});
  return cases;
}

class Oracle : public ::testing::TestWithParam<Case> {};

// Small sizes: a few thousand primitives, so brute stays fast.
double testSize(const std::string& scene) {
  if (scene == "crowd") return 0.004;
  if (scene == "demo") return 1.0;
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
        rays = test::oracleRays(ps, 0, 0, 9);
        std::vector<Ray> atT = test::oracleRays(ps, 1500, 0, uint64_t(t * 100) + 1);
        for (Ray& r : atT) r.time = t;
        const auto rep = test::compareWithOracle(*oracle, *tested, atT);
        EXPECT_EQ(rep.wrong, 0u) << c.scene << " frozen@" << t << ": " << rep.firstFailure;
        EXPECT_EQ(rep.anyWrong, 0u) << c.scene << " frozen@" << t;
        EXPECT_GT(rep.hits, rep.rays / 20) << "too few hits to mean anything";
      }
      continue;
    }
    auto tested = Accel::build(*ps.scene, to);
    rays = test::oracleRays(ps, 3000, 60, 7);
    const auto rep = test::compareWithOracle(*oracle, *tested, rays);
    EXPECT_EQ(rep.wrong, 0u) << c.scene << " " << toString(c.kind) << " width " << branching << ": "
                             << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << c.scene << " " << toString(c.kind) << " width " << branching;
    EXPECT_GT(rep.hits, rep.rays / 20) << "too few hits to mean anything";
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
