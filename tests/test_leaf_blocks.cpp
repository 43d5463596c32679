// The leaf blocks of `frozen` and `bvh-interp` (geometry/triangle_block.h,
// bvh/leaf_blocks.h, bvh/motion_leaf_blocks.h) against the one-by-one
// test: intersectTriangleBlock lane by lane against intersectTriangle (bits
// of t, u, v), and a blocked leaf against intersectPrimitive on each
// reference in order and against the leaf's own path (intersectLeaf): the
// same hit, bits of t, u, v, Ng and ids, the same final tfar, the same
// occlusion. The cases: shared edges and vertices (zero edge functions,
// the double path), degenerate triangles (a segment, a point), duplicate
// triangles (ties), coordinates beyond float's edge-function range, lanes
// left out of a block, geometry masks, time ranges and steps (motion
// blocks), filters (no blocks) and leaf sizes 1 to 13 around the block
// width. Then the trees: their leaves fill blocks, and they agree with
// brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "bvh/leaf_blocks.h"
#include "bvh/motion_leaf_blocks.h"
#include "kd/kd_leaf_batch.h"
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

// Leaves as the builder stores them (each sorted by geometry, then
// primitive) in a one-node tree, laid out as layOut does for blocks: each
// leaf starts at a multiple of four in the table, the gaps repeating its
// last reference.
template <bool Motion = false>
detail::WideBvh<8, Motion> leavesOf(std::vector<std::vector<detail::PrimRef>> leaves) {
  detail::WideBvh<8, Motion> bvh;
  bvh.nodes.resize(1);
  bvh.nodes[0].clear();
  for (size_t lane = 0; lane < leaves.size(); ++lane) {
    std::vector<detail::PrimRef>& refs = leaves[lane];
    std::sort(refs.begin(), refs.end(), [](detail::PrimRef a, detail::PrimRef b) {
      return a.geomID != b.geomID ? a.geomID < b.geomID : a.primID < b.primID;
    });
    bvh.nodes[0].count[lane] = uint8_t(refs.size());
    bvh.nodes[0].child[lane] = uint32_t(bvh.prims.size());
    bvh.prims.insert(bvh.prims.end(), refs.begin(), refs.end());
    while (bvh.prims.size() % 4 != 0) {
      bvh.prims.push_back(refs.back());
      ++bvh.paddingRefs;
    }
  }
  return bvh;
}
template <bool Motion = false>
detail::WideBvh<8, Motion> oneLeaf(std::vector<detail::PrimRef> refs) {
  return leavesOf<Motion>({std::move(refs)});
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
    const detail::TriangleLeafBlocks blocks(ctx, bvh, fixed, time);
    const detail::TriangleLeafBlock* b = blocks.of(0);
    ASSERT_NE(b, nullptr);
    ASSERT_EQ(blocks.blocks.size(), (count + 3) / 4);
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
    ASSERT_EQ(detail::intersectLeaf<true>(ctx, bvh.prims.data(), count, leaf, viaLeaf, nullptr, &fixed), found);
    ASSERT_EQ(detail::leaf_block::intersectBlocks(b, count, blocked, detail::BlockRay<4>(ray), got), found) << what;
    EXPECT_TRUE(sameBits(blocked.tfar, one.tfar)) << what;
    EXPECT_TRUE(sameBits(blocked.tfar, leaf.tfar)) << what;
    if (found) {
      expectSameHit(got, expected, what);
      expectSameHit(got, viaLeaf, what);
    }
    EXPECT_EQ(detail::leaf_block::occludedBlocks(b, count, anyBlocked, detail::BlockRay<4>(ray)), occluded) << what;
    EXPECT_EQ(detail::occludedLeaf<true>(ctx, bvh.prims.data(), count, anyLeaf, &fixed), occluded) << what;
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
  const detail::FixedTimeTriangles fixed(ctx, 0.0f);
  const detail::TriangleLeafBlocks mixed(ctx, oneLeaf({{0, 0}, {0, 1}, {filtered, 0}}), fixed, 0.0f);
  EXPECT_TRUE(mixed.empty());
  const detail::TriangleLeafBlocks plain(ctx, oneLeaf({{0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}}), fixed, 0.0f);
  ASSERT_NE(plain.of(0), nullptr);
  EXPECT_EQ(plain.blocks.size(), 2u);
  // Beside a blocked leaf, a leaf with a filtered geometry is tested one by
  // one: its block is marked, the other leaf's blocks are found.
  const detail::TriangleLeafBlocks both(
      ctx, leavesOf({{{0, 0}, {0, 1}, {0, 2}, {0, 3}, {0, 4}}, {{0, 5}, {filtered, 0}}, {{0, 6}}}), fixed, 0.0f);
  ASSERT_EQ(both.blocks.size(), 4u);
  ASSERT_NE(both.of(0), nullptr);
  EXPECT_EQ(both.of(0)[1].primID[0], 4u);
  EXPECT_EQ(both.of(8), nullptr);
  ASSERT_NE(both.of(12), nullptr);
  EXPECT_EQ(both.of(12)->primID[0], 6u);
  // A table whose leaves do not start at multiples of four gets no blocks.
  detail::WideBvh<8, false> unaligned = oneLeaf({{0, 0}, {0, 1}, {0, 2}, {0, 3}});
  unaligned.nodes[0].count[1] = 2;
  unaligned.nodes[0].child[1] = 1;
  EXPECT_TRUE(detail::TriangleLeafBlocks(ctx, unaligned, fixed, 0.0f).empty());
}

// The grids of the motion-leaf tests: 5, 2 and 1 steps (one alive over
// part of the shutter only), masks 1 to 3, and one beyond float's
// edge-function range (the double path).
void addMotionGrids(Scene& scene) {
  scene.setMask(addGrid(scene, 5, 1.0f, 0.0f, 5, true), 1u);
  scene.setMask(addGrid(scene, 5, 1.0f, 0.0f, 2, false, {0.25f, 0.75f}), 2u);
  scene.setMask(addGrid(scene, 4, 1.0f, 0.25f, 1, true), 3u);
  addGrid(scene, 3, 1e13f, 0.5f, 3, true);
}

// A leaf of 1 to 13 references of geometry g: consecutive triangles, a
// quarter of them replaced by any other.
std::vector<detail::PrimRef> drawLeaf(std::mt19937& rng, const Geometry& g, uint32_t geomID) {
  const uint32_t numTris = uint32_t(g.triangles().size());
  const uint32_t count = 1 + rng() % 13;
  const uint32_t first = rng() % (numTris - count);
  std::vector<detail::PrimRef> refs;
  for (uint32_t i = 0; i < count; ++i) refs.push_back({geomID, uint32_t(rng() % 4 == 0 ? rng() % numTris : first + i)});
  return refs;
}

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
    const detail::MotionLeafBlocks mb(ctx, bvh);
    const detail::MotionLeafBlocks::Leaf* leaf = mb.of(0);
    ASSERT_NE(leaf, nullptr);
    ASSERT_EQ(mb.blocks.size(), (count + 3) / 4 * g.numSteps());
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
    const detail::BlockRay<4> r(ray);
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(count) + " references";
    ASSERT_EQ(detail::intersectLeaf(ctx, bvh.prims.data(), count, viaLeaf, leafHit, nullptr), found) << what;
    ASSERT_EQ(detail::leaf_block::intersectMotionBlocks(ctx, mb, *leaf, bvh.prims.data(), count, viaBlocks, r, got),
              found)
        << what;
    EXPECT_TRUE(sameBits(viaBlocks.tfar, one.tfar)) << what;
    if (found) {
      expectSameHit(got, expected, what);
      expectSameHit(got, leafHit, what);
    }
    EXPECT_EQ(detail::leaf_block::occludedMotionBlocks(ctx, mb, *leaf, bvh.prims.data(), count, anyBlocks, r),
              occluded)
        << what;
    EXPECT_EQ(detail::occludedLeaf(ctx, bvh.prims.data(), count, anyLeaf), occluded) << what;
    hits += found;
    blocked += g.numSteps() > 1;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(blocked, 3000);
}

// Runs gathered into blocks through their indices (testGatheredRun, what
// `stbvh`, `bvh-segments` and `msbvh` leaves do): leaves of 1 to 13
// references of one or two geometries, at random times and on steps,
// through intersectLeaf and occludedLeaf with the block ray (the triangles
// read through the primitive ids, or from ReferenceTriangles) against the
// same without it and against intersectPrimitive one by one; geometries of
// 1, 2 and 5 steps, one alive over part of the shutter, and one whose
// vertices are the caller's, 20 bytes apart from an odd address (the
// gather's 12-byte loads at any alignment, none past a vertex).
TEST(LeafBlocks, GatheredRunsAgreeWithTheOneByOneTest) {
  Scene scene;
  addMotionGrids(scene);
  const uint32_t shared = addGrid(scene, 4, 1.0f, 0.5f, 2, true);
  // The shared grid's steps copied 20 bytes apart from an odd address,
  // ending exactly at the last vertex's z (nothing readable after it).
  std::vector<std::vector<char>> bytes(2);
  for (uint32_t k = 0; k < 2; ++k) {
    const VertexBuffer& v = scene.geometry(shared).vertices(k);
    bytes[k].assign(1 + 20 * (v.count - 1) + 12, 0);
    for (size_t i = 0; i < v.count; ++i) {
      const Vec3f p = v[i];
      std::memcpy(bytes[k].data() + 1 + 20 * i, &p, sizeof p);
    }
    scene.setVertices(shared, k, VertexBuffer{bytes[k].data() + 1, 20, v.count, 0});
  }
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  std::mt19937 rng(7);
  int hits = 0, gathered = 0;
  for (int trial = 0; trial < 8000; ++trial) {
    const uint32_t geomID = rng() % scene.numGeometries();
    const Geometry& g = ctx.geometry(geomID);
    std::vector<detail::PrimRef> refs = drawLeaf(rng, g, geomID);
    if (trial % 3 == 0) {  // a second geometry's run after the first
      const uint32_t other = (geomID + 1) % scene.numGeometries();
      const uint32_t more = 1 + rng() % 6;
      for (uint32_t i = 0; i < more; ++i) refs.push_back({other, uint32_t(rng() % ctx.geometry(other).triangles().size())});
      std::sort(refs.begin(), refs.end(), [](detail::PrimRef a, detail::PrimRef b) { return a.geomID < b.geomID; });
    }
    const uint32_t n = uint32_t(refs.size());
    float time = std::uniform_real_distribution<float>(0, 1)(rng);
    if (trial % 5 == 0) time = float(rng() % 5) / 4.0f;  // on a step, at the ends of the range
    const float scale = geomID == 3 ? 1e13f : 1.0f;
    const detail::PrimRef aim = refs[rng() % n];
    const Geometry& ag = ctx.geometry(aim.geomID);
    detail::RayQuery ray = rayTowards(rng, ag, aim.primID, aim.geomID == 3 ? 1e13f : scale,
                                      ag.timeRange().contains(time) ? time : 0.5f);
    ray.time = time;
    test::varyMaskAndTfar(rng, trial, ray);
    detail::RayQuery viaRuns = ray, viaBlocks = ray, anyRuns = ray, anyBlocks = ray, viaIndices = ray,
                     anyIndices = ray;
    Hit runHit, got, indexedHit;
    const detail::ReferenceTriangles indices(ctx, refs);
    const test::OneByOne reference = test::oneByOne(ctx, std::span(refs), ray);
    const detail::LeafBlockRay r(ray);
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(n) + " references";
    TraversalCounters c;
    ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), n, viaRuns, runHit, nullptr), reference.found) << what;
    ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), n, viaBlocks, got, &c, nullptr, &r), reference.found) << what;
    ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), n, viaIndices, indexedHit, nullptr, nullptr, &r,
                                    indices.from(0)),
              reference.found)
        << what;
    EXPECT_TRUE(sameBits(viaBlocks.tfar, reference.ray.tfar)) << what;
    EXPECT_TRUE(sameBits(viaIndices.tfar, reference.ray.tfar)) << what;
    if (reference.found) {
      expectSameHit(got, reference.hit, what);
      expectSameHit(got, runHit, what);
      expectSameHit(indexedHit, reference.hit, what);
    }
    EXPECT_EQ(detail::occludedLeaf(ctx, refs.data(), n, anyBlocks, nullptr, &r), reference.occluded) << what;
    EXPECT_EQ(detail::occludedLeaf(ctx, refs.data(), n, anyIndices, nullptr, &r, indices.from(0)), reference.occluded)
        << what;
    EXPECT_EQ(detail::occludedLeaf(ctx, refs.data(), n, anyRuns), reference.occluded) << what;
    hits += reference.found;
    gathered += c.blockPrimitiveTests > 0;
  }
  EXPECT_GT(hits, 1500);
  EXPECT_GT(gathered, 3000);
}

// The kd kinds' leaves (kd/kd_leaf_batch.h): the references that pass a
// leaf's kd checks, of up to three geometries in any order and up to the
// batch's capacity, tested together, against intersectPrimitive one by one
// over the same references in geometry order (the batch's promise for
// ties), at random times and on steps; and the batch is empty afterwards.
TEST(LeafBlocks, KdLeafBatchesAgreeWithTheOneByOneTest) {
  Scene scene;
  addMotionGrids(scene);
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  std::mt19937 rng(11);
  int hits = 0, gathered = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    std::vector<detail::PrimRef> refs;
    const uint32_t n = 1 + rng() % detail::KdLeafBatch::kCapacity;
    const uint32_t geoms = 1 + rng() % 3, first = rng() % scene.numGeometries();
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t geomID = (first + rng() % geoms) % scene.numGeometries();
      refs.push_back({geomID, uint32_t(rng() % ctx.geometry(geomID).triangles().size())});
    }
    float time = std::uniform_real_distribution<float>(0, 1)(rng);
    if (trial % 5 == 0) time = float(rng() % 5) / 4.0f;  // on a step, at the ends of the range
    const detail::PrimRef aim = refs[rng() % n];
    const Geometry& ag = ctx.geometry(aim.geomID);
    detail::RayQuery ray = rayTowards(rng, ag, aim.primID, aim.geomID == 3 ? 1e13f : 1.0f,
                                      ag.timeRange().contains(time) ? time : 0.5f);
    ray.time = time;
    test::varyMaskAndTfar(rng, trial, ray);
    std::vector<detail::PrimRef> inGeometryOrder = refs;
    std::stable_sort(inGeometryOrder.begin(), inGeometryOrder.end(),
                     [](detail::PrimRef a, detail::PrimRef b) { return a.geomID < b.geomID; });
    const test::OneByOne reference = test::oneByOne(ctx, std::span(inGeometryOrder), ray);
    const detail::LeafBlockRay r(ray);
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(n) + " references";
    detail::KdLeafBatch closest, any;
    for (const detail::PrimRef& p : refs) {
      closest.add(p);
      any.add(p);
    }
    EXPECT_EQ(closest.full(), n == detail::KdLeafBatch::kCapacity);
    detail::RayQuery viaBatch = ray, anyBatch = ray;
    Hit got;
    TraversalCounters c;
    ASSERT_EQ((closest.test<false, true>(ctx, viaBatch, &got, &c, r)), reference.found) << what;
    EXPECT_TRUE(sameBits(viaBatch.tfar, reference.ray.tfar)) << what;
    if (reference.found) expectSameHit(got, reference.hit, what);
    EXPECT_EQ((any.test<true, false>(ctx, anyBatch, nullptr, nullptr, r)), reference.occluded) << what;
    EXPECT_EQ(c.primitiveTests, n) << what;
    EXPECT_LE(c.blockPrimitiveTests, n) << what;
    EXPECT_TRUE(closest.empty() && any.empty()) << what;
    hits += reference.found;
    gathered += c.blockPrimitiveTests > 0;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(gathered, 3000);
}

// A motion leaf of two geometries, or of a geometry with a filter, is not
// blocked (its runs take intersectLeaf's paths).
TEST(LeafBlocks, MixedOrFilteredMotionLeavesAreNotBlocked) {
  Scene scene;
  addGrid(scene, 2, 1.0f, 0.0f, 2, false);
  addGrid(scene, 2, 1.0f, 0.0f, 2, false);
  const uint32_t filtered = addGrid(scene, 2, 1.0f, 0.0f, 2, false);
  scene.setFilter(filtered, [](const FilterArgs&) { return true; });
  BuildOptions o;
  detail::BuildBudget budget;
  const detail::SceneContext ctx(scene, o, budget);
  EXPECT_TRUE(detail::MotionLeafBlocks(ctx, oneLeaf<true>({{0, 0}, {1, 1}})).empty());
  EXPECT_TRUE(detail::MotionLeafBlocks(ctx, oneLeaf<true>({{filtered, 0}, {filtered, 1}})).empty());
  const detail::MotionLeafBlocks plain(ctx, oneLeaf<true>({{1, 0}, {1, 1}, {1, 2}, {1, 3}, {1, 4}}));
  ASSERT_NE(plain.of(0), nullptr);
  EXPECT_EQ(plain.blocks.size(), 4u);  // 2 blocks x 2 steps
  // Leaves side by side: each blocked one found from its first reference,
  // the mixed one tested one by one.
  const detail::MotionLeafBlocks both(
      ctx, leavesOf<true>({{{1, 0}, {1, 1}, {1, 2}, {1, 3}, {1, 4}}, {{0, 0}, {1, 5}}, {{0, 6}}}));
  EXPECT_EQ(both.blocks.size(), 6u);  // (2 + 1) blocks x 2 steps
  ASSERT_NE(both.of(0), nullptr);
  EXPECT_EQ(both.of(0)->first, 0u);
  EXPECT_EQ(both.of(8), nullptr);
  ASSERT_NE(both.of(12), nullptr);
  EXPECT_EQ(both.of(12)->geomID, 0u);
  EXPECT_EQ(both.of(12)->first, 4u);
  detail::WideBvh<8, true> unaligned = oneLeaf<true>({{1, 0}, {1, 1}, {1, 2}, {1, 3}});
  unaligned.nodes[0].count[1] = 2;
  unaligned.nodes[0].child[1] = 1;
  EXPECT_TRUE(detail::MotionLeafBlocks(ctx, unaligned).empty());
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

// `stbvh` and `bvh-segments` over a scene whose triangles' indices take
// more than 1 MB (translate at 0.5: 100k triangles) keep each reference's
// triangle beside the reference table (ReferenceTriangles::pays), and its
// 12 bytes a reference are in their bytes; below that (0.05) they do not.
// Both agree with brute force at random and step times.
TEST(LeafBlocks, TreesKeepingReferenceTrianglesAgreeWithBrute) {
  for (double size : {0.5, 0.05}) {
    const ProceduralScene ps = makeProceduralScene("translate", size, 7);
    BuildOptions bo;
    bo.kind = AccelKind::Brute;
    auto oracle = Accel::build(*ps.scene, bo);
    detail::BuildBudget budget;
    const detail::SceneContext ctx(*ps.scene, bo, budget);
    const bool pays = detail::ReferenceTriangles::pays(ctx);
    EXPECT_EQ(pays, size > 0.1) << size;
    for (AccelKind kind : {AccelKind::Stbvh, AccelKind::BvhSegments}) {
      BuildOptions o;
      o.kind = kind;
      auto tested = Accel::build(*ps.scene, o);
      const AccelStats st = tested->stats();
      // Bytes per reference: the nodes and the reference table (~21), and
      // 12 more with the triangles beside the references.
      const double perReference = double(st.bytes) / double(st.references);
      if (pays) EXPECT_GT(perReference, 28.0) << size << " " << toString(kind);  // 32-35 measured
      else EXPECT_LT(perReference, 28.0) << size << " " << toString(kind);       // 21 measured
      const auto rep =
          test::compareWithOracle(*oracle, *tested, test::oracleRays(ps, test::scaled(300, 100), test::scaled(6, 3), 29));
      EXPECT_EQ(rep.wrong, 0u) << size << " " << toString(kind) << ": " << rep.firstFailure;
      EXPECT_EQ(rep.anyWrong, 0u) << size << " " << toString(kind);
      EXPECT_GT(rep.hits, rep.rays / 4) << "too few hits to mean anything";
    }
  }
}

// The counters and the stats say what the leaf blocks hold and test:
// every leaf of `bvh-interp` over one triangle mesh is blocked, so all its
// primitive tests are block tests, and the blocks' bytes are a part of its
// bytes; `stbvh` keeps no blocks but gathers its leaves' runs of two or
// more triangles into blocks (leaf_block::testGatheredRun): most of its
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
