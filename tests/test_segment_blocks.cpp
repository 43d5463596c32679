// The segment blocks of `frozen` (geometry/segment_block.h,
// leaves/segment_blocks.h) against the one-by-one test: a lane the block
// test leaves out must be one that intersectSegment misses at any distance
// (the block only sorts out misses), on segments of every shape the scalar
// test knows (cones, spheres, a zero radius at one end, a solid inside
// another's cap, points, sizes beyond float's range that go to double,
// origins inside the solid); a blocked leaf finds the hit of
// intersectPrimitive on each reference in order (bits of t, u, Ng, ids, the
// final tfar, occlusion) with masks, steps and leaf sizes 1 to 13, as do
// runs gathered into blocks at the ray's time (the motion trees' leaves,
// scene/leaf_intersect.h); and the tree of a hair scene is laid out in segment blocks and agrees with brute
// force at the frozen time.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "bvh/leaf_table.h"
#include "leaves/segment_blocks.h"
#include "leaf_test_grid.h"
#include "oracle.h"
#include "scene/scene_context.h"
#include "test_util.h"

namespace mbrt {
namespace {

using test::expectSameHit;
using test::sameBits;

// A random segment of size about `scale`, of one of the scalar test's
// shapes.
void randomSegment(std::mt19937& rng, float scale, Vec3f& p0, Vec3f& p1, float& r0, float& r1) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  p0 = Vec3f{u(rng), u(rng), u(rng)} * scale;
  p1 = p0 + Vec3f{u(rng), u(rng), u(rng)} * scale;
  r0 = (0.01f + 0.3f * w(rng)) * scale;
  r1 = (0.01f + 0.3f * w(rng)) * scale;
  switch (rng() % 6) {
    case 0: r1 = 0.0f; break;               // a cone to a point
    case 1: p1 = p0; break;                 // a sphere
    case 2: r0 = 2.0f * length(p1 - p0) * 1.01f + r1; break;  // one cap holds the other
    case 3: r0 = r1 = 0.0f; break;          // no solid
    default: break;
  }
}

// A ray through, near or away from the segment, or from inside it.
detail::RayQuery rayNear(std::mt19937& rng, Vec3f p0, Vec3f p1, float r, float scale) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  const Vec3f target = p0 + (p1 - p0) * w(rng) + Vec3f{u(rng), u(rng), u(rng)} * (r * 1.5f);
  Ray ray;
  const bool inside = rng() % 8 == 0;  // from the target, in a random direction
  ray.org = inside ? target : target + Vec3f{u(rng), u(rng), u(rng)} * (3.0f * scale);
  ray.dir = inside || rng() % 8 == 0 ? Vec3f{u(rng), u(rng), u(rng)} : target - ray.org;
  if (rng() % 16 == 0) ray.dir = ray.dir * 1e-3f;  // a short direction: the test's unit direction differs
  return detail::RayQuery(ray);
}

TEST(SegmentBlocks, LanesLeftOutAreMissesOfTheScalarTest) {
  std::mt19937 rng(5);
  int hits = 0, leftOut = 0, lanes = 0, scalarSizes = 0;
  for (const float scale : {1.0f, 1e-3f, 3e3f, 1e-6f, 1e7f}) {
    for (int trial = 0; trial < 3000; ++trial) {
      detail::SegmentBlock<4> b;
      Vec3f p[4][2];
      float r[4][2];
      for (int lane = 0; lane < 4; ++lane) {
        randomSegment(rng, scale, p[lane][0], p[lane][1], r[lane][0], r[lane][1]);
        b.set(lane, p[lane][0], p[lane][1], r[lane][0], r[lane][1]);
      }
      const int aim = int(rng() % 4);
      detail::RayQuery ray = rayNear(rng, p[aim][0], p[aim][1], std::max(r[aim][0], r[aim][1]), scale);
      const uint32_t valid = rng() % 4 == 0 ? uint32_t(rng() % 16) : 15u;
      const uint32_t candidates = detail::segmentBlockCandidates(detail::SegmentBlockRay<4>(ray), b, valid);
      EXPECT_EQ(candidates & ~valid, 0u);
      // Every distance along the line: a lane left out must have no hit at all.
      detail::RayQuery anywhere = ray;
      anywhere.tnear = -3e38f;
      anywhere.tfar = 3e38f;
      for (int lane = 0; lane < 4; ++lane) {
        if (!(valid >> lane & 1u)) continue;
        ++lanes;
        detail::SegmentHit sh;
        const bool hit = detail::intersectSegment(anywhere, p[lane][0], p[lane][1], r[lane][0], r[lane][1], sh);
        hits += hit;
        const bool candidate = candidates >> lane & 1u;
        leftOut += !candidate;
        if (hit) EXPECT_TRUE(candidate) << "scale " << scale << ", trial " << trial << ", lane " << lane;
        const float reach = 0.5f * length(p[lane][1] - p[lane][0]) + std::max(r[lane][0], r[lane][1]);
        if ((r[lane][0] > 0 || r[lane][1] > 0) && !(reach >= 1e-4f && reach <= 1e5f)) {
          ++scalarSizes;
          EXPECT_TRUE(candidate) << "a size the scalar test takes to double, scale " << scale;
        }
      }
    }
  }
  EXPECT_GT(hits, lanes / 8);      // the aimed lanes mostly hit
  EXPECT_GT(leftOut, lanes / 3);   // and the block sorts out most of the others
  EXPECT_GT(scalarSizes, 1000);    // the tiny and huge scales reach the double path
}

// Segments of `n` strands crossing each other (ties at crossings, shared
// end points), over `steps` steps.
uint32_t addStrands(Scene& scene, int n, uint32_t steps, float lift) {
  std::vector<Segment> segs;
  std::vector<std::vector<Vec3f>> pos(steps);
  std::vector<float> radii;
  const int per = 6;
  for (int s = 0; s < n; ++s)
    for (int k = 0; k <= per; ++k) {
      const float a = float(k) / per * 2 - 1, b = float(s) / float(n) * 2 - 1;
      for (uint32_t st = 0; st < steps; ++st)
        pos[st].push_back(s % 2 ? Vec3f{a, b, lift + 0.05f * float(st)} : Vec3f{b, a, lift + 0.02f * float(k)});
      radii.push_back(k % 3 == 0 ? 0.0f : 0.04f + 0.01f * float(k));
      if (k > 0) segs.push_back({uint32_t(s * (per + 1) + k - 1), uint32_t(s * (per + 1) + k)});
    }
  return scene.addSegments(std::move(segs), std::move(pos), std::move(radii));
}

// The strand geometries of the leaf tests, of `steps` steps: two copies of
// 8 strands (masks 1 and 2: ties across geometries) and 5 strands lifted
// above them (mask 3), with their context and every reference.
struct StrandLeaves {
  Scene scene;
  BuildOptions options;
  detail::BuildBudget budget;
  detail::SceneContext ctx;
  std::vector<detail::PrimRef> all;

  explicit StrandLeaves(uint32_t steps) : scene(withStrands(steps)), ctx(scene, options, budget), all(ctx.primitives()) {}

 private:
  static Scene withStrands(uint32_t steps) {
    Scene s;
    s.setMask(addStrands(s, 8, steps, 0.0f), 1u);
    s.setMask(addStrands(s, 8, steps, 0.0f), 2u);
    s.setMask(addStrands(s, 5, steps, 0.1f), 3u);
    return s;
  }
};

// A leaf of 1 to 13 references from `all`, mostly consecutive (one
// geometry's neighbours), a quarter of them drawn anywhere.
std::vector<detail::PrimRef> drawStrandLeaf(std::mt19937& rng, const std::vector<detail::PrimRef>& all) {
  const uint32_t count = 1 + rng() % 13;
  std::vector<detail::PrimRef> refs;
  const uint32_t first = rng() % uint32_t(all.size() - count);
  for (uint32_t i = 0; i < count; ++i) refs.push_back(rng() % 4 == 0 ? all[rng() % all.size()] : all[first + i]);
  return refs;
}

// A ray at `time` passing near one of the references' segments, with the
// mask and tfar varied by trial.
detail::RayQuery rayAtOneOf(std::mt19937& rng, const detail::SceneContext& ctx,
                            const std::vector<detail::PrimRef>& refs, float time, int trial) {
  const detail::PrimRef aim = refs[rng() % refs.size()];
  const Geometry& g = ctx.geometry(aim.geomID);
  const Segment& s = g.segments()[aim.primID];
  const Vec3f p0 = g.vertexAt(time, s.v0), p1 = g.vertexAt(time, s.v1);
  detail::RayQuery ray = rayNear(rng, p0, p1, 0.03f, 1.0f);
  ray.time = time;
  test::varyMaskAndTfar(rng, trial, ray);
  return ray;
}

TEST(SegmentBlocks, BlockedLeavesAgreeWithTheOneByOneTest) {
  for (uint32_t steps : {1u, 3u}) {
    const StrandLeaves leaves(steps);
    const detail::SceneContext& ctx = leaves.ctx;
    const std::vector<detail::PrimRef>& all = leaves.all;
    std::mt19937 rng(13);
    const float time = 0.375f;
    int hits = 0;
    for (int trial = 0; trial < 4000; ++trial) {
      std::vector<detail::PrimRef> refs = drawStrandLeaf(rng, all);
      const uint32_t count = uint32_t(refs.size());
      std::sort(refs.begin(), refs.end(), [](detail::PrimRef a, detail::PrimRef b) {
        return a.geomID != b.geomID ? a.geomID < b.geomID : a.primID < b.primID;
      });
      detail::WideBvh<8, false> bvh;
      bvh.nodes.resize(1);
      bvh.nodes[0].clear();
      bvh.nodes[0].count[0] = uint8_t(count);
      bvh.nodes[0].child[0] = 0;
      bvh.prims = refs;
      while (bvh.prims.size() % 4 != 0) bvh.prims.push_back(refs.back());
      const detail::SegmentBlockLeaves blocks(ctx, detail::leafTable(bvh, time));
      ASSERT_NE(blocks.blocksOf(0), nullptr);
      const detail::RayQuery ray = rayAtOneOf(rng, ctx, refs, time, trial);
      const test::OneByOne reference = test::oneByOne(ctx, refs, ray);
      const std::string what = "steps " + std::to_string(steps) + ", trial " + std::to_string(trial);
      detail::RayQuery blocked = ray, anyBlocked = ray;
      Hit got;
      const detail::LeafBlockRay r(ray);
      const detail::LeafRefs leaf{bvh.prims.data(), count, 0};
      ASSERT_EQ((blocks.test<false, false>(ctx, leaf, blocked, r, &got, nullptr)), reference.found) << what;
      EXPECT_TRUE(sameBits(blocked.tfar, reference.ray.tfar)) << what;
      if (reference.found) expectSameHit(got, reference.hit, what);
      EXPECT_EQ((blocks.test<true, false>(ctx, leaf, anyBlocked, r, nullptr, nullptr)), reference.occluded) << what;
      hits += reference.found;
    }
    EXPECT_GT(hits, 800);
  }
}

// Runs of segments gathered into blocks at the ray's time through their
// vertex indices (leaves/gathered_runs.h, what the motion trees' and the
// kd kinds' leaves do): leaves of 1 to 13 references of up to three
// strand geometries of 1 or 3 steps (one a copy of another: ties), at
// random times and on the steps, through intersectLeaf and occludedLeaf
// with the block ray, against intersectPrimitive one by one and against
// the same leaf test without it.
TEST(SegmentBlocks, GatheredRunsAgreeWithTheOneByOneTest) {
  for (uint32_t steps : {1u, 3u}) {
    const StrandLeaves leaves(steps);
    const detail::SceneContext& ctx = leaves.ctx;
    const std::vector<detail::PrimRef>& all = leaves.all;
    std::mt19937 rng(17);
    int hits = 0, gathered = 0;
    for (int trial = 0; trial < 4000; ++trial) {
      std::vector<detail::PrimRef> refs = drawStrandLeaf(rng, all);
      const uint32_t count = uint32_t(refs.size());
      std::stable_sort(refs.begin(), refs.end(),
                       [](detail::PrimRef a, detail::PrimRef b) { return a.geomID < b.geomID; });
      float time = std::uniform_real_distribution<float>(0, 1)(rng);
      if (trial % 5 == 0) time = float(rng() % 3) / 2.0f;  // on a step, at the ends of the shutter
      const detail::RayQuery ray = rayAtOneOf(rng, ctx, refs, time, trial);
      const test::OneByOne reference = test::oneByOne(ctx, refs, ray);
      const std::string what = "steps " + std::to_string(steps) + ", trial " + std::to_string(trial);
      detail::RayQuery viaBlocks = ray, viaRuns = ray, anyBlocks = ray;
      Hit got, runHit;
      TraversalCounters c;
      const detail::LeafBlockRay r(ray);
      ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), count, viaBlocks, got, &c, &r), reference.found) << what;
      ASSERT_EQ(detail::intersectLeaf(ctx, refs.data(), count, viaRuns, runHit, nullptr), reference.found) << what;
      EXPECT_TRUE(sameBits(viaBlocks.tfar, reference.ray.tfar)) << what;
      if (reference.found) {
        expectSameHit(got, reference.hit, what);
        expectSameHit(got, runHit, what);
      }
      EXPECT_EQ(detail::occludedLeaf(ctx, refs.data(), count, anyBlocks, &r), reference.occluded) << what;
      hits += reference.found;
      gathered += c.blockPrimitiveTests > 0;
    }
    EXPECT_GT(hits, 800);
    EXPECT_GT(gathered, 2000);
  }
}

TEST(SegmentBlocks, AHairTreeIsLaidOutInBlocksAndAgreesWithBrute) {
  const ProceduralScene ps = makeProceduralScene("hair", 0.02, 5);
  BuildOptions bo;
  bo.kind = AccelKind::Brute;
  auto oracle = Accel::build(*ps.scene, bo);
  for (float t : {0.0f, 0.5f, 1.0f}) {
    BuildOptions to;
    to.kind = AccelKind::Frozen;
    to.frozenTime = t;
    auto tested = Accel::build(*ps.scene, to);
    const AccelStats st = tested->stats();
    EXPECT_GT(st.leafBlockBytes, 0u);
    EXPECT_GT(double(st.references) / double(st.leafNodes), 2.0);
    const auto rays = test::oracleRays(ps, test::scaled(2000, 500), 0, 29, t);
    TraversalCounters c;
    for (const Ray& r : rays) {
      Hit h;
      tested->intersect(r, h, c);
    }
    EXPECT_EQ(c.blockPrimitiveTests, c.primitiveTests) << "every leaf of segments is blocked";
    const auto rep = test::compareWithOracle(*oracle, *tested, rays);
    EXPECT_EQ(rep.wrong, 0u) << "frozen@" << t << ": " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << "frozen@" << t;
    EXPECT_GT(rep.hits, rep.rays / 4) << "too few hits to mean anything";
  }
}

}  // namespace
}  // namespace mbrt
