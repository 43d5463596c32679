// Triangle blocks of a static tree (`frozen`): each leaf whose references
// are all stored triangles (FixedTimeTriangles: plain triangles, no filter)
// is laid out as ceil(n / 4) blocks of four triangles with their vertices
// at the tree's time, structure of arrays, and tested a block at a time by
// intersectTriangleBlock (geometry/triangle_block.h). This is Embree's
// static leaf (Triangle4: the vertices gathered into the leaf, four
// triangles per SIMD test) under a tree whose SAH charges a leaf per block
// (leaf_width.h), so that the leaves fill their blocks.
//
// The lanes keep the leaf's reference order and each lane is checked
// against the ray's mask as its geometry's run would be; candidates are
// taken in lane order against the shrinking tfar, so the hits (ties
// included) are exactly those of the reference test (reference_leaves.h).
// The time-range check of the runs always passes here: the tree holds only
// geometries alive at its time, and blocks are used only when ray.time is
// it. The blocks are found from the leaf alone: every leaf starts at a
// multiple of four in the reference table, so block i holds references
// [4i, 4i + 4), a dependent load per leaf less than a map from leaf to
// blocks (docs/performance.md, "Leaf blocks for `frozen`").
#pragma once

#include <algorithm>
#include <vector>

#include "core/huge_pages.h"
#include "leaves/fixed_time_triangles.h"
#include "leaves/leaf_width.h"

namespace mbrt::detail {

// Four triangles of one leaf: 192 bytes, three cache lines.
struct alignas(64) TriangleLeafBlock {
  TriangleBlock<kLeafBlockWidth> tri;
  uint32_t geomID[kLeafBlockWidth];
  uint32_t primID[kLeafBlockWidth];
  uint32_t mask[kLeafBlockWidth];  // each lane's geometry mask
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

}  // namespace leaf_block

// The format. Blocks of leaves that cannot be blocked (a filtered geometry)
// are marked by geomID[0] = kNone and tested as references; none are laid
// out when the tree is not laid out in blocks of four.
class TriangleBlockLeaves {
 public:
  using RayState = LeafBlockRay;
  static constexpr uint32_t kNone = 0xFFFFFFFFu;

  TriangleBlockLeaves() = default;
  TriangleBlockLeaves(const SceneContext& ctx, const LeafTable& table) : time_(table.fixedTime.value()) {
    if (!laidOutInBlocks(table)) return;
    // The triangles at the tree's time, only while the blocks are made.
    const FixedTimeTriangles stored(ctx, time_);
    bool any = false;
    for (const LeafRange& l : table.leaves) any = any || blockable(table, l, stored);
    if (any) layOut(ctx, table, stored);
    ctx.budget().release(stored.vertices.size() * sizeof(Vec3f));
  }

  RayState rayState(const RayQuery& ray) const { return LeafBlockRay(ray); }
  template <bool AnyHit, bool Count>
  bool test(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const RayState& r, Hit* hit,
            TraversalCounters* counters) const {
    if (const TriangleLeafBlock* b = of(leaf, ray)) {
      if constexpr (Count) counters->blockPrimitiveTests += leaf.count;
      if constexpr (AnyHit) return leaf_block::testBlocks(b, leaf.count, ray, r, [](const Hit&) { return true; });
      else
        return leaf_block::closestOf(
            ray, *hit, [&](auto&& onHit) { return leaf_block::testBlocks(b, leaf.count, ray, r, onHit); });
    }
    return testReferences<AnyHit, Count>(ctx, leaf, ray, r, hit, counters);
  }
  size_t bytes() const { return blocks_.size() * sizeof(TriangleLeafBlock); }

  // Inspection: whether any leaf is blocked, the blocks laid out, and the
  // first block of the leaf at table entry `first` (null: tested as
  // references).
  bool empty() const { return blocks_.empty(); }
  size_t blockCount() const { return blocks_.size(); }
  const TriangleLeafBlock* blocksOf(uint32_t first) const {
    if (blocks_.empty()) return nullptr;
    const TriangleLeafBlock* b = &blocks_[first / kLeafBlockWidth];
    return b->geomID[0] == kNone ? nullptr : b;
  }

 private:
  const TriangleLeafBlock* of(const LeafRefs& leaf, const RayQuery& ray) const {
    return leaf.inTable() && ray.time == time_ ? blocksOf(leaf.first) : nullptr;
  }
  static bool blockable(const LeafTable& table, const LeafRange& l, const FixedTimeTriangles& stored) {
    for (uint32_t i = l.begin; i < l.begin + l.count; ++i)
      if (!stored.of(table.prims[i].geomID)) return false;
    return true;
  }
  void layOut(const SceneContext& ctx, const LeafTable& table, const FixedTimeTriangles& stored) {
    const size_t count = table.prims.size() / kLeafBlockWidth;
    ctx.budget().charge(count * sizeof(TriangleLeafBlock), "the frozen tree's leaf blocks");
    resizeOnHugePages(blocks_, count);
    for (TriangleLeafBlock& b : blocks_) b.geomID[0] = kNone;
    for (const LeafRange& l : table.leaves) {
      if (!blockable(table, l, stored)) continue;
      for (uint32_t i = 0; i < l.count; i += kLeafBlockWidth) {
        TriangleLeafBlock& b = blocks_[(l.begin + i) / kLeafBlockWidth];
        for (int lane = 0; lane < kLeafBlockWidth; ++lane) {
          // Lanes past the leaf's end repeat its last triangle (never tested).
          const PrimRef ref = table.prims[l.begin + std::min(i + uint32_t(lane), l.count - 1)];
          const Vec3f* p = stored.of(ref.geomID) + 3 * size_t(ref.primID);
          b.tri.set(lane, p[0], p[1], p[2]);
          b.geomID[lane] = ref.geomID;
          b.primID[lane] = ref.primID;
          b.mask[lane] = ctx.geometry(ref.geomID).mask();
        }
      }
    }
  }

  float time_ = 0.0f;
  std::vector<TriangleLeafBlock> blocks_;
};

}  // namespace mbrt::detail
