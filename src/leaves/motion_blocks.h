// Motion blocks (`bvh-interp`; also the static tree of a near-rigid cluster,
// bvh/kinds/cluster_bvh.h, whose leaves move): each leaf whose references
// are all triangles of one geometry without a filter keeps, per block of
// four, the four triangles' vertices at every step of the geometry
// (TriangleBlock: structure of arrays, world axes). The test interpolates
// the ray's two steps in the block, lane by lane with the arithmetic of
// leaf_run::VerticesAt (lerp: a * (1 - f) + b * f, no FMA), then runs the
// block test of gathered_runs.h, so hits are those of the reference test.
// The leaf's mask and time range are its geometry's, checked once as the
// run would. (Embree's motion-blur leaves, Triangle4vMB, likewise keep the
// vertices of a time segment's two ends.)
//
// Found as the triangle blocks are (triangle_blocks.h): every leaf starts at
// a multiple of four in the reference table, so the leaf at `begin` is
// leaves[begin / 4] (one entry per four table entries, 3 bytes per
// reference), read from the leaf with no map in between; geomID = kNone
// marks a slot without blocks.
#pragma once

#include <algorithm>
#include <vector>

#include "core/huge_pages.h"
#include "leaves/leaf_width.h"
#include "leaves/reference_leaves.h"

namespace mbrt::detail {

class MotionBlockLeaves {
 public:
  using RayState = LeafBlockRay;
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  struct Leaf {
    uint32_t geomID = kNone;
    uint32_t steps = 0;  // the geometry's vertex steps
    uint32_t first = 0;  // index in `blocks` of block 0 at step 0; block b at step k: first + b * steps + k
  };

  MotionBlockLeaves() = default;
  // The blocks of every leaf in the table whose references are all
  // triangles of one geometry without a filter; none when the tree is not
  // laid out in blocks of four.
  MotionBlockLeaves(const SceneContext& ctx, const LeafTable& table) {
    constexpr uint32_t W = kLeafBlockWidth;
    if (!laidOutInBlocks(table)) return;
    size_t count = 0;
    for (const LeafRange& l : table.leaves)
      if (const Geometry* g = oneGeometry(ctx, table, l)) count += (l.count + W - 1) / W * g->numSteps();
    if (count == 0 || count >= kNone) return;
    const size_t slots = table.prims.size() / W;
    ctx.budget().charge(bytesFor(slots, count), "the motion tree's leaf blocks");
    resizeOnHugePages(leaves_, slots);
    resizeOnHugePages(blocks_, count);
    uint32_t next = 0;
    for (const LeafRange& l : table.leaves) {
      const Geometry* g = oneGeometry(ctx, table, l);
      if (!g) continue;
      leaves_[l.begin / W] = {table.prims[l.begin].geomID, g->numSteps(), next};
      const std::span<const Triangle> tris = g->triangles();
      for (uint32_t i = 0; i < l.count; i += W)
        for (uint32_t k = 0; k < g->numSteps(); ++k, ++next) {
          const VertexBuffer& v = g->vertices(k);
          for (uint32_t lane = 0; lane < W; ++lane) {
            // Lanes past the leaf's end repeat its last triangle (never tested).
            const Triangle& t = tris[table.prims[l.begin + std::min(i + lane, l.count - 1)].primID];
            blocks_[next].set(int(lane), v[t.v0], v[t.v1], v[t.v2]);
          }
        }
    }
  }

  RayState rayState(const RayQuery& ray) const { return LeafBlockRay(ray); }
  template <bool AnyHit, bool Count>
  bool test(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const RayState& r, Hit* hit,
            TraversalCounters* counters) const {
    if (const Leaf* l = of(leaf)) {
      if constexpr (Count) counters->blockPrimitiveTests += leaf.count;
      if constexpr (AnyHit) return testBlocks(ctx, *l, leaf, ray, r, [](const Hit&) { return true; });
      else
        return leaf_block::closestOf(ray, *hit,
                                     [&](auto&& onHit) { return testBlocks(ctx, *l, leaf, ray, r, onHit); });
    }
    return testReferences<AnyHit, Count>(ctx, leaf, ray, r, hit, counters);
  }
  size_t bytes() const { return bytesFor(leaves_.size(), blocks_.size()); }

  // Inspection: whether any leaf is blocked, the blocks laid out (one per
  // four triangles and step), and the blocked leaf at table entry `first`
  // (null: tested as references).
  bool empty() const { return blocks_.empty(); }
  size_t blockCount() const { return blocks_.size(); }
  const Leaf* leafAt(uint32_t first) const {
    if (blocks_.empty()) return nullptr;
    const Leaf* l = &leaves_[first / kLeafBlockWidth];
    return l->geomID == kNone ? nullptr : l;
  }

 private:
  const Leaf* of(const LeafRefs& leaf) const { return leaf.inTable() ? leafAt(leaf.first) : nullptr; }
  // The leaf's triangles at the ray's time: onHit(hit) for each candidate
  // hit in reference order, as testRun would call it; stops when onHit
  // returns true.
  template <class OnHit>
  bool testBlocks(const SceneContext& ctx, const Leaf& l, const LeafRefs& leaf, RayQuery& ray,
                  const LeafBlockRay& r, OnHit&& onHit) const {
    using P = Pack<kLeafBlockWidth>;
    constexpr int W = kLeafBlockWidth;
    uint32_t s;
    float f;
    // As the run's check of mask and time range, and VerticesAt's segment.
    if (!r.segmentOf(l.geomID, ctx.geometry(l.geomID), ray, s, f)) return false;
    const P w0 = P::set1(1.0f - f), w1 = P::set1(f);
    const TriangleBlock<W>* b = blocks_.data() + l.first;
    alignas(4 * W) TriangleBlock<W> at;  // the block at the ray's time
    const PrimRef* prims = leaf.prims;
    for (uint32_t first = 0; first < leaf.count; first += W, b += l.steps) {
      const TriangleBlock<W>* tri = b;
      if (l.steps > 1) {
        const TriangleBlock<W>&a = b[s], &c = b[s + 1];
        for (int k = 0; k < 3; ++k)
          for (int axis = 0; axis < 3; ++axis)
            (P::load(a.p[k][axis]) * w0 + P::load(c.p[k][axis]) * w1).store(at.p[k][axis]);
        tri = &at;
      }
      const auto ref = [prims, first](int lane) { return prims[first + uint32_t(lane)]; };
      if (leaf_block::testBlock(*tri, leaf_block::presentLanes(leaf.count - first), ref, ray, r, onHit)) return true;
    }
    return false;
  }
  static size_t bytesFor(size_t slots, size_t numBlocks) {
    return slots * sizeof(Leaf) + numBlocks * sizeof(TriangleBlock<kLeafBlockWidth>);
  }
  // The geometry of the leaf when all its references are triangles of that
  // one geometry without a filter, else null.
  static const Geometry* oneGeometry(const SceneContext& ctx, const LeafTable& table, const LeafRange& l) {
    const uint32_t geomID = table.prims[l.begin].geomID;
    const Geometry& g = ctx.geometry(geomID);
    if (g.type() != GeometryType::Triangles || g.hasFilter()) return nullptr;
    for (uint32_t i = l.begin; i < l.begin + l.count; ++i)
      if (table.prims[i].geomID != geomID) return nullptr;
    return &g;
  }

  std::vector<Leaf> leaves_;  // per four entries of the reference table
  std::vector<TriangleBlock<kLeafBlockWidth>> blocks_;
};

}  // namespace mbrt::detail
