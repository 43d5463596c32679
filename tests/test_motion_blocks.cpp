// The motion blocks of `bvh-interp` (leaves/motion_blocks.h) against the
// one-by-one test: leaves of one geometry of 1, 2 or 5 steps (one alive
// over part of the shutter), masks, at random and step times, the same hits
// bit for bit as intersectPrimitive on each reference and as the reference
// test; and the leaves that are not blocked (two geometries, a filter, a
// table not laid out in blocks).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "bvh/leaf_table.h"
#include "leaves/motion_blocks.h"
#include "scene/scene_context.h"
#include "leaf_test_grid.h"
#include "test_util.h"

namespace mbrt {
namespace {

using namespace test;  // leaf_test_grid.h

// Motion blocks: leaves of 1 to 13 references of one geometry, at random
// times, against intersectPrimitive one by one and intersectLeaf through
// the vertex buffers; geometries of 1, 2 and 5 steps, one alive over part
// of the shutter only, masks.
TEST(LeafBlocks, MotionBlocksAgreeWithTheOneByOneTest) {
  Scene scene;
  addMotionGrids(scene);
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  std::mt19937 rng(5);
  int hits = 0, blocked = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    const uint32_t geomID = rng() % scene.numGeometries();
    const Geometry& g = ctx.geometry(geomID);
    std::vector<detail::PrimRef> refs = drawLeaf(rng, g, geomID);
    const uint32_t count = uint32_t(refs.size());
    const detail::WideBvh<8, true> bvh = oneLeaf<true>(refs);
    const detail::MotionBlockLeaves mb(ctx, detail::leafTable(bvh));
    ASSERT_NE(mb.leafAt(0), nullptr);
    ASSERT_EQ(mb.blockCount(), (count + 3) / 4 * g.numSteps());
    float time = std::uniform_real_distribution<float>(0, 1)(rng);
    if (trial % 5 == 0) time = float(rng() % 5) / 4.0f;  // on a step, at the ends of the range
    const detail::PrimRef aim = bvh.prims[rng() % count];
    const float scale = geomID == 3 ? 1e13f : 1.0f;
    detail::RayQuery ray = rayTowards(rng, g, aim.primID, scale, g.timeRange().contains(time) ? time : 0.5f);
    ray.time = time;
    test::varyMaskAndTfar(rng, trial, ray);
    detail::RayQuery viaLeaf = ray, viaBlocks = ray, anyLeaf = ray, anyBlocks = ray;
    Hit leafHit, got;
    const test::OneByOne reference = test::oneByOne(ctx, std::span(bvh.prims).first(count), ray);
    const bool found = reference.found, occluded = reference.occluded;
    const Hit& expected = reference.hit;
    const detail::RayQuery& one = reference.ray;
    const detail::LeafBlockRay r(ray);
    const detail::LeafRefs leafRefs{bvh.prims.data(), count, 0};
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(count) + " references";
    ASSERT_EQ(detail::intersectLeaf(ctx, bvh.prims.data(), count, viaLeaf, leafHit, nullptr), found) << what;
    ASSERT_EQ((mb.test<false, false>(ctx, leafRefs, viaBlocks, r, &got, nullptr)), found) << what;
    EXPECT_TRUE(sameBits(viaBlocks.tfar, one.tfar)) << what;
    if (found) {
      expectSameHit(got, expected, what);
      expectSameHit(got, leafHit, what);
    }
    EXPECT_EQ((mb.test<true, false>(ctx, leafRefs, anyBlocks, r, nullptr, nullptr)), occluded) << what;
    EXPECT_EQ(detail::occludedLeaf(ctx, bvh.prims.data(), count, anyLeaf), occluded) << what;
    hits += found;
    blocked += g.numSteps() > 1;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(blocked, 3000);
}

// A motion leaf of two geometries, or of a geometry with a filter, is not
// blocked (its runs are tested as references, reference_leaves.h).
TEST(LeafBlocks, MixedOrFilteredMotionLeavesAreNotBlocked) {
  Scene scene;
  addGrid(scene, 2, 1.0f, 0.0f, 2, false);
  addGrid(scene, 2, 1.0f, 0.0f, 2, false);
  const uint32_t filtered = addGrid(scene, 2, 1.0f, 0.0f, 2, false);
  scene.setFilter(filtered, [](const FilterArgs&) { return true; });
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  const auto blocksOf = [&](const detail::WideBvh<8, true>& bvh) {
    return detail::MotionBlockLeaves(ctx, detail::leafTable(bvh));
  };
  EXPECT_TRUE(blocksOf(oneLeaf<true>({{0, 0}, {1, 1}})).empty());
  EXPECT_TRUE(blocksOf(oneLeaf<true>({{filtered, 0}, {filtered, 1}})).empty());
  const detail::MotionBlockLeaves plain = blocksOf(oneLeaf<true>({{1, 0}, {1, 1}, {1, 2}, {1, 3}, {1, 4}}));
  ASSERT_NE(plain.leafAt(0), nullptr);
  EXPECT_EQ(plain.blockCount(), 4u);  // 2 blocks x 2 steps
  // Leaves side by side: each blocked one found from its first reference,
  // the mixed one tested one by one.
  const detail::MotionBlockLeaves both =
      blocksOf(leavesOf<true>({{{1, 0}, {1, 1}, {1, 2}, {1, 3}, {1, 4}}, {{0, 0}, {1, 5}}, {{0, 6}}}));
  EXPECT_EQ(both.blockCount(), 6u);  // (2 + 1) blocks x 2 steps
  ASSERT_NE(both.leafAt(0), nullptr);
  EXPECT_EQ(both.leafAt(0)->first, 0u);
  EXPECT_EQ(both.leafAt(8), nullptr);
  ASSERT_NE(both.leafAt(12), nullptr);
  EXPECT_EQ(both.leafAt(12)->geomID, 0u);
  EXPECT_EQ(both.leafAt(12)->first, 4u);
  detail::WideBvh<8, true> unaligned = oneLeaf<true>({{1, 0}, {1, 1}, {1, 2}, {1, 3}});
  unaligned.nodes[0].count[1] = 2;
  unaligned.nodes[0].child[1] = 1;
  EXPECT_TRUE(blocksOf(unaligned).empty());
}

}  // namespace
}  // namespace mbrt
