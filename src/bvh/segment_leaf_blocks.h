// Segment leaf blocks of a static tree (`frozen`): the counterpart of
// leaf_blocks.h for trees of mostly round segments (hair). Each leaf whose
// references are all segments of geometries without a filter is laid out
// as ceil(n / 4) blocks of four segments, their end points at the tree's
// time (leaf_run::VerticesAt, the values the per-reference test
// interpolates) and their radii, structure of arrays; the block test
// (geometry/segment_block.h) sorts out the lanes whose line misses the
// solid four at a time and hands the rest to intersectSegment in lane
// order, so the hits (ties included) are exactly those of intersectLeaf.
// Found from the node alone, as the triangle blocks are: every leaf starts
// at a multiple of four in the reference table and block i holds
// references [4i, 4i + 4).
#pragma once

#include <vector>

#include "bvh/leaf_blocks.h"
#include "geometry/segment_block.h"

namespace mbrt::detail {

// Four segments of one leaf: 176 bytes, padded to three cache lines.
struct alignas(64) SegmentLeafBlock {
  SegmentBlock<kLeafBlockWidth> seg;
  uint32_t geomID[kLeafBlockWidth];
  uint32_t primID[kLeafBlockWidth];
  uint32_t mask[kLeafBlockWidth];  // each lane's geometry mask
};

// A plain segment geometry (no filter) alive at `time`: its segments go
// into blocks.
inline bool blocksSegments(const Geometry& g, float time) {
  return g.type() == GeometryType::Segments && !g.hasFilter() && g.timeRange().contains(time);
}

struct SegmentLeafBlocks {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  float time = 0.0f;
  std::vector<SegmentLeafBlock> blocks;

  SegmentLeafBlocks() = default;
  // The blocks of every leaf of `bvh` (not kept in a node) whose references
  // are all segments that blocksSegments takes, at `time`; none when the
  // tree is not laid out in blocks of four.
  template <int N>
  SegmentLeafBlocks(const SceneContext& ctx, const WideBvh<N, false>& bvh, float t) : time(t) {
    constexpr uint32_t W = kLeafBlockWidth;
    if (bvh.prims.size() % W != 0 || bvh.inlineRefs != 0) return;
    bool aligned = true, any = false;
    forEachLeaf(ctx, bvh, [&](uint32_t begin, uint32_t, bool blockable) {
      aligned = aligned && begin % W == 0;
      any = any || blockable;
    });
    if (!aligned || !any) return;
    const size_t count = bvh.prims.size() / W;
    ctx.budget().charge(count * sizeof(SegmentLeafBlock), "the frozen tree's segment blocks");
    resizeOnHugePages(blocks, count);
    for (SegmentLeafBlock& b : blocks) b.geomID[0] = kNone;
    forEachLeaf(ctx, bvh, [&](uint32_t begin, uint32_t n, bool blockable) {
      if (!blockable) return;
      for (uint32_t i = 0; i < n; i += W) {
        SegmentLeafBlock& b = blocks[(begin + i) / W];
        for (uint32_t lane = 0; lane < W; ++lane) {
          // Lanes past the leaf's end repeat its last segment (never tested).
          const PrimRef ref = bvh.prims[begin + std::min(i + lane, n - 1)];
          const Geometry& g = ctx.geometry(ref.geomID);
          const leaf_run::VerticesAt at(g, time);
          const Segment& s = g.segments()[ref.primID];
          b.seg.set(int(lane), at[s.v0], at[s.v1], g.radii()[s.v0], g.radii()[s.v1]);
          b.geomID[lane] = ref.geomID;
          b.primID[lane] = ref.primID;
          b.mask[lane] = g.mask();
        }
      }
    });
  }

  bool empty() const { return blocks.empty(); }
  // The first block of the leaf at reference `begin`, or null when that
  // leaf is tested one by one.
  const SegmentLeafBlock* of(uint32_t begin) const {
    const SegmentLeafBlock* b = &blocks[begin / kLeafBlockWidth];
    return b->geomID[0] == kNone ? nullptr : b;
  }
  size_t bytes() const { return blocks.size() * sizeof(SegmentLeafBlock); }

 private:
  // fn(first reference, count, blockable) for each leaf in the reference
  // table.
  template <int N, class Fn>
  void forEachLeaf(const SceneContext& ctx, const WideBvh<N, false>& bvh, Fn&& fn) const {
    for (const auto& node : bvh.nodes)
      for (int lane = 0; lane < N; ++lane) {
        if (!node.isLeaf(lane) || node.count[lane] == kInlineLeaf) continue;
        const uint32_t begin = node.child[lane], n = node.count[lane];
        bool all = true;
        for (uint32_t i = begin; i < begin + n && all; ++i) all = blocksSegments(ctx.geometry(bvh.prims[i].geomID), time);
        fn(begin, n, all);
      }
  }
};

namespace leaf_block {

// The blocks of a leaf of `count` segments: onHit(hit) for each hit in
// reference order, as testRun would call it; stops when onHit returns
// true. r is SegmentBlockRay(ray), made once per ray.
template <class OnHit>
inline bool testSegmentBlocks(const SegmentLeafBlock* blocks, uint32_t count, RayQuery& ray,
                              const SegmentBlockRay<kLeafBlockWidth>& r, OnHit&& onHit) {
  constexpr int W = kLeafBlockWidth;
  for (uint32_t first = 0; first < count; first += W, ++blocks) {
    const SegmentLeafBlock& b = *blocks;
    const uint32_t valid = nonZeroAndMask4(b.mask, ray.mask) & presentLanes(count - first);
    for (uint32_t todo = segmentBlockCandidates(r, b.seg, valid); todo != 0; todo &= todo - 1) {
      const int lane = __builtin_ctz(todo);
      SegmentHit sh;
      if (!intersectSegment(ray, b.seg.end(0, lane), b.seg.end(1, lane), b.seg.radius(0, lane),
                            b.seg.radius(1, lane), sh))
        continue;
      if (onHit(leaf_detail::segmentHit(PrimRef{b.geomID[lane], b.primID[lane]}, sh))) return true;
    }
  }
  return false;
}

// Closest hit among the leaf's segments (as intersectLeaf).
inline bool intersectSegmentBlocks(const SegmentLeafBlock* blocks, uint32_t count, RayQuery& ray,
                                   const SegmentBlockRay<kLeafBlockWidth>& r, Hit& hit) {
  return closestOf(ray, hit, [&](auto&& onHit) { return testSegmentBlocks(blocks, count, ray, r, onHit); });
}

// Any hit among the leaf's segments (as occludedLeaf).
inline bool occludedSegmentBlocks(const SegmentLeafBlock* blocks, uint32_t count, RayQuery& ray,
                                  const SegmentBlockRay<kLeafBlockWidth>& r) {
  return testSegmentBlocks(blocks, count, ray, r, [](const Hit&) { return true; });
}

}  // namespace leaf_block
}  // namespace mbrt::detail
