// What the leaf tests (test_leaf_runs.cpp, test_leaf_blocks.cpp,
// test_motion_blocks.cpp, test_gathered_runs.cpp, test_segment_blocks.cpp)
// share: a grid of triangles with shared edges, ties and degenerate
// triangles, rays aimed at its vertices, edges and insides, bit-exact hit
// comparison, and leaves laid out as a tree's.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "bvh/nodes/wide_bvh.h"
#include "core/ray_query.h"
#include "scene/primitive_intersect.h"
#include "scene/scene_context.h"
#include "mbrt/ray.h"
#include "mbrt/scene.h"

namespace mbrt::test {

inline bool sameBits(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline void expectSameHit(const Hit& a, const Hit& b, const std::string& what) {
  EXPECT_TRUE(sameBits(a.t, b.t) && sameBits(a.u, b.u) && sameBits(a.v, b.v)) << what;
  EXPECT_TRUE(sameBits(a.Ng.x, b.Ng.x) && sameBits(a.Ng.y, b.Ng.y) && sameBits(a.Ng.z, b.Ng.z)) << what;
  EXPECT_EQ(a.geomID, b.geomID) << what;
  EXPECT_EQ(a.primID, b.primID) << what;
}

// A grid of 2 * n * n triangles in the plane z = zOffset (shared edges),
// each triangle twice (ties), then `degenerate` triangles: a segment (its
// third vertex on the first edge) and a point, over `steps` steps (alive
// over `range`).
inline uint32_t addGrid(Scene& scene, int n, float scale, float zOffset, uint32_t steps, bool degenerate = false,
                        TimeRange range = {}) {
  std::vector<Triangle> tris;
  std::vector<std::vector<Vec3f>> pos(steps);
  for (uint32_t s = 0; s < steps; ++s)
    for (int y = 0; y <= n; ++y)
      for (int x = 0; x <= n; ++x)
        pos[s].push_back(Vec3f{float(x) / float(n) * 2 - 1 + 0.1f * float(s), float(y) / float(n) * 2 - 1,
                               zOffset} * scale);
  const auto at = [n](int x, int y) { return uint32_t(y * (n + 1) + x); };
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      for (int copy = 0; copy < 2; ++copy) {
        tris.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
        tris.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
      }
      if (degenerate) {
        tris.push_back({at(x, y), at(x + 1, y + 1), at(x, y)});
        tris.push_back({at(x, y), at(x, y), at(x, y)});
      }
    }
  return scene.addTriangleMesh(std::move(tris), std::move(pos), range);
}

// A ray towards a vertex of triangle `prim` (through shared edges and
// corners), the middle of its first edge, or a random point of it, from a
// random origin above the grid.
inline detail::RayQuery rayTowards(std::mt19937& rng, const Geometry& g, uint32_t prim, float scale, float time) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f), w(0.0f, 1.0f);
  const Triangle& tri = g.triangles()[prim];
  const Vec3f v0 = g.vertexAt(time, tri.v0), v1 = g.vertexAt(time, tri.v1), v2 = g.vertexAt(time, tri.v2);
  Vec3f target = v0;
  const uint32_t where = rng() % 3;
  if (where == 1) target = (v0 + v1) * 0.5f;
  if (where == 2) {
    const float a = w(rng), b = w(rng) * (1 - a);
    target = v0 + (v1 - v0) * a + (v2 - v0) * b;
  }
  Ray r;
  r.org = target + Vec3f{u(rng), u(rng), 2 + u(rng)} * scale;
  r.dir = target - r.org;
  r.time = time;
  return detail::RayQuery(r);
}

// A mask that leaves out some geometries of the grids (masks 1, 2, 3), and
// on every third trial a tfar that may end before the hit.
inline void varyMaskAndTfar(std::mt19937& rng, int trial, detail::RayQuery& ray) {
  const uint32_t masks[] = {~0u, 1u, 2u, 4u};
  ray.mask = masks[rng() % 4];
  if (trial % 3 == 0) ray.tfar = std::uniform_real_distribution<float>(0.5f, 1.0f)(rng);
}

// What testing a leaf's references one by one finds, the oracle of the
// leaf tests: intersectPrimitive on each in order (the closest hit and the
// tfar it leaves) and occludedPrimitive on each.
struct OneByOne {
  bool found = false, occluded = false;
  Hit hit;
  detail::RayQuery ray;
};
inline OneByOne oneByOne(const detail::SceneContext& ctx, std::span<const detail::PrimRef> prims,
                         const detail::RayQuery& ray) {
  OneByOne out{false, false, Hit(), ray};
  for (const detail::PrimRef& p : prims) {
    out.found |= detail::intersectPrimitive(ctx, p, out.ray, out.hit);
    out.occluded = out.occluded || detail::occludedPrimitive(ctx, p, ray);
  }
  return out;
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

// The grids of the motion-leaf tests: 5, 2 and 1 steps (one alive over
// part of the shutter only), masks 1 to 3, and one beyond float's
// edge-function range (the double path).
inline void addMotionGrids(Scene& scene) {
  scene.setMask(addGrid(scene, 5, 1.0f, 0.0f, 5, true), 1u);
  scene.setMask(addGrid(scene, 5, 1.0f, 0.0f, 2, false, {0.25f, 0.75f}), 2u);
  scene.setMask(addGrid(scene, 4, 1.0f, 0.25f, 1, true), 3u);
  addGrid(scene, 3, 1e13f, 0.5f, 3, true);
}

// A leaf of 1 to 13 references of geometry g: consecutive triangles, a
// quarter of them replaced by any other.
inline std::vector<detail::PrimRef> drawLeaf(std::mt19937& rng, const Geometry& g, uint32_t geomID) {
  const uint32_t numTris = uint32_t(g.triangles().size());
  const uint32_t count = 1 + rng() % 13;
  const uint32_t first = rng() % (numTris - count);
  std::vector<detail::PrimRef> refs;
  for (uint32_t i = 0; i < count; ++i) refs.push_back({geomID, uint32_t(rng() % 4 == 0 ? rng() % numTris : first + i)});
  return refs;
}

}  // namespace mbrt::test
