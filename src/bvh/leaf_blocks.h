// Leaf blocks of a static tree (`frozen`): each leaf whose references are
// all stored triangles (FixedTimeTriangles: plain triangles, no filter) is
// laid out as ceil(n / 4) blocks of four triangles with their vertices at
// the tree's time, structure of arrays, and tested a block at a time by
// intersectTriangleBlock (geometry/triangle_block.h). This is Embree's
// static leaf (Triangle4: the vertices gathered into the leaf, four
// triangles per SIMD test) under a tree whose SAH charges a leaf per block
// (BuildSettings::leafBlock), so that the leaves fill their blocks.
//
// The lanes keep the leaf's reference order and each lane is checked
// against the ray's mask as its geometry's run would be; candidates are
// taken in lane order against the shrinking tfar, so the hits (ties
// included) are exactly those of intersectLeaf testing the references one
// by one. The time-range check of the runs always passes here: the tree
// holds only geometries alive at its time, every ray is traced at that
// time, and blocks are used only when ray.time is it.
#pragma once

#include <algorithm>
#include <vector>

#include "scene/leaf_intersect.h"
#include "bvh/nodes/wide_bvh.h"
#include "core/huge_pages.h"
#include "geometry/triangle_block.h"

namespace mbrt::detail {

// The leaf block a tree's SAH charges (BuildSettings::leafBlock): four when
// at least 3/4 of the primitives can be tested in blocks (triangles here,
// or a static tree's segments, segment_leaf_blocks.h), else one (what is
// tested one by one, larger leaves of it only cost; `hair` per reference
// in the quick bench: 1.58 -> 11.4 primitive tests per ray).
inline int leafBlockWidth(size_t blockable, size_t primitives) {
  return 4 * blockable >= 3 * primitives ? kLeafBlockWidth : 1;
}

// The leaf block of a motion tree over the scene (`bvh-interp`, `stbvh`,
// `bvh-segments`): four when at least 3/4 of its primitives are triangles
// without a filter, which its leaves test four at a time (copied into
// motion blocks, motion_leaf_blocks.h, or gathered, testGatheredRun).
inline int triangleLeafBlockWidth(const SceneContext& ctx) {
  size_t triangles = 0, all = 0;
  for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id) {
    const Geometry& g = ctx.geometry(id);
    all += g.numPrimitives();
    if (g.type() == GeometryType::Triangles && !g.hasFilter()) triangles += g.numPrimitives();
  }
  return leafBlockWidth(triangles, all);
}

// Four triangles of one leaf: 192 bytes, three cache lines.
struct alignas(64) TriangleLeafBlock {
  TriangleBlock<kLeafBlockWidth> tri;
  uint32_t geomID[kLeafBlockWidth];
  uint32_t primID[kLeafBlockWidth];
  uint32_t mask[kLeafBlockWidth];  // each lane's geometry mask
};

// The blocks of a tree laid out with leafBlock = kLeafBlockWidth (layOut):
// every leaf starts at a multiple of four in the reference table, so block
// i holds references [4i, 4i + 4) and a leaf at `begin` has its blocks from
// begin / 4 on. Traversal reaches them from the node alone, with no map in
// between (a dependent load per leaf: 23% of the `frozen` traversal's
// samples on `crowd` sat on it). Blocks of leaves that cannot be blocked (a
// filtered geometry) are marked by geomID[0] = kNone.
struct TriangleLeafBlocks {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  float time = 0.0f;
  std::vector<TriangleLeafBlock> blocks;

  TriangleLeafBlocks() = default;
  // The blocks of every leaf of `bvh` (not kept in a node) whose references
  // all have stored triangles in `stored`, at `time`; none when the tree is
  // not laid out in blocks of four.
  template <int N>
  TriangleLeafBlocks(const SceneContext& ctx, const WideBvh<N, false>& bvh, const FixedTimeTriangles& stored,
                     float t)
      : time(t) {
    if (bvh.prims.size() % kLeafBlockWidth != 0 || bvh.inlineRefs != 0) return;
    bool aligned = true, any = false;
    forEachLeaf(bvh, stored, [&](uint32_t begin, uint32_t, bool blockable) {
      aligned = aligned && begin % kLeafBlockWidth == 0;
      any = any || blockable;
    });
    if (!aligned || !any) return;
    const size_t count = bvh.prims.size() / kLeafBlockWidth;
    ctx.budget().charge(count * sizeof(TriangleLeafBlock), "the frozen tree's leaf blocks");
    resizeOnHugePages(blocks, count);
    for (TriangleLeafBlock& b : blocks) b.geomID[0] = kNone;
    forEachLeaf(bvh, stored, [&](uint32_t begin, uint32_t n, bool blockable) {
      if (!blockable) return;
      for (uint32_t i = 0; i < n; i += kLeafBlockWidth) {
        TriangleLeafBlock& b = blocks[(begin + i) / kLeafBlockWidth];
        for (int lane = 0; lane < kLeafBlockWidth; ++lane) {
          // Lanes past the leaf's end repeat its last triangle (never tested).
          const PrimRef ref = bvh.prims[begin + std::min(i + uint32_t(lane), n - 1)];
          const Vec3f* p = stored.of(ref.geomID) + 3 * size_t(ref.primID);
          b.tri.set(lane, p[0], p[1], p[2]);
          b.geomID[lane] = ref.geomID;
          b.primID[lane] = ref.primID;
          b.mask[lane] = ctx.geometry(ref.geomID).mask();
        }
      }
    });
  }

  bool empty() const { return blocks.empty(); }
  // The first block of the leaf at reference `begin`, or null when that
  // leaf is tested one by one.
  const TriangleLeafBlock* of(uint32_t begin) const {
    const TriangleLeafBlock* b = &blocks[begin / kLeafBlockWidth];
    return b->geomID[0] == kNone ? nullptr : b;
  }
  size_t bytes() const { return blocks.size() * sizeof(TriangleLeafBlock); }

 private:
  // fn(first reference, count, blockable) for each leaf in the reference
  // table; blockable: all its references have stored triangles.
  template <int N, class Fn>
  static void forEachLeaf(const WideBvh<N, false>& bvh, const FixedTimeTriangles& stored, Fn&& fn) {
    for (const auto& node : bvh.nodes)
      for (int lane = 0; lane < N; ++lane) {
        if (!node.isLeaf(lane) || node.count[lane] == kInlineLeaf) continue;
        const uint32_t begin = node.child[lane], n = node.count[lane];
        bool all = true;
        for (uint32_t i = begin; i < begin + n; ++i) all = all && stored.of(bvh.prims[i].geomID) != nullptr;
        fn(begin, n, all);
      }
  }
};

namespace leaf_block {

// The blocks of a leaf of `count` triangles: onHit(hit) for each candidate
// hit in reference order, as testRun would call it; stops when onHit
// returns true. r is BlockRay(ray), made once per ray.
template <class OnHit>
inline bool testBlocks(const TriangleLeafBlock* blocks, uint32_t count, RayQuery& ray,
                       const BlockRay<kLeafBlockWidth>& r, OnHit&& onHit) {
  constexpr int W = kLeafBlockWidth;
  for (uint32_t first = 0; first < count; first += W, ++blocks) {
    const TriangleLeafBlock& b = *blocks;
    const uint32_t valid = nonZeroAndMask4(b.mask, ray.mask) & presentLanes(count - first);
    if (valid == 0) continue;
    const auto ref = [&b](int lane) { return PrimRef{b.geomID[lane], b.primID[lane]}; };
    if (testBlock(b.tri, valid, ref, ray, r, onHit)) return true;
  }
  return false;
}

// Closest hit among the leaf's triangles (as intersectLeaf).
inline bool intersectBlocks(const TriangleLeafBlock* blocks, uint32_t count, RayQuery& ray,
                            const BlockRay<kLeafBlockWidth>& r, Hit& hit) {
  return closestOf(ray, hit, [&](auto&& onHit) { return testBlocks(blocks, count, ray, r, onHit); });
}

// Any hit among the leaf's triangles (as occludedLeaf).
inline bool occludedBlocks(const TriangleLeafBlock* blocks, uint32_t count, RayQuery& ray,
                           const BlockRay<kLeafBlockWidth>& r) {
  return testBlocks(blocks, count, ray, r, [](const Hit&) { return true; });
}

}  // namespace leaf_block
}  // namespace mbrt::detail
