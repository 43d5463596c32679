// Embree agreement that can fail: Embree and brute on the cases the plain
// comparisons leave out (segment scenes, segments exactly at step times,
// instances with mixed keys, the ends of partial time ranges). Where they
// differ, the float64 reference decides: brute wrong fails the test, Embree
// wrong is counted, listed and printed (docs/robustness.md has the figures).
#include <gtest/gtest.h>

#ifndef MBRT_HAVE_EMBREE

TEST(EmbreeReference, NotBuiltIn) { GTEST_SKIP() << "mbrt was built without Embree (MBRT_WITH_EMBREE=OFF)"; }

#else

#include <embree3/rtcore.h>

#include <cstdio>

#include "mixed_scene.h"
#include "reference_check.h"
#include "test_util.h"

using namespace mbrt;

namespace {

// Settles `rays` on `ps` and reports; Embree's count is informational, brute
// must never be the one the reference finds wrong.
void settleAndReport(const ProceduralScene& ps, const std::vector<Ray>& rays, const std::string& what,
                     float tolerance = 2e-4f) {
  const ref::Reference reference(*ps.scene);
  auto brute = test::buildKind(*ps.scene, AccelKind::Brute);
  auto embree = test::buildKind(*ps.scene, AccelKind::Embree);
  // Brute on every ray, not only where they differ.
  const ref::RefReport b = test::judgeWithReference(reference, *brute, rays);
  EXPECT_EQ(b.wrong + b.anyWrong, 0u) << what << ": " << b.firstFailure;
  const test::Settlement s = test::settleWithReference(reference, *brute, *embree, rays, tolerance, what);
  EXPECT_EQ(s.bruteWrong, 0u) << what;
  EXPECT_GT(b.hits, rays.size() / 5) << what << ": too few hits to mean anything";
  std::printf("embree vs brute, %-26s %6zu rays: differ on %4zu, embree wrong on %4zu\n", what.c_str(), rays.size(),
              s.differing, s.peerWrong);
  for (size_t i = 0; i < std::min<size_t>(3, s.listed.size()); ++i) std::printf("  %s\n", s.listed[i].c_str());
  ::testing::Test::RecordProperty("embree_wrong", std::to_string(s.peerWrong));
}

TEST(EmbreeReference, HairAndDemo) {
  for (const char* name : {"hair", "demo", "hairball", "ribbons"}) {
    const std::string n = name;
    const ProceduralScene ps = makeProceduralScene(name, n == "demo" ? 0.3 : n == "ribbons" ? 0.1 : 0.003, 5);
    // oracleRays includes rays at 0, 1 and every step time.
    settleAndReport(ps, test::oracleRays(ps, test::scaled(6000, 300), test::scaled(40, 4), 31), name);
  }
}

// Round segments of varying radii, with a third of the rays exactly at step
// times (0, 1/2, 1 for three steps).
TEST(EmbreeReference, SegmentsAtExactStepTimes) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto scene = std::make_shared<Scene>();
  std::vector<Segment> segs;
  std::vector<std::vector<Vec3f>> steps(3);
  std::vector<float> radii;
  for (uint32_t strand = 0; strand < 40; ++strand) {
    Vec3f p{u(rng), u(rng), u(rng)};
    const Vec3f move = Vec3f{u(rng), u(rng), u(rng)} * 0.2f;
    const uint32_t first = uint32_t(radii.size());
    for (uint32_t j = 0; j < 6; ++j) {
      for (uint32_t k = 0; k < 3; ++k) steps[k].push_back(p + move * (0.5f * float(k)));
      radii.push_back(0.02f + 0.03f * std::fabs(u(rng)));
      p += Vec3f{u(rng), u(rng), u(rng)} * 0.15f;
      if (j > 0) segs.push_back({first + j - 1, first + j});
    }
  }
  scene->addSegments(segs, steps, radii);
  ProceduralScene ps;
  ps.scene = scene;
  ps.camera = frameBox(Box3f(Vec3f(-1.2f), Vec3f(1.2f)));
  std::vector<Ray> rays = test::oracleRays(ps, test::scaled(3000, 300), 0, 41);
  for (float t : {0.0f, 0.5f, 1.0f})
    for (const Ray& r : test::oracleRays(ps, test::scaled(1000, 100), 0, 43 + uint64_t(t * 4), t)) rays.push_back(r);
  settleAndReport(ps, rays, "segments at step times");
}

// The mixed scene (meshes of 1..5 steps, partial ranges, segments,
// instances) at one instance level, which is what Embree nests; rays at
// random times, every step time, and around every partial range end.
TEST(EmbreeReference, MixedInstancesAndPartialRangeEnds) {
  const ProceduralScene nested = test::mixedScene(2);
  if (RTC_MAX_INSTANCE_LEVEL_COUNT < 2) {
    EXPECT_THROW(test::buildKind(*nested.scene, AccelKind::Embree), Error) << "two levels with a one-level Embree";
  } else {
    settleAndReport(nested, test::oracleRays(nested, test::scaled(4000, 300), test::scaled(20, 2), 51),
                    "mixed, nested");
  }
  const ProceduralScene ps = test::mixedScene(1);
  settleAndReport(ps, test::oracleRays(ps, test::scaled(4000, 300), test::scaled(20, 2), 53), "mixed");
  settleAndReport(ps, test::rangeEndRays(ps, test::scaled(200, 20), 55), "mixed, at range ends");
}

}  // namespace

#endif
