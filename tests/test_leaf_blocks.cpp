// The triangle blocks of `frozen` (geometry/triangle_block.h,
// leaves/triangle_blocks.h) against the one-by-one test:
// intersectTriangleBlock lane by lane against intersectTriangle (bits of t,
// u, v), and a blocked leaf against intersectPrimitive on each reference in
// order and against the reference test (intersectLeaf): the same hit, bits
// of t, u, v, Ng and ids, the same final tfar, the same occlusion. The
// cases: shared edges and vertices (zero edge functions, the double path),
// degenerate triangles (a segment, a point), duplicate triangles (ties),
// coordinates beyond float's edge-function range, lanes left out of a
// block, geometry masks, filters (no blocks) and leaf sizes 1 to 13 around
// the block width. Then the trees: their leaves fill blocks, and they agree
// with brute force; and what the counters and the stats say of the blocks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "bvh/leaf_table.h"
#include "leaves/triangle_blocks.h"
#include "oracle.h"
#include "scene/scene_context.h"
#include "leaf_test_grid.h"
#include "test_util.h"

namespace mbrt {
namespace {

using namespace test;  // leaf_test_grid.h

// intersectTriangleBlock<4> lane by lane against intersectTriangle; the
// lanes it hands to the scalar test are those with an edge function
// exactly zero or T beyond float (counted: the cases occur).
TEST(LeafBlocks, BlockLanesAgreeWithTheScalarTest) {
  Scene scene;
  addGrid(scene, 6, 1.0f, 0.0f, 1, true);
  addGrid(scene, 3, 1e13f, 0.5f, 1, true);
  std::mt19937 rng(3);
  int hits = 0, scalarLanes = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    const bool large = trial % 2 != 0;
    const Geometry& g = scene.geometry(large ? 1 : 0);
    const uint32_t numTris = uint32_t(g.triangles().size());
    uint32_t prim[4];
    for (uint32_t& p : prim) p = rng() % numTris;
    if (trial % 5 == 0) prim[3] = prim[1];  // a tie inside the block
    detail::RayQuery ray = rayTowards(rng, g, prim[rng() % 4], large ? 1e13f : 1.0f, 0.0f);
    if (trial % 3 == 0) ray.tfar = std::uniform_real_distribution<float>(0.5f, 1.0f)(rng);
    if (trial % 7 == 0) ray.tnear = std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
    detail::TriangleBlock<4> block;
    Vec3f v[4][3];
    for (int lane = 0; lane < 4; ++lane) {
      const Triangle& tri = g.triangles()[prim[lane]];
      v[lane][0] = g.vertexAt(0.0f, tri.v0);
      v[lane][1] = g.vertexAt(0.0f, tri.v1);
      v[lane][2] = g.vertexAt(0.0f, tri.v2);
      block.set(lane, v[lane][0], v[lane][1], v[lane][2]);
      for (int k = 0; k < 3; ++k) ASSERT_TRUE(sameBits(block.vertex(k, lane).x, v[lane][k].x));
    }
    const uint32_t valid = trial % 4 == 0 ? 1u + rng() % 15u : 15u;
    detail::TriangleBlockResult<4> res;
    detail::intersectTriangleBlock(ray, block, valid, res);
    EXPECT_EQ((res.candidates | res.scalar) & ~valid, 0u);
    EXPECT_EQ(res.candidates & res.scalar, 0u);
    for (int lane = 0; lane < 4; ++lane) {
      if (!(valid >> lane & 1u)) continue;
      if (res.scalar >> lane & 1u) {
        ++scalarLanes;
        continue;
      }
      detail::TriangleHit expected, got;
      const bool hit = detail::intersectTriangle(ray, v[lane][0], v[lane][1], v[lane][2], expected);
      const std::string what = "trial " + std::to_string(trial) + " lane " + std::to_string(lane);
      ASSERT_EQ(res.candidates >> lane & 1u ? res.accept(lane, ray, got) : false, hit) << what;
      if (hit) {
        EXPECT_TRUE(sameBits(got.t, expected.t) && sameBits(got.u, expected.u) && sameBits(got.v, expected.v))
            << what;
      }
      hits += hit;
    }
  }
  EXPECT_GT(hits, 800);  // a quarter of the lanes aim elsewhere, some are degenerate
  EXPECT_GT(scalarLanes, 100);
}

// Leaves of 1 to 13 references drawn from the grids (several geometries
// in one leaf), rays with masks that leave out some geometries.
void checkBlockedLeaves(Scene& scene, float scale) {
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  const std::vector<detail::PrimRef> all = ctx.primitives();
  std::mt19937 rng(11);
  const float time = 0.375f;
  const detail::FixedTimeTriangles fixed(ctx, time);
  int hits = 0, masked = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const uint32_t count = 1 + rng() % 13;
    std::vector<detail::PrimRef> refs;
    const uint32_t first = rng() % uint32_t(all.size() - count);
    for (uint32_t i = 0; i < count; ++i)  // mostly neighbours (ties, shared edges), some anywhere
      refs.push_back(rng() % 4 == 0 ? all[rng() % all.size()] : all[first + i]);
    const detail::WideBvh<8, false> bvh = oneLeaf(refs);
    const detail::TriangleBlockLeaves blocks(ctx, detail::leafTable(bvh, time));
    ASSERT_NE(blocks.blocksOf(0), nullptr);
    ASSERT_EQ(blocks.blockCount(), (count + 3) / 4);
    const detail::PrimRef aim = bvh.prims[rng() % count];
    detail::RayQuery ray = rayTowards(rng, ctx.geometry(aim.geomID), aim.primID, scale, time);
    test::varyMaskAndTfar(rng, trial, ray);
    detail::RayQuery leaf = ray, blocked = ray, anyLeaf = ray, anyBlocked = ray;
    Hit viaLeaf, got;
    const test::OneByOne reference = test::oneByOne(ctx, std::span(bvh.prims).first(count), ray);
    const bool found = reference.found, occluded = reference.occluded;
    const Hit& expected = reference.hit;
    const detail::RayQuery& one = reference.ray;
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(count) + " references";
    const detail::LeafRefs leafRefs{bvh.prims.data(), count, 0};
    const detail::LeafBlockRay r(ray);
    ASSERT_EQ(detail::intersectLeaf(ctx, bvh.prims.data(), count, leaf, viaLeaf, nullptr, nullptr, nullptr, fixed),
              found);
    ASSERT_EQ((blocks.test<false, false>(ctx, leafRefs, blocked, r, &got, nullptr)), found) << what;
    EXPECT_TRUE(sameBits(blocked.tfar, one.tfar)) << what;
    EXPECT_TRUE(sameBits(blocked.tfar, leaf.tfar)) << what;
    if (found) {
      expectSameHit(got, expected, what);
      expectSameHit(got, viaLeaf, what);
    }
    EXPECT_EQ((blocks.test<true, false>(ctx, leafRefs, anyBlocked, r, nullptr, nullptr)), occluded) << what;
    EXPECT_EQ(detail::occludedLeaf(ctx, bvh.prims.data(), count, anyLeaf, nullptr, nullptr, fixed), occluded) << what;
    hits += found;
    masked += ray.mask != ~0u;
  }
  EXPECT_GT(hits, 800);  // the rays aim at the leaf's triangles; a quarter of the masks leave them out
  EXPECT_GT(masked, 2000);
}

TEST(LeafBlocks, BlockedLeavesAgreeWithTheOneByOneTest) {
  for (uint32_t steps : {1u, 3u}) {
    Scene scene;
    scene.setMask(addGrid(scene, 6, 1.0f, 0.0f, steps, true), 1u);
    scene.setMask(addGrid(scene, 6, 1.0f, 0.0f, steps, false), 2u);  // the same triangles: ties across geometries
    scene.setMask(addGrid(scene, 5, 1.0f, 0.25f, steps, true), 3u);
    checkBlockedLeaves(scene, 1.0f);
  }
}

TEST(LeafBlocks, BlockedLeavesAgreeBeyondFloatEdgeFunctions) {
  Scene scene;
  addGrid(scene, 4, 1e13f, 0.5f, 2, true);  // edge functions and T overflow float: the double path
  addGrid(scene, 4, 1e13f, 0.5f, 2, false);
  checkBlockedLeaves(scene, 1e13f);
}

// A leaf with a reference of a geometry with a filter is not blocked (its
// run takes the per-reference path); the others are.
TEST(LeafBlocks, LeavesWithFiltersAreNotBlocked) {
  Scene scene;
  addGrid(scene, 2, 1.0f, 0.0f, 1, false);
  const uint32_t filtered = addGrid(scene, 2, 1.0f, 0.0f, 1, false);
  scene.setFilter(filtered, [](const FilterArgs&) { return true; });
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  const auto blocksOf = [&](const detail::WideBvh<8, false>& bvh) {
    return detail::TriangleBlockLeaves(ctx, detail::leafTable(bvh, 0.0f));
  };
  EXPECT_TRUE(blocksOf(oneLeaf({{0, 0}, {0, 1}, {filtered, 0}})).empty());
  const detail::TriangleBlockLeaves plain = blocksOf(oneLeaf({{0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}}));
  ASSERT_NE(plain.blocksOf(0), nullptr);
  EXPECT_EQ(plain.blockCount(), 2u);
  // Beside a blocked leaf, a leaf with a filtered geometry is tested one by
  // one: its block is marked, the other leaf's blocks are found.
  const detail::TriangleBlockLeaves both =
      blocksOf(leavesOf({{{0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}}, {{0, 5}, {filtered, 0}}, {{0, 6}}}));
  ASSERT_EQ(both.blockCount(), 4u);
  ASSERT_NE(both.blocksOf(0), nullptr);
  EXPECT_EQ(both.blocksOf(0)[1].primID[0], 4u);
  EXPECT_EQ(both.blocksOf(8), nullptr);
  ASSERT_NE(both.blocksOf(12), nullptr);
  EXPECT_EQ(both.blocksOf(12)->primID[0], 6u);
  // A table whose leaves do not start at multiples of four gets no blocks.
  detail::WideBvh<8, false> unaligned = oneLeaf({{0, 0}, {0, 1}, {0, 2}, {0, 3}});
  unaligned.nodes[0].count[1] = 2;
  unaligned.nodes[0].child[1] = 1;
  EXPECT_TRUE(blocksOf(unaligned).empty());
}

// The trees whose SAH charges leaves per block keep leaves that fill
// blocks (per reference, the SAH and the lane filling leave ~1.1 per leaf),
// and `frozen` (at two times) and `bvh-interp` (at random and step times)
// on them agree with brute force.
TEST(LeafBlocks, BlockTreesFillBlocksAndAgreeWithBrute) {
  for (const char* name : {"translate", "deform", "hairball"}) {
    const ProceduralScene ps = makeProceduralScene(name, 0.02, 5);
    BuildOptions bo;
    bo.kind = AccelKind::Brute;
    auto oracle = Accel::build(*ps.scene, bo);
    for (float t : {0.0f, 0.5f}) {
      BuildOptions to;
      to.kind = AccelKind::Frozen;
      to.frozenTime = t;
      auto tested = Accel::build(*ps.scene, to);
      const AccelStats st = tested->stats();
      EXPECT_GT(double(st.references) / double(st.leafNodes), 2.0) << name;
      const auto rep = test::compareWithOracle(*oracle, *tested, test::oracleRays(ps, test::scaled(2000, 500), 0, 17, t));
      EXPECT_EQ(rep.wrong, 0u) << name << " frozen@" << t << ": " << rep.firstFailure;
      EXPECT_EQ(rep.anyWrong, 0u) << name << " frozen@" << t;
      EXPECT_GT(rep.hits, rep.rays / 4) << "too few hits to mean anything";
    }
    BuildOptions mo;
    mo.kind = AccelKind::BvhInterp;
    auto motion = Accel::build(*ps.scene, mo);
    const AccelStats st = motion->stats();
    EXPECT_GT(double(st.references) / double(st.leafNodes), 2.0) << name;
    const auto rep = test::compareWithOracle(*oracle, *motion, test::oracleRays(ps, test::scaled(2000, 500), test::scaled(20, 5), 19));
    EXPECT_EQ(rep.wrong, 0u) << name << " bvh-interp: " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << name << " bvh-interp";
    EXPECT_GT(rep.hits, rep.rays / 4) << "too few hits to mean anything";
  }
}

// The counters and the stats say what the leaf blocks hold and test:
// every leaf of `bvh-interp` over one triangle mesh is blocked, so all its
// primitive tests are block tests, and the blocks' bytes are a part of its
// bytes; `stbvh` keeps no blocks but gathers its leaves' runs of two or
// more triangles into blocks (leaves/gathered_runs.h): most of its
// tests are block tests, and no bytes are in blocks.
TEST(LeafBlocks, CountersAndStatsReportTheBlocks) {
  const ProceduralScene ps = makeProceduralScene("translate", 0.02, 5);
  const auto rays = test::oracleRays(ps, 500, 0, 23);
  for (AccelKind kind : {AccelKind::BvhInterp, AccelKind::Stbvh, AccelKind::Mbkd, AccelKind::FuzzyKd}) {
    BuildOptions o;
    o.kind = kind;
    auto accel = Accel::build(*ps.scene, o);
    TraversalCounters c;
    for (const Ray& r : rays) {
      Hit h;
      accel->intersect(r, h, c);
    }
    const AccelStats st = accel->stats();
    EXPECT_GT(c.primitiveTests, 0u);
    if (kind == AccelKind::BvhInterp) {
      EXPECT_EQ(c.blockPrimitiveTests, c.primitiveTests);
      EXPECT_GT(st.leafBlockBytes, 0u);
      EXPECT_LT(st.leafBlockBytes, st.bytes);
    } else if (kind == AccelKind::Stbvh) {
      EXPECT_GT(c.blockPrimitiveTests, c.primitiveTests / 2);
      EXPECT_LE(c.blockPrimitiveTests, c.primitiveTests);
      EXPECT_EQ(st.leafBlockBytes, 0u);
    } else {  // the kd kinds gather a leaf's surviving triangles (kd_leaf_batch.h)
      EXPECT_GT(c.blockPrimitiveTests, 0u) << toString(kind);
      EXPECT_LE(c.blockPrimitiveTests, c.primitiveTests) << toString(kind);
    }
  }
}

}  // namespace
}  // namespace mbrt
