// Leaf blocks of a motion tree (`bvh-interp`; also the static tree of a
// near-rigid cluster, cluster_bvh.h, whose leaves move): each leaf whose
// references are all triangles of one geometry without a filter keeps, per
// block of four, the four triangles' vertices at every step of the geometry
// (TriangleBlock: structure of arrays, world axes). The test interpolates
// the ray's two steps in the block, lane by lane with the arithmetic of
// leaf_run::VerticesAt (lerp: a * (1 - f) + b * f, no FMA), then runs the
// block test of leaf_blocks.h, so hits are those of intersectLeaf. The
// leaf's mask and time range are its geometry's, checked once as the run
// would. (Embree's motion-blur leaves, Triangle4vMB, likewise keep the
// vertices of a time segment's two ends.)
#pragma once

#include <algorithm>
#include <vector>

#include "bvh/leaf_blocks.h"

namespace mbrt::detail {

// Found as TriangleLeafBlocks finds its blocks: the tree is laid out with
// leafBlock = kLeafBlockWidth (layOut), every leaf starting at a multiple of
// four in the reference table, so the leaf at `begin` is leaves[begin / 4]
// (one entry per four table entries, 3 bytes per reference), read from the
// node with no map in between; geomID = kNone marks a slot without blocks.
struct MotionLeafBlocks {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  struct Leaf {
    uint32_t geomID = kNone;
    uint32_t steps = 0;  // the geometry's vertex steps
    uint32_t first = 0;  // index in `blocks` of block 0 at step 0; block b at step k: first + b * steps + k
  };
  std::vector<Leaf> leaves;  // per four entries of the reference table
  std::vector<TriangleBlock<kLeafBlockWidth>> blocks;

  MotionLeafBlocks() = default;
  // The blocks of every leaf of `bvh` in the reference table whose
  // references are all triangles of one geometry without a filter; none
  // when the tree is not laid out in blocks of four.
  template <int N, bool Motion>
  MotionLeafBlocks(const SceneContext& ctx, const WideBvh<N, Motion>& bvh) {
    constexpr uint32_t W = kLeafBlockWidth;
    if (bvh.prims.size() % W != 0 || bvh.inlineRefs != 0) return;
    size_t count = 0;
    bool aligned = true;
    forEachLeaf(ctx, bvh, [&](uint32_t begin, uint32_t n, const Geometry* g) {
      aligned = aligned && begin % W == 0;
      if (g) count += (n + W - 1) / W * g->numSteps();
    });
    if (!aligned || count == 0 || count >= kNone) return;
    const size_t slots = bvh.prims.size() / W;
    ctx.budget().charge(bytesFor(slots, count), "the motion tree's leaf blocks");
    resizeOnHugePages(leaves, slots);
    resizeOnHugePages(blocks, count);
    uint32_t next = 0;
    forEachLeaf(ctx, bvh, [&](uint32_t begin, uint32_t n, const Geometry* g) {
      if (!g) return;
      leaves[begin / W] = {bvh.prims[begin].geomID, g->numSteps(), next};
      const std::span<const Triangle> tris = g->triangles();
      for (uint32_t i = 0; i < n; i += W)
        for (uint32_t k = 0; k < g->numSteps(); ++k, ++next) {
          const VertexBuffer& v = g->vertices(k);
          for (uint32_t lane = 0; lane < W; ++lane) {
            // Lanes past the leaf's end repeat its last triangle (never tested).
            const Triangle& t = tris[bvh.prims[begin + std::min(i + lane, n - 1)].primID];
            blocks[next].set(int(lane), v[t.v0], v[t.v1], v[t.v2]);
          }
        }
    });
  }

  bool empty() const { return blocks.empty(); }
  // The blocked leaf at reference `begin`, or null.
  const Leaf* of(uint32_t begin) const {
    const Leaf* l = &leaves[begin / kLeafBlockWidth];
    return l->geomID == kNone ? nullptr : l;
  }
  size_t bytes() const { return bytesFor(leaves.size(), blocks.size()); }

 private:
  static size_t bytesFor(size_t slots, size_t numBlocks) {
    return slots * sizeof(Leaf) + numBlocks * sizeof(TriangleBlock<kLeafBlockWidth>);
  }
  // fn(first reference, count, geometry) for each leaf in the reference
  // table; the geometry is null unless all its references are triangles of
  // that one geometry without a filter.
  template <int N, bool Motion, class Fn>
  static void forEachLeaf(const SceneContext& ctx, const WideBvh<N, Motion>& bvh, Fn&& fn) {
    for (const auto& node : bvh.nodes)
      for (int lane = 0; lane < N; ++lane) {
        if (!node.isLeaf(lane) || node.count[lane] == kInlineLeaf) continue;
        const uint32_t begin = node.child[lane], n = node.count[lane];
        const uint32_t geomID = bvh.prims[begin].geomID;
        const Geometry& g = ctx.geometry(geomID);
        bool one = g.type() == GeometryType::Triangles && !g.hasFilter();
        for (uint32_t i = begin; one && i < begin + n; ++i) one = bvh.prims[i].geomID == geomID;
        fn(begin, n, one ? &g : nullptr);
      }
  }
};

namespace leaf_block {

// The leaf's triangles at the ray's time: onHit(hit) for each candidate
// hit in reference order, as testRun would call it; stops when onHit
// returns true. `prims`: the leaf's `count` references.
template <class OnHit>
inline bool testMotionBlocks(const SceneContext& ctx, const MotionLeafBlocks& mb, const MotionLeafBlocks::Leaf& leaf,
                             const PrimRef* prims, uint32_t count, RayQuery& ray, const BlockRay<kLeafBlockWidth>& r,
                             OnHit&& onHit) {
  using P = Pack<kLeafBlockWidth>;
  constexpr int W = kLeafBlockWidth;
  const Geometry& g = ctx.geometry(leaf.geomID);
  if ((g.mask() & ray.mask) == 0 || !g.timeRange().contains(ray.time)) return false;  // as the run's check
  uint32_t s;
  float f;
  g.segmentAt(ray.time, s, f);  // as VerticesAt
  const P w0 = P::set1(1.0f - f), w1 = P::set1(f);
  const TriangleBlock<W>* b = mb.blocks.data() + leaf.first;
  alignas(4 * W) TriangleBlock<W> at;  // the block at the ray's time
  for (uint32_t first = 0; first < count; first += W, b += leaf.steps) {
    const TriangleBlock<W>* tri = b;
    if (leaf.steps > 1) {
      const TriangleBlock<W>&a = b[s], &c = b[s + 1];
      for (int k = 0; k < 3; ++k)
        for (int axis = 0; axis < 3; ++axis)
          (P::load(a.p[k][axis]) * w0 + P::load(c.p[k][axis]) * w1).store(at.p[k][axis]);
      tri = &at;
    }
    const auto ref = [prims, first](int lane) { return prims[first + uint32_t(lane)]; };
    if (testBlock(*tri, presentLanes(count - first), ref, ray, r, onHit)) return true;
  }
  return false;
}

inline bool intersectMotionBlocks(const SceneContext& ctx, const MotionLeafBlocks& mb,
                                  const MotionLeafBlocks::Leaf& leaf, const PrimRef* prims, uint32_t count,
                                  RayQuery& ray, const BlockRay<kLeafBlockWidth>& r, Hit& hit) {
  return closestOf(ray, hit,
                   [&](auto&& onHit) { return testMotionBlocks(ctx, mb, leaf, prims, count, ray, r, onHit); });
}

inline bool occludedMotionBlocks(const SceneContext& ctx, const MotionLeafBlocks& mb,
                                 const MotionLeafBlocks::Leaf& leaf, const PrimRef* prims, uint32_t count,
                                 RayQuery& ray, const BlockRay<kLeafBlockWidth>& r) {
  return testMotionBlocks(ctx, mb, leaf, prims, count, ray, r, [](const Hit&) { return true; });
}

}  // namespace leaf_block
}  // namespace mbrt::detail
