// The leaf test of the BVH kinds (bvh/leaf_intersect.h: runs of one
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

#include "bvh/leaf_intersect.h"
#include "scene/scene_context.h"
#include "test_util.h"

namespace mbrt {
namespace {

bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expectSameHit(const Hit& a, const Hit& b, const std::string& what) {
  EXPECT_TRUE(sameBits(a.t, b.t) && sameBits(a.u, b.u) && sameBits(a.v, b.v)) << what;
  EXPECT_TRUE(sameBits(a.Ng.x, b.Ng.x) && sameBits(a.Ng.y, b.Ng.y) && sameBits(a.Ng.z, b.Ng.z)) << what;
  EXPECT_EQ(a.geomID, b.geomID) << what;
  EXPECT_EQ(a.primID, b.primID) << what;
}

// A grid of 2 * n * n triangles in the plane z = zOffset (shared edges),
// each triangle twice (ties), moving along x over `steps` steps.
uint32_t addGrid(Scene& scene, int n, float scale, float zOffset, uint32_t steps) {
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> pos(steps);
  for (uint32_t s = 0; s < steps; ++s)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x)
        pos[s].push_back(Vec3f{float(x) / float(n) * 2 - 1 + 0.1f * float(s), float(y) / float(n) * 2 - 1,
                               zOffset} * scale);
  const auto at = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int copy = 0; copy < 2; ++copy) {
        tris.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
        tris.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
      }
  return scene.addTriangleMesh(std::move(tris), std::move(pos));
}

// A ray towards a vertex of triangle `prim` (through shared edges and
// corners) or a random point of it, from a random origin above the grid.
detail::RayQuery rayTowards(std::mt19937& rng, const Geometry& g, uint32_t prim, float scale, float time) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  const Triangle& tri = g.triangles()[prim];
  const Vec3f v0 = g.vertexAt(time, tri.v0), v1 = g.vertexAt(time, tri.v1), v2 = g.vertexAt(time, tri.v2);
  Vec3f target = v0;
  if (rng() % 2) {
    const float a = w(rng), b = w(rng) * (1 - a);
    target = v0 + (v1 - v0) * a + (v2 - v0) * b;
  }
  Ray r;
  r.org = target + Vec3f{u(rng), u(rng), 2 + u(rng)} * scale;
  r.dir = target - r.org;
  r.time = time;
  return detail::RayQuery(r);
}

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
    const detail::FixedTimeTriangles* source = stored ? &fixed : nullptr;
    const std::string what = "trial " + std::to_string(trial) + ", " + std::to_string(count) + " references";
    ASSERT_EQ(detail::intersectLeaf<true>(ctx, prims, count, leaf, got, nullptr, source), found) << what;
    EXPECT_TRUE(sameBits(leaf.tfar, one.tfar)) << what;
    if (found) expectSameHit(got, expected, what);
    EXPECT_EQ(detail::occludedLeaf<true>(ctx, prims, count, anyRay, source), occluded) << what;
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
