// Segment blocks of a static tree (`frozen`): the counterpart of
// triangle_blocks.h for trees of mostly round segments (hair). Each leaf
// whose references are all segments of geometries without a filter is laid
// out as ceil(n / 4) blocks of four segments, their end points at the
// tree's time (leaf_run::VerticesAt, the values the reference test
// interpolates) and their radii, structure of arrays; the block test
// (geometry/segment_block.h) sorts out the lanes whose line misses the
// solid four at a time and hands the rest to intersectSegment in lane
// order, so the hits (ties included) are exactly those of the reference
// test. Found from the leaf alone, as the triangle blocks are: every leaf
// starts at a multiple of four in the reference table and block i holds
// references [4i, 4i + 4).
#pragma once

#include <vector>

#include "core/huge_pages.h"
#include "leaves/leaf_width.h"
#include "leaves/reference_leaves.h"

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

class SegmentBlockLeaves {
 public:
  using RayState = LeafBlockRay;
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  SegmentBlockLeaves() = default;
  // The blocks of every leaf in the table whose references are all
  // segments that blocksSegments takes, at the table's fixed time; none
  // when the tree is not laid out in blocks of four.
  SegmentBlockLeaves(const SceneContext& ctx, const LeafTable& table) : time_(table.fixedTime.value()) {
    constexpr uint32_t W = kLeafBlockWidth;
    if (!laidOutInBlocks(table)) return;
    bool any = false;
    for (const LeafRange& l : table.leaves) any = any || blockable(ctx, table, l);
    if (!any) return;
    const size_t count = table.prims.size() / W;
    ctx.budget().charge(count * sizeof(SegmentLeafBlock), "the frozen tree's segment blocks");
    resizeOnHugePages(blocks_, count);
    for (SegmentLeafBlock& b : blocks_) b.geomID[0] = kNone;
    for (const LeafRange& l : table.leaves) {
      if (!blockable(ctx, table, l)) continue;
      for (uint32_t i = 0; i < l.count; i += W) {
        SegmentLeafBlock& b = blocks_[(l.begin + i) / W];
        for (uint32_t lane = 0; lane < W; ++lane) {
          // Lanes past the leaf's end repeat its last segment (never tested).
          const PrimRef ref = table.prims[l.begin + std::min(i + lane, l.count - 1)];
          const Geometry& g = ctx.geometry(ref.geomID);
          const leaf_run::VerticesAt at(g, time_);
          const Segment& s = g.segments()[ref.primID];
          b.seg.set(int(lane), at[s.v0], at[s.v1], g.radii()[s.v0], g.radii()[s.v1]);
          b.geomID[lane] = ref.geomID;
          b.primID[lane] = ref.primID;
          b.mask[lane] = g.mask();
        }
      }
    }
  }

  RayState rayState(const RayQuery& ray) const { return LeafBlockRay(ray); }
  template <bool AnyHit, bool Count>
  bool test(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const RayState& r, Hit* hit,
            TraversalCounters* counters) const {
    if (const SegmentLeafBlock* b = of(leaf, ray)) {
      if constexpr (Count) counters->blockPrimitiveTests += leaf.count;
      const SegmentBlockRay<kLeafBlockWidth>& sr = r.segments(ray);
      if constexpr (AnyHit) return testBlocks(b, leaf.count, ray, sr, [](const Hit&) { return true; });
      else return leaf_block::closestOf(ray, *hit, [&](auto&& onHit) { return testBlocks(b, leaf.count, ray, sr, onHit); });
    }
    return testReferences<AnyHit, Count>(ctx, leaf, ray, r, hit, counters);
  }
  size_t bytes() const { return blocks_.size() * sizeof(SegmentLeafBlock); }

  // Inspection, as TriangleBlockLeaves'.
  bool empty() const { return blocks_.empty(); }
  size_t blockCount() const { return blocks_.size(); }
  const SegmentLeafBlock* blocksOf(uint32_t first) const {
    if (blocks_.empty()) return nullptr;
    const SegmentLeafBlock* b = &blocks_[first / kLeafBlockWidth];
    return b->geomID[0] == kNone ? nullptr : b;
  }

 private:
  const SegmentLeafBlock* of(const LeafRefs& leaf, const RayQuery& ray) const {
    return leaf.inTable() && ray.time == time_ ? blocksOf(leaf.first) : nullptr;
  }
  bool blockable(const SceneContext& ctx, const LeafTable& table, const LeafRange& l) const {
    for (uint32_t i = l.begin; i < l.begin + l.count; ++i)
      if (!blocksSegments(ctx.geometry(table.prims[i].geomID), time_)) return false;
    return true;
  }
  // The blocks of a leaf of `count` segments: onHit(hit) for each hit in
  // reference order, as testRun would call it; stops when onHit returns
  // true.
  template <class OnHit>
  static bool testBlocks(const SegmentLeafBlock* blocks, uint32_t count, RayQuery& ray,
                         const SegmentBlockRay<kLeafBlockWidth>& r, OnHit&& onHit) {
    constexpr int W = kLeafBlockWidth;
    for (uint32_t first = 0; first < count; first += W, ++blocks) {
      const SegmentLeafBlock& b = *blocks;
      const uint32_t valid = nonZeroAndMask4(b.mask, ray.mask) & leaf_block::presentLanes(count - first);
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

  float time_ = 0.0f;
  std::vector<SegmentLeafBlock> blocks_;
};

}  // namespace mbrt::detail
