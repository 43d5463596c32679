// The leaf test of the BVH kinds (scene/leaf_intersect.h: runs of one
// geometry) against the oracle's one-by-one test: a leaf of n references must give
// exactly the hit (bits of t, u, v, Ng, ids) and the final tfar that
// intersectPrimitive on each reference in order gives, for leaves of every
// size from 1 to 13, with ties (duplicate triangles), rays
// through shared edges and vertices (zero edge functions), coordinates
// beyond float's edge-function range, and through the stored triangles of
// `frozen` (FixedTimeTriangles) as through the vertex buffers.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "leaves/fixed_time_triangles.h"
#include "leaf_test_grid.h"
#include "scene/scene_context.h"
#include "test_util.h"

namespace mbrt {
namespace {

using namespace test;  // leaf_test_grid.h

void checkLeaves(const Scene& scene, float scale, bool stored) {
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  const std::vector<detail::PrimRef> all = ctx.primitives();
  std::mt19937 rng(11);
  const float fixedTime = 0.375f;
  const detail::FixedTimeTriangles fixed(ctx, fixedTime);
  int hits = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const uint32_t count = 1 + rng() % 13;
    const uint32_t first = rng() % uint32_t(all.size() - count);
    const detail::PrimRef* prims = all.data() + first;
    const float time = stored ? fixedTime : std::uniform_real_distribution<float>(0, 1)(rng);
    const uint32_t aim = all[first + rng() % count].primID;
    const detail::RayQuery ray = rayTowards(rng, ctx.geometry(0), aim, scale, time);
    detail::RayQuery one = ray, leaf = ray, anyRay = ray;
    Hit expected, got;
    bool found = false, occluded = false;
    for (uint32_t i = 0; i < count; ++i) {
      found |= detail::intersectPrimitive(ctx, prims[i], one, expected);
      occluded = occluded || detail::occludedPrimitive(ctx, prims[i], ray);
    }
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(count) + " references";
    const bool viaLeaf = stored ? detail::intersectLeaf(ctx, prims, count, leaf, got, nullptr, nullptr, nullptr, fixed)
                                : detail::intersectLeaf(ctx, prims, count, leaf, got, nullptr);
    ASSERT_EQ(viaLeaf, found) << what;
    EXPECT_TRUE(sameBits(leaf.tfar, one.tfar)) << what;
    if (found) expectSameHit(got, expected, what);
    const bool anyLeaf = stored ? detail::occludedLeaf(ctx, prims, count, anyRay, nullptr, nullptr, fixed)
                                : detail::occludedLeaf(ctx, prims, count, anyRay);
    EXPECT_EQ(anyLeaf, occluded) << what;
    hits += found;
  }
  EXPECT_GT(hits, 2000);  // the rays aim at the leaf's triangles: most of them hit
}

TEST(LeafRuns, AgreeWithTheOneByOneTest) {
  for (uint32_t steps : {1u, 3u}) {
    Scene scene;
    addGrid(scene, 6, 1.0f, 0.0f, steps);
    checkLeaves(scene, 1.0f, false);
  }
}

TEST(LeafRuns, AgreeBeyondFloatEdgeFunctions) {
  Scene scene;
  addGrid(scene, 4, 1e13f, 0.5f, 2);  // edge functions and T overflow float: the double path
  checkLeaves(scene, 1e13f, false);
}

TEST(LeafRuns, StoredTrianglesAgreeWithTheVertexBuffers) {
  for (uint32_t steps : {1u, 4u}) {
    Scene scene;
    addGrid(scene, 6, 1.0f, 0.0f, steps);
    checkLeaves(scene, 1.0f, true);
  }
}

}  // namespace
}  // namespace mbrt
