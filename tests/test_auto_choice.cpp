// `auto`'s choices: the whole scene as one object where the decomposition
// would cost more per ray (and agreement with brute then), the decomposition
// where instances pay, and the memory budget charged for the kept trial
// build only.
#include <gtest/gtest.h>

#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

std::unique_ptr<Accel> build(const Scene& scene, AccelKind kind, size_t budget = 0) {
  BuildOptions o;
  o.kind = kind;
  o.memoryBudget = budget;
  return Accel::build(scene, o);
}

// One rigidly translating mesh: an instance would only add a ray transform
// to linear bounds that are exact already; the demo: few objects in a
// small scene, where one stbvh-like tree beats three overlapping ones.
TEST(AutoChoice, FewObjectsThatGainNothingAreBuiltAsOneObject) {
  for (const char* name : {"translate", "demo"}) {
    const ProceduralScene ps = makeProceduralScene(name, 0.05, 3);
    auto tested = build(*ps.scene, AccelKind::Auto);
    const AccelStats s = tested->stats();
    EXPECT_NE(s.objects.find("the whole scene as one object"), std::string::npos) << name << ": " << s.objects;
    auto oracle = build(*ps.scene, AccelKind::Brute);
    const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2000, 300), test::scaled(30, 5), 7);
    const auto rep = test::compareWithOracle(*oracle, *tested, rays);
    EXPECT_EQ(rep.wrong, 0u) << name << ": " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << name;
    EXPECT_GT(rep.hits, rep.rays / 10) << name;
  }
}

// Many rigid objects: the decomposition is kept without a flat trial.
TEST(AutoChoice, ManyRigidObjectsStayInstances) {
  const ProceduralScene ps = makeProceduralScene("crowd", 0.05, 3);
  const AccelStats s = build(*ps.scene, AccelKind::Auto)->stats();
  EXPECT_NE(s.objects.find(": rigid,"), std::string::npos) << s.objects;
  EXPECT_EQ(s.objects.find("the whole scene as one object"), std::string::npos) << s.objects;
}

// A deforming scene gets trial builds of four kinds. Only the kept one is
// charged: a budget a quarter above the largest single trial's peak
// suffices, though the trials' structures held together, with the largest
// build's scratch, need more; a budget below every trial fails with a clear
// error.
TEST(AutoBudget, OnlyTheKeptTrialBuildIsCharged) {
  const ProceduralScene ps = makeProceduralScene("deform", 0.02, 3);
  const AccelStats unlimited = build(*ps.scene, AccelKind::Auto)->stats();
  ASSERT_NE(unlimited.objects.find("trial builds"), std::string::npos) << unlimited.objects;
  size_t sumBytes = 0, maxPeak = 0, bytesOfMaxPeak = 0;
  for (AccelKind k : {AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Stbvh, AccelKind::Msbvh}) {
    const AccelStats s = build(*ps.scene, k)->stats();
    sumBytes += s.bytes;
    if (s.peakBuildBytes > maxPeak) maxPeak = s.peakBuildBytes, bytesOfMaxPeak = s.bytes;
  }
  const size_t budget = maxPeak + maxPeak / 4;
  EXPECT_GT(sumBytes - bytesOfMaxPeak + maxPeak, budget) << "the trials must not fit together";
  const AccelStats fitted = build(*ps.scene, AccelKind::Auto, budget)->stats();
  EXPECT_EQ(fitted.bytes, unlimited.bytes);
  EXPECT_EQ(fitted.objects, unlimited.objects);
  EXPECT_LE(fitted.peakBuildBytes, budget);
  try {
    build(*ps.scene, AccelKind::Auto, 64 << 10);
    ADD_FAILURE() << "a budget of 64 KiB was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("memory budget"), std::string::npos) << e.what();
  }
}

}  // namespace
