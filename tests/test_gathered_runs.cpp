// Runs gathered into blocks at the ray's time through their indices
// (leaves/gathered_runs.h), through the triangles' indices kept beside the
// references (leaves/reference_triangles.h) and in the kd kinds' batches
// (kd/kd_leaf_batch.h), against the one-by-one test; and the trees that
// keep the indices beside their references, against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>

#include "kd/kd_leaf_batch.h"
#include "leaves/reference_triangles.h"
#include "oracle.h"
#include "scene/scene_context.h"
#include "leaf_test_grid.h"
#include "test_util.h"

namespace mbrt {
namespace {

using namespace test;  // leaf_test_grid.h

// Runs gathered into blocks through their indices (testGatheredRun, what
// `stbvh`, `bvh-segments` and `msbvh` leaves do): leaves of 1 to 13
// references of one or two geometries, at random times and on steps,
// through intersectLeaf and occludedLeaf with the block ray (the triangles
// read through the primitive ids, or from ReferenceTriangleLeaves) against the
// same without it and against intersectPrimitive one by one; geometries of
// 1, 2 and 5 steps, one alive over part of the shutter, and two whose
// vertices are the caller's: one 12 bytes apart from an odd address (the
// gather's 12-byte loads at any alignment, none past a vertex), one 16
// bytes apart in buffers that end at the last vertex's fourth float, which
// their padding says (the 16-byte loads of buffers that allow them,
// PackedVerticesAt).
TEST(LeafBlocks, GatheredRunsAgreeWithTheOneByOneTest) {
  Scene scene;
  addMotionGrids(scene);
  const uint32_t shared = addGrid(scene, 4, 1.0f, 0.5f, 2, true);
  const uint32_t shared16 = addGrid(scene, 4, 2.0f, 0.25f, 2, true);
  // The shared grid's steps copied 12 bytes apart from an odd address,
  // ending exactly at the last vertex's z (nothing readable after it).
  std::vector<std::vector<char>> bytes(2);
  for (uint32_t k = 0; k < 2; ++k) {
    const VertexBuffer& v = scene.geometry(shared).vertices(k);
    bytes[k].assign(1 + 12 * v.count, 0);
    for (size_t i = 0; i < v.count; ++i) {
      const Vec3f p = v[i];
      std::memcpy(bytes[k].data() + 1 + 12 * i, &p, sizeof p);
    }
    scene.setVertices(shared, k, VertexBuffer{bytes[k].data() + 1, 12, v.count, 0});
  }
  std::vector<std::vector<float>> floats(2);
  for (uint32_t k = 0; k < 2; ++k) {
    const VertexBuffer& v = scene.geometry(shared16).vertices(k);
    floats[k].assign(4 * v.count, -1.0f);
    for (size_t i = 0; i < v.count; ++i) {
      const Vec3f p = v[i];
      std::memcpy(&floats[k][4 * i], &p, sizeof p);
    }
    scene.setVertices(shared16, k, VertexBuffer{floats[k].data(), 16, v.count, 4});
  }
  ASSERT_TRUE(detail::leaf_block::wideReadable(scene.geometry(shared16).vertices(1)));
  ASSERT_FALSE(detail::leaf_block::wideReadable(scene.geometry(shared).vertices(1)));
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
    const detail::ReferenceTriangleLeaves indices(ctx, detail::LeafTable{refs});
    const test::OneByOne reference = test::oneByOne(ctx, std::span(refs), ray);
    const detail::LeafBlockRay r(ray);
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(n) + " references";
    TraversalCounters c;
    ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), n, viaRuns, runHit, nullptr), reference.found) << what;
    ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), n, viaBlocks, got, &c, &r), reference.found) << what;
    ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), n, viaIndices, indexedHit, nullptr, &r, indices.from(0)),
              reference.found)
        << what;
    EXPECT_TRUE(sameBits(viaBlocks.tfar, reference.ray.tfar)) << what;
    EXPECT_TRUE(sameBits(viaIndices.tfar, reference.ray.tfar)) << what;
    if (reference.found) {
      expectSameHit(got, reference.hit, what);
      expectSameHit(got, runHit, what);
      expectSameHit(indexedHit, reference.hit, what);
    }
    EXPECT_EQ(detail::occludedLeaf(ctx, refs.data(), n, anyBlocks, &r), reference.occluded) << what;
    EXPECT_EQ(detail::occludedLeaf(ctx, refs.data(), n, anyIndices, &r, indices.from(0)), reference.occluded) << what;
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
    const detail::ReferenceLeaves plain;
    ASSERT_EQ((closest.test<false, true>(plain, ctx, viaBatch, &got, &c, r)), reference.found) << what;
    EXPECT_TRUE(sameBits(viaBatch.tfar, reference.ray.tfar)) << what;
    if (reference.found) expectSameHit(got, reference.hit, what);
    EXPECT_EQ((any.test<true, false>(plain, ctx, anyBatch, nullptr, nullptr, r)), reference.occluded) << what;
    EXPECT_EQ(c.primitiveTests, n) << what;
    EXPECT_LE(c.blockPrimitiveTests, n) << what;
    EXPECT_TRUE(closest.empty() && any.empty()) << what;
    hits += reference.found;
    gathered += c.blockPrimitiveTests > 0;
  }
  EXPECT_GT(hits, 1000);
  EXPECT_GT(gathered, 3000);
}

// `stbvh` and `bvh-segments` over a scene whose triangles' indices take
// more than 1 MB (translate at 0.5: 100k triangles) keep each reference's
// triangle beside the reference table (ReferenceTriangleLeaves::pays), and its
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
    const bool pays = detail::ReferenceTriangleLeaves::pays(ctx);
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

}  // namespace
}  // namespace mbrt
