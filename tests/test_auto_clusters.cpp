// `auto`'s near-rigid clusters (docs/auto.md, "Near-rigid clusters"): a
// bending tube is decomposed into clusters of coherent affine motion, each
// traced by a static tree over its fuzzy boxes in its own frame with
// world-space leaves (bvh/kinds/cluster_bvh.h); hits agree with brute at
// random times and at every step time, for closest and any hit, with masks
// and the mesh's partial time range; the top level's boxes of a cluster hold
// its triangles at sampled times.
#include <gtest/gtest.h>

#include <set>

#include "auto/auto_plan.h"
#include "auto/part_bounds.h"
#include "auto_scene.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

TEST(AutoClusters, ABendingTubeIsDecomposedIntoClusters) {
  const ProceduralScene ps = test::bendingTubeScene();
  const detail::AutoPlan plan = detail::planDecomposition(*ps.scene, 1e-5);
  EXPECT_TRUE(plan.rigid.empty()) << "no single key fits a bending tube";
  ASSERT_GE(plan.clusters.size(), 2u) << "the two halves move apart";
  std::multiset<uint32_t> seen;
  for (const auto& c : plan.clusters) {
    EXPECT_EQ(c.geomID, 0u);
    EXPECT_GE(c.prims.size(), detail::kMinClusterTriangles);
    EXPECT_EQ(c.maps.size(), ps.scene->geometry(0).numSteps());
    EXPECT_TRUE(std::is_sorted(c.prims.begin(), c.prims.end()));
    seen.insert(c.prims.begin(), c.prims.end());
  }
  for (const auto& w : plan.world) {
    ASSERT_EQ(w.geomID, 0u);
    ASSERT_FALSE(w.prims.empty()) << "the world part is the triangles of no cluster";
    seen.insert(w.prims.begin(), w.prims.end());
  }
  const uint32_t n = ps.scene->geometry(0).numPrimitives();
  ASSERT_EQ(seen.size(), n) << "every triangle in exactly one part";
  for (uint32_t p = 0; p < n; ++p) EXPECT_EQ(seen.count(p), 1u) << p;
}

TEST(AutoClusters, TopLevelBoxesHoldTheClusterAtSampledTimes) {
  const ProceduralScene ps = test::bendingTubeScene();
  const Geometry& g = ps.scene->geometry(0);
  const detail::AutoPlan plan = detail::planDecomposition(*ps.scene, 1e-5);
  ASSERT_FALSE(plan.clusters.empty());
  for (const auto& c : plan.clusters) {
    const std::vector<Box3f> boxes = detail::trianglesKeyBoxes(g, c.prims, 0.0f);
    ASSERT_EQ(boxes.size(), g.numSteps());
    for (int i = 0; i <= 200; ++i) {
      const float t = g.timeRange().lo + (g.timeRange().hi - g.timeRange().lo) * float(i) / 200.0f;
      uint32_t s;
      float f;
      g.segmentAt(t, s, f);
      const Box3f b = lerp(boxes[s], boxes[s + 1], f);
      for (uint32_t p : c.prims)
        for (uint32_t v : {g.triangles()[p].v0, g.triangles()[p].v1, g.triangles()[p].v2}) {
          const Vec3f x = g.vertexAt(t, v);
          ASSERT_TRUE(x.x >= b.lower.x && x.y >= b.lower.y && x.z >= b.lower.z && x.x <= b.upper.x &&
                      x.y <= b.upper.y && x.z <= b.upper.z)
              << "time " << t << " vertex " << v;
        }
    }
  }
}

TEST(AutoClusters, AgreeWithBruteAtEveryTime) {
  const ProceduralScene ps = test::bendingTubeScene();
  auto oracle = test::buildBrute(*ps.scene);
  const std::vector<Ray> rays = test::oracleRays(ps, test::scaled(3000, 400), test::scaled(60, 10), 17);
  for (int branching : {2, 4, 8}) {
    BuildOptions o;
    o.kind = AccelKind::Auto;
    o.branching = branching;
    o.autoLeafKind = AccelKind::BvhInterp;  // the decomposition kept: no flat trial
    auto tested = Accel::build(*ps.scene, o);
    const AccelStats s = tested->stats();
    EXPECT_NE(s.objects.find("near-rigid cluster"), std::string::npos) << s.objects;
    const auto rep = test::compareWithOracle(*oracle, *tested, rays);
    EXPECT_EQ(rep.wrong, 0u) << "branching " << branching << ": " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << "branching " << branching;
    EXPECT_GT(rep.hits, rep.rays / 10);
    const auto maskedRep = test::compareMasked(*oracle, *tested, rays, 2u);
    EXPECT_EQ(maskedRep.hits, 0u);
    EXPECT_EQ(maskedRep.wrong + maskedRep.anyWrong, 0u) << maskedRep.firstFailure;
  }
  // As auto chooses (the flat trial may keep the tube whole): still exact.
  BuildOptions o;
  o.kind = AccelKind::Auto;
  auto chosen = Accel::build(*ps.scene, o);
  const auto rep = test::compareWithOracle(*oracle, *chosen, rays);
  EXPECT_EQ(rep.wrong + rep.anyWrong, 0u) << rep.firstFailure;
}

}  // namespace
