// `auto`'s choices: the whole scene as one object where the decomposition
// would cost more per ray (and agreement with brute then), the decomposition
// where instances pay, the cost model's cache factor and sample, and the
// memory budget charged for the kept trial build only.
#include <gtest/gtest.h>

#include "auto/ray_cost.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

// The cost model's choices: without the measured confirmation, whose
// timing would make them depend on the machine (test_auto_trace.cpp tests
// it with injected measurements).
std::unique_ptr<Accel> build(const Scene& scene, AccelKind kind, size_t budget = 0) {
  BuildOptions o;
  o.kind = kind;
  o.memoryBudget = budget;
  o.autoConfirmByTrace = false;
  return Accel::build(scene, o);
}

// `tested` agrees with brute on the oracle's rays of `ps` (closest and any
// hit), which hit often enough to mean something.
void expectAgreesWithBrute(const ProceduralScene& ps, const Accel& tested, const std::string& what) {
  auto oracle = build(*ps.scene, AccelKind::Brute);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(2000, 300), test::scaled(30, 5), 7);
  const auto rep = test::compareWithOracle(*oracle, tested, rays);
  EXPECT_EQ(rep.wrong, 0u) << what << ": " << rep.firstFailure;
  EXPECT_EQ(rep.anyWrong, 0u) << what;
  EXPECT_GT(rep.hits, rep.rays / 10) << what;
}

// The demo: few objects in a small scene, where one tree over the whole
// scene beats three overlapping ones under a top level (measured: the
// decomposition takes 1.08x its thread time per ray, docs/performance.md,
// "Instance entries priced by time").
TEST(AutoChoice, FewObjectsThatGainNothingAreBuiltAsOneObject) {
  const ProceduralScene ps = makeProceduralScene("demo", 0.05, 3);
  auto tested = build(*ps.scene, AccelKind::Auto);
  const AccelStats s = tested->stats();
  EXPECT_NE(s.objects.find("the whole scene as one object"), std::string::npos) << s.objects;
  expectAgreesWithBrute(ps, *tested, "demo");
}

// One rigidly translating mesh: its linear bounds are exact already, yet a
// static tree under one instance costs less per ray (a static node and a
// block at one time read less than their motion counterparts, and the
// entry's transform stays in the caches: 0.66x the thread time per ray of
// the mesh's own `bvh-interp` tree at size 1, 0.84x at 0.05) at a quarter
// of its memory. The flat trial runs and keeps the decomposition; hits
// agree with brute.
TEST(AutoChoice, ARigidlyTranslatingMeshBecomesAnInstance) {
  for (double size : {0.05, 0.2}) {
    const ProceduralScene ps = makeProceduralScene("translate", size, 3);
    auto tested = build(*ps.scene, AccelKind::Auto);
    const AccelStats s = tested->stats();
    EXPECT_NE(s.objects.find("kept the decomposition"), std::string::npos) << size << ": " << s.objects;
    EXPECT_NE(s.objects.find(": rigid,"), std::string::npos) << size << ": " << s.objects;
    EXPECT_NE(s.objects.find("kind frozen"), std::string::npos) << size << ": " << s.objects;
    expectAgreesWithBrute(ps, *tested, "translate " + std::to_string(size));
  }
}

// Many rigid objects in a large scene: the decomposition is kept without a
// flat trial (crowd at 0.2: 90,000 triangles, above the flat trial's
// 65,536).
TEST(AutoChoice, ManyRigidObjectsInALargeSceneStayInstances) {
  const ProceduralScene ps = makeProceduralScene("crowd", 0.2, 3);
  ASSERT_GT(ps.scene->numPrimitives(), 65536u);
  const AccelStats s = build(*ps.scene, AccelKind::Auto)->stats();
  EXPECT_NE(s.objects.find(": rigid,"), std::string::npos) << s.objects;
  EXPECT_EQ(s.objects.find("whole scene as one object"), std::string::npos) << s.objects;
}

// A small scene of many rigid objects (crowd at 0.02: 80-triangle objects)
// gets the flat trial whatever its number of objects: the decomposition
// and the whole scene as one object are both priced, and the choice agrees
// with brute. There the two are within the model's error (101 frozen
// instances, or one `stbvh` whose leaves are gathered into blocks at 1.06x
// their thread time per ray, docs/performance.md), so either may be kept.
TEST(AutoChoice, SmallScenesOfManyObjectsGetTheFlatTrial) {
  const ProceduralScene ps = makeProceduralScene("crowd", 0.02, 3);
  ASSERT_LE(ps.scene->numPrimitives(), 65536u);
  ASSERT_GT(ps.scene->numGeometries(), 4u);
  auto tested = build(*ps.scene, AccelKind::Auto);
  const AccelStats s = tested->stats();
  const bool kept = s.objects.find("kept the decomposition (cost per sampled ray / memory: decomposed") !=
                    std::string::npos;
  const bool flat = s.objects.find("whole scene as one object, cheaper than its decomposition (cost per sampled "
                                   "ray / memory: decomposed") != std::string::npos;
  EXPECT_TRUE(kept || flat) << "no flat trial: " << s.objects;
  expectAgreesWithBrute(ps, *tested, "crowd 0.02");
}

// The cache factor: no weight up to 1 MB, a quarter more per doubling
// above; it multiplies the counted work, entries included. A test in a
// leaf block weighs a quarter of one made alone; frozen's counts 0.8.
TEST(AutoCost, CacheFactorWeighsBytesAboveOneMegabyte) {
  const detail::RayCostWeights w;
  EXPECT_DOUBLE_EQ(w.cacheFactor(0), 1.0);
  EXPECT_DOUBLE_EQ(w.cacheFactor(size_t(1) << 20), 1.0);
  EXPECT_DOUBLE_EQ(w.cacheFactor(size_t(2) << 20), 1.25);
  EXPECT_DOUBLE_EQ(w.cacheFactor(size_t(8) << 20), 1.75);
  // 4 of 5 MB in leaf blocks, weighed a quarter: 2 MB.
  EXPECT_DOUBLE_EQ(w.cacheFactor(size_t(5) << 20, size_t(4) << 20), 1.25);
  detail::RayCost c;
  c.nodes = 4;
  c.primitives = 6;
  c.blockPrimitives = 4;
  c.entries = 1;  // its instance test is one of the two tests made one at a time
  EXPECT_DOUBLE_EQ(c.work(w, AccelKind::Stbvh), 4 + 1 + 4 * 0.25 + 0.7);
  EXPECT_DOUBLE_EQ(c.work(w, AccelKind::Frozen), (4 + 1 + 4 * 0.25 + 0.7) * 0.8);
  EXPECT_DOUBLE_EQ(c.total(w, AccelKind::Stbvh, size_t(4) << 20, 0), (4 + 1 + 4 * 0.25 + 0.7) * 1.5);
  // Three of the nodes and the four block tests made inside a frozen object
  // weigh 0.8 of the same counts in the top level.
  c.frozenNodes = 3;
  c.frozenPrimitives = 4;
  c.frozenBlockPrimitives = 4;
  EXPECT_DOUBLE_EQ(c.work(w, AccelKind::Stbvh), 4 + 1 + 4 * 0.25 + 0.7 - 0.2 * (3 + 4 * 0.25));
}

// A segment's test weighs 3.7 triangle tests: an object's tests made one
// at a time are priced by its mix (one triangle and three segments: 3.025);
// a scene of triangles keeps 1, as does an empty one.
TEST(AutoCost, SegmentTestsWeighByTheSceneMix) {
  Scene mixed;
  mixed.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  mixed.addSegments({{0, 1}, {1, 2}, {2, 3}},
                    std::vector<std::vector<Vec3f>>{{{0, 0, 1}, {1, 0, 1}, {2, 0, 1}, {3, 0, 1}}},
                    std::vector<float>(4, 0.1f));
  const detail::RayCostWeights w = detail::weightsFor(mixed);
  EXPECT_DOUBLE_EQ(w.primitive, (1 + 3 * 3.7) / 4);
  EXPECT_DOUBLE_EQ(w.blockPrimitive, 0.25) << "blocks hold triangles only";
  Scene triangles;
  triangles.addTriangleMesh({{0, 1, 2}}, std::vector<std::vector<Vec3f>>{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}});
  EXPECT_DOUBLE_EQ(detail::weightsFor(triangles).primitive, 1.0);
  EXPECT_DOUBLE_EQ(detail::weightsFor(Scene()).primitive, 1.0);
}

// The sample's second half: diffuse bounces from the first half's hits,
// one per sampled ray, cycling through the hits; off the surface on the
// side the ray came from, in that hemisphere, at the hitting ray's time.
TEST(AutoCost, BouncesLeaveTheHitSurfaceOnTheIncomingSide) {
  std::vector<detail::RayQuery> rays(3);
  rays[0].setup({0, 0, 5}, {0, 0, -2}, 0, kInf, 0.25f, ~0u);  // hits z = 1 at t = 2
  rays[1].setup({0, 5, 0}, {0, -1, 0}, 0, kInf, 0.5f, ~0u);   // misses
  rays[2].setup({0, 0, -5}, {0, 0, 1}, 0, kInf, 0.75f, ~0u);  // hits z = -1 from below, t = 4
  std::vector<Hit> hits(3);
  hits[0].t = 2;
  hits[0].Ng = {0, 0, -1};  // facing away from the ray: turned towards it
  hits[0].geomID = 0;
  hits[2].t = 4;
  hits[2].Ng = {0, 0, -3};
  hits[2].geomID = 0;
  const std::vector<detail::RayQuery> b = detail::bounceRays(rays, hits);
  ASSERT_EQ(b.size(), rays.size());
  for (size_t j = 0; j < b.size(); ++j) {
    const bool first = j % 2 == 0;  // cycles through the two hits
    EXPECT_EQ(b[j].time, first ? 0.25f : 0.75f);
    EXPECT_NEAR(b[j].org.z, first ? 1.0f : -1.0f, 1e-2f);
    EXPECT_GT(first ? b[j].org.z - 1.0f : -1.0f - b[j].org.z, 0.0f) << "off the surface, on the ray's side";
    EXPECT_GT(first ? b[j].dir.z : -b[j].dir.z, 0.0f) << "into the incoming side's hemisphere";
    EXPECT_NEAR(length(b[j].dir), 1.0f, 1e-5f);
  }
  EXPECT_TRUE(detail::bounceRays(rays, std::vector<Hit>(3)).empty()) << "no hits, no bounces";
}

// A hit on a huge triangle (its normal's length overflows a float) still
// gives valid bounces, and none the API would refuse.
TEST(AutoCost, BouncesFromHugeTrianglesAreValidRays) {
  std::vector<detail::RayQuery> rays(1);
  rays[0].setup({0.2f, 0.2f, -1e16f}, {0, 0, 1}, 0, kInf, 0.5f, ~0u);
  std::vector<Hit> hits(1);
  hits[0].t = 1e16f;
  hits[0].Ng = {0, 0, 4e34f};  // (v1 - v0) x (v2 - v0) of edges ~2e17 long
  hits[0].geomID = 0;
  const std::vector<detail::RayQuery> b = detail::bounceRays(rays, hits);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_TRUE(isValidRay(Ray{b[0].org, b[0].tnear, b[0].dir, b[0].tfar, b[0].time, b[0].mask}));
  EXPECT_LT(b[0].dir.z, 0.0f) << "back towards the ray's side";
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
