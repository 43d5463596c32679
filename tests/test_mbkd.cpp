// mbkd (Yang et al. 2017) and the kd-tree core: the static kd-tree against
// brute force, a fast-moving triangle crossing every plane, conservative leaf
// time intervals (sampled), the SIMD leaf block test at its interval ends,
// build statistics (the paper's Table 2).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <tuple>
#include <cstdio>
#include <random>

#include "core/inspect.h"
#include "kd/mbkd.h"
#include "scene/scene_context.h"
#include "kd/kd_builder.h"
#include "kd/kd_leaf_blocks.h"
#include "oracle.h"
#include "test_util.h"

using namespace mbrt;

namespace {

using Rng = std::mt19937;

std::unique_ptr<Accel> build(const Scene& scene, AccelKind kind) { return test::buildKind(scene, kind); }

// Rays of every kind against brute: random, axis-parallel, and lying in the
// axis planes through the scene (where kd split planes sit).
std::vector<Ray> mixedRays(Rng& rng, int count, bool randomTimes) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    const float time = randomTimes ? u(rng) : 0.5f;
    Ray r = test::randomRay(rng, time);
    const int kind = i % 4;
    if (kind == 1) {  // parallel to two axes
      const int a = int(u(rng) * 3) % 3;
      r.dir = Vec3f(0.0f);
      r.dir[a] = u(rng) < 0.5f ? -1.0f : 1.0f;
      r.org[a] = -3.0f * r.dir[a];
      r.org[(a + 1) % 3] = 2 * u(rng) - 1;
      r.org[(a + 2) % 3] = 2 * u(rng) - 1;
    } else if (kind == 2) {  // parallel to one axis plane
      const int a = int(u(rng) * 3) % 3;
      r.dir[a] = 0.0f;
      if (r.dir.x == 0 && r.dir.y == 0 && r.dir.z == 0) r.dir[(a + 1) % 3] = 1.0f;
    }
    rays.push_back(r);
  }
  return rays;
}

TEST(Mbkd, StaticKdTreeMatchesBrute) {
  Rng rng(3);
  Scene scene;
  test::addRandomMovingTriangles(scene, rng, 1500, 1, 0.15f, 0.0f);
  // Axis-aligned grid in z = 0: triangles lying in kd planes.
  std::vector<Triangle> tris;
  std::vector<Vec3f> v;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x) {
      const uint32_t b = uint32_t(v.size());
      const float x0 = -1 + x * 0.25f, y0 = -1 + y * 0.25f;
      v.push_back({x0, y0, 0});
      v.push_back({x0 + 0.25f, y0, 0});
      v.push_back({x0 + 0.25f, y0 + 0.25f, 0});
      v.push_back({x0, y0 + 0.25f, 0});
      tris.push_back({b, b + 1, b + 2});
      tris.push_back({b, b + 2, b + 3});
    }
  scene.addTriangleMesh(std::move(tris), {std::move(v)});
  auto brute = build(scene, AccelKind::Brute);
  auto kd = build(scene, AccelKind::Mbkd);
  const auto rep = test::compareWithOracle(*brute, *kd, mixedRays(rng, 20000, true));
  EXPECT_EQ(rep.wrong, 0u) << rep.firstFailure;
  EXPECT_EQ(rep.anyWrong, 0u);
  EXPECT_GT(rep.hits, rep.rays / 4);
  // Without motion nothing is duplicated.
  detail::BuildBudget budget;
  BuildOptions o;
  o.kind = AccelKind::Mbkd;
  detail::SceneContext ctx(scene, o, budget);
  auto st = detail::makeMbkd(ctx);
  EXPECT_EQ(detail::statsOf<detail::KdBuildStats>(*st).duplicatedRefs, 0u);
  const AccelStats s = kd->stats();
  EXPECT_GT(s.innerNodes, 100u);
  EXPECT_GT(s.sahCost, 0.0);
}

// Many small static triangles (many planes) and one triangle racing across
// the whole scene, in 1 step segment and in 4.
TEST(Mbkd, FastTriangleAcrossTheSceneIsNeverMissed) {
  for (uint32_t steps : {2u, 5u}) {
    Rng rng(11 + steps);
    Scene scene;
    test::addRandomMovingTriangles(scene, rng, 3000, 1, 0.05f, 0.0f);
    std::vector<std::vector<Vec3f>> pos(steps);
    for (uint32_t s = 0; s < steps; ++s) {
      const float f = float(s) / float(steps - 1);
      const Vec3f c{-1.5f + 3.0f * f, std::sin(6.0f * f) * 0.8f, -0.9f + 1.8f * f * f};
      pos[s] = {c + Vec3f{-0.1f, -0.1f, 0}, c + Vec3f{0.1f, -0.1f, 0.02f}, c + Vec3f{0, 0.12f, -0.02f}};
    }
    const uint32_t fast = scene.addTriangleMesh({Triangle{0, 1, 2}}, std::move(pos));
    auto brute = build(scene, AccelKind::Brute);
    auto kd = build(scene, AccelKind::Mbkd);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    const Geometry& g = scene.geometry(fast);
    size_t fastHits = 0;
    std::vector<Ray> rays;
    for (int i = 0; i <= 4000; ++i) {
      const float t = i < 4000 ? u(rng) : 1.0f;
      const Vec3f target = (g.vertexAt(t, 0) + g.vertexAt(t, 1) + g.vertexAt(t, 2)) * (1.0f / 3.0f);
      Ray r;
      r.org = target + Vec3f{u(rng) - 0.5f, u(rng) - 0.5f, 1.0f} * 4.0f;
      if (i % 3 == 0) r.org = target + Vec3f{0.0f, 0.0f, 3.0f};  // straight down z
      r.dir = target - r.org;
      r.time = i % 7 == 0 ? float(i % 5) / 4.0f : t;
      rays.push_back(r);
      Hit h;
      if (brute->intersect(r, h) && h.geomID == fast) ++fastHits;
    }
    const auto rep = test::compareWithOracle(*brute, *kd, rays);
    EXPECT_EQ(rep.wrong, 0u) << steps << " steps: " << rep.firstFailure;
    EXPECT_EQ(rep.anyWrong, 0u) << steps << " steps";
    EXPECT_GT(fastHits, rays.size() / 4) << "the moving triangle should be hit often";
    // It crosses many cells: it is referenced by many leaves.
    auto ctxBudget = std::make_unique<detail::BuildBudget>();
    BuildOptions o;
    o.kind = AccelKind::Mbkd;
    detail::SceneContext ctx(scene, o, *ctxBudget);
    auto st = detail::makeMbkd(ctx);
    size_t leavesWithFast = 0;
    detail::inspect(*st).forEachLane([&](const detail::LaneView& leaf) {
      for (const detail::PrimRef& p : leaf.below) leavesWithFast += p.geomID == fast;
    });
    EXPECT_GT(leavesWithFast, 20u);
  }
}

// A primitive's actual box at time t overlaps a leaf's cell only if the leaf
// references it with t inside the stored interval.
TEST(Mbkd, LeafTimeIntervalsAreConservative) {
  Rng rng(5);
  auto scene = std::make_shared<Scene>();
  test::addRandomMovingTriangles(*scene, rng, 300, 2, 0.1f, 0.6f);
  test::addRandomMovingTriangles(*scene, rng, 300, 5, 0.1f, 0.3f);
  test::addRandomMovingTriangles(*scene, rng, 200, 3, 0.1f, 0.5f, {0.2f, 0.7f});
  BuildOptions o;
  o.kind = AccelKind::Mbkd;
  detail::BuildBudget budget;
  detail::SceneContext ctx(*scene, o, budget);
  auto st = detail::makeMbkd(ctx);
  const detail::Inspect& inspect = detail::inspect(*st);
  EXPECT_GT(detail::statsOf<detail::KdBuildStats>(inspect).duplicatedRefs, 0u);
  size_t checks = 0, failures = 0;
  std::string first;
  inspect.forEachLane([&](const detail::LaneView& leaf) {
    const Box3f cell = leaf.box(0.5f);
    ASSERT_EQ(leaf.times.size(), leaf.below.size());
    // primitive -> its intervals in this leaf (a primitive that leaves and
    // comes back has several)
    std::multimap<std::pair<uint32_t, uint32_t>, std::pair<float, float>> in;
    for (size_t k = 0; k < leaf.below.size(); ++k)
      in.insert({{leaf.below[k].geomID, leaf.below[k].primID}, {leaf.times[k].lo, leaf.times[k].hi}});
    uint32_t index = 0;
    for (uint32_t gid = 0; gid < scene->numGeometries(); ++gid) {
      const Geometry& g = scene->geometry(gid);
      for (uint32_t p = 0; p < g.numPrimitives(); ++p, ++index) {
        const Triangle& tri = g.triangles()[p];
        for (int k = 0; k <= 64; ++k) {
          const float t = float(k) / 64.0f;
          if (!g.timeRange().contains(t)) continue;
          Box3f b(g.vertexAt(t, tri.v0));
          b.extend(Box3f(g.vertexAt(t, tri.v1)));
          b.extend(Box3f(g.vertexAt(t, tri.v2)));
          if (intersect(b, cell).empty()) continue;
          ++checks;
          const auto range = in.equal_range({gid, p});
          bool covered = false;
          for (auto it = range.first; it != range.second; ++it) covered |= t >= it->second.first && t <= it->second.second;
          if (!covered && failures++ == 0)
            first = "prim " + std::to_string(index) + " t " + std::to_string(t) + (range.first == range.second ? " not in leaf" : " outside");
        }
      }
    }
  });
  EXPECT_GT(checks, 10000u);
  EXPECT_EQ(failures, 0u) << first;
}

// The paper's Table 2 and 3 figures on three suite scenes at small size
// (MBRT_TEST_SCALE=50: the default sizes, as in docs/mbkd.md).
TEST(Mbkd, BuildStatisticsLikeTable2) {
  for (const char* name : {"hairball", "skinned", "rotate"}) {
    const ProceduralScene ps = makeProceduralScene(name, 0.02 * test::testScale(), 5);
    BuildOptions o;
    o.kind = AccelKind::Mbkd;
    detail::BuildBudget budget;
    detail::SceneContext ctx(*ps.scene, o, budget);
    auto st = detail::makeMbkd(ctx);
    const auto& s = detail::statsOf<detail::KdBuildStats>(*st);
    const size_t refs = s.normalRefs + s.duplicatedRefs;
    AccelStats as;
    st->fillStats(as);
    std::printf(
        "[mbkd %s] prims %zu refs %zu (%.2f per prim) duplicated %.1f%% | build %.3fs: SAH %.1f%% "
        "duplication %.1f%% propagation %.1f%% | nodes %zu bytes %zu SAH %.2f depth %zu\n",
        name, s.primitives, refs, double(refs) / double(s.primitives), 100.0 * double(s.duplicatedRefs) / double(refs),
        s.totalSeconds, 100 * s.sahSeconds / s.totalSeconds, 100 * s.duplicationSeconds / s.totalSeconds,
        100 * s.propagationSeconds / s.totalSeconds, as.innerNodes + as.leafNodes, as.bytes, as.sahCost,
        as.maxDepth);
    EXPECT_GT(refs, s.primitives / 2);
    EXPECT_EQ(as.references, refs);
  }
}

// The block test (kd_leaf_blocks.h): a lane is alive exactly on its closed
// interval (ends, 0 and 1 included), padding lanes never, and an alive
// lane's box is the linear bounds at the ray's time.
TEST(Mbkd, LeafBlockLanesAreAliveOnTheirClosedIntervals) {
  // One leaf, three references of primitive 0: a unit box moving +x by 4
  // over the shutter, alive on [0, 0.25], [0.5, 0.5] and [0.75, 1].
  detail::KdTree tree;
  tree.nodes.push_back(detail::KdNode::leaf(0, 3));
  tree.refs = {{0, 0.75f, 1.0f}, {0, 0.0f, 0.25f}, {0, 0.5f, 0.5f}};
  const detail::PrimRef prim{7, 9};
  const LBounds moving(Box3f(Vec3f(0.0f), Vec3f(1.0f)), Box3f(Vec3f(4.0f, 0.0f, 0.0f), Vec3f(5.0f, 1.0f, 1.0f)));
  const detail::KdLeafBlocks blocks =
      detail::KdLeafBlocks::build(tree, &prim, [&](uint32_t, TimeRange) { return moving; });
  ASSERT_EQ(blocks.blocks.size(), 1u);
  const detail::KdLeafBlock& b = blocks.blocks[0];
  EXPECT_EQ(b.t0[0], 0.0f);  // sorted by interval start
  EXPECT_EQ(b.t0[2], 0.75f);
  EXPECT_EQ(b.prim[1].geomID, 7u);
  // A ray along +y through x = 0.5 + 4 t hits the box at time t only.
  auto test = [&](float time, float x, uint32_t& hits) {
    detail::RayQuery q;
    q.setup(Vec3f(x, -1.0f, 0.5f), Vec3f(0.0f, 1.0f, 0.0f), 0.0f, kInf, time, ~0u);
    return detail::kdBlockTest(b, detail::KdBlockRay(q), q.tfar, hits);
  };
  uint32_t hits;
  EXPECT_EQ(test(0.0f, 0.5f, hits), 0b001u);
  EXPECT_EQ(hits, 0b001u);
  EXPECT_EQ(test(0.25f, 1.5f, hits), 0b001u);
  EXPECT_EQ(hits, 0b001u);
  EXPECT_EQ(test(0.25f, 3.5f, hits), 0b001u);  // alive, but the box is elsewhere
  EXPECT_EQ(hits, 0u);
  EXPECT_EQ(test(std::nextafter(0.25f, 1.0f), 1.5f, hits), 0u);
  EXPECT_EQ(test(0.5f, 2.5f, hits), 0b010u);
  EXPECT_EQ(hits, 0b010u);
  EXPECT_EQ(test(std::nextafter(0.5f, 1.0f), 2.5f, hits), 0u);
  EXPECT_EQ(test(0.75f, 3.5f, hits), 0b100u);
  EXPECT_EQ(hits, 0b100u);
  EXPECT_EQ(test(1.0f, 4.5f, hits), 0b100u);
  EXPECT_EQ(hits, 0b100u);
  EXPECT_EQ(test(1.5f, 4.5f, hits), 0u);  // padding lanes 3..7 never alive
}

// Time slices (kd_leaf_blocks.h): a leaf of many short-lived references is
// sliced; at every time (0, 1, slice ends and the floats beside them, random
// ones) the blocks of the time's slice hold every reference alive then, and
// forEachReference reports each reference once.
TEST(Mbkd, SlicedLeafBlocksHoldEveryReferenceAliveAtTheRaysTime) {
  detail::KdTree tree;
  Rng rng(17);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (uint32_t i = 0; i < 400; ++i) {
    const float t0 = u(rng), t1 = std::min(1.0f, t0 + 0.03f * u(rng));
    tree.refs.push_back({i % 7, i % 50 == 0 ? 0.0f : t0, i % 60 == 0 ? 1.0f : t1});
  }
  tree.refs.push_back({3, 0.5f, 0.5f});
  tree.refs.push_back({4, 0.25f, 0.75f});
  tree.nodes.push_back(detail::KdNode::leaf(0, uint32_t(tree.refs.size())));
  std::vector<detail::PrimRef> prims;
  for (uint32_t p = 0; p < 7; ++p) prims.push_back({p, 100 + p});
  const LBounds box(Box3f(Vec3f(0.0f), Vec3f(1.0f)), Box3f(Vec3f(0.0f), Vec3f(1.0f)));
  const detail::KdLeafBlocks blocks =
      detail::KdLeafBlocks::build(tree, prims.data(), [&](uint32_t, TimeRange) { return box; });
  const detail::KdNode& leaf = blocks.cells.nodes[0];
  ASSERT_GT(leaf.count(), 1u) << "short-lived references should be sliced";
  // Once each, with their intervals.
  std::multiset<std::tuple<uint32_t, float, float>> expected, reported;
  for (const detail::KdLeafRef& r : tree.refs) expected.insert({prims[r.prim].primID, r.t0, r.t1});
  blocks.forEachReference(leaf, [&](detail::PrimRef p, TimeRange t) { reported.insert({p.primID, t.lo, t.hi}); });
  EXPECT_EQ(reported, expected);
  std::vector<float> times = {0.0f, 1.0f, std::nextafter(1.0f, 0.0f), std::nextafter(0.0f, 1.0f)};
  for (uint32_t i = 1; i < leaf.count(); ++i) {
    const float end = detail::kdSliceStart(i, leaf.count());
    times.insert(times.end(), {end, std::nextafter(end, 0.0f), std::nextafter(end, 1.0f)});
  }
  for (int i = 0; i < 200; ++i) times.push_back(u(rng));
  for (const detail::KdLeafRef& r : tree.refs) times.insert(times.end(), {r.t0, r.t1});
  for (float t : times) {
    std::multiset<std::tuple<uint32_t, float, float>> alive, found;
    for (const detail::KdLeafRef& r : tree.refs)
      if (r.t0 <= t && t <= r.t1) alive.insert({prims[r.prim].primID, r.t0, r.t1});
    const detail::KdLeafBlocks::Range range = blocks.blocksAt(leaf, t);
    for (uint32_t k = range.begin; k < range.end; ++k)
      for (int lane = 0; lane < detail::kKdBlockLanes; ++lane) {
        const detail::KdLeafBlock& b = blocks.blocks[k];
        if (b.t0[lane] <= t && t <= b.t1[lane]) found.insert({b.prim[lane].primID, b.t0[lane], b.t1[lane]});
      }
    EXPECT_EQ(found, alive) << "time " << t;
  }
}

TEST(Mbkd, MemoryBudgetStopsTheBuild) {
  Rng rng(9);
  Scene scene;
  test::addRandomMovingTriangles(scene, rng, 2000, 3, 0.1f, 0.4f);
  BuildOptions o;
  o.kind = AccelKind::Mbkd;
  o.memoryBudget = 20000;
  EXPECT_THROW(Accel::build(scene, o), Error);
}

}  // namespace
