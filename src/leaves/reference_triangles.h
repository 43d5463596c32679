// References with their triangles' vertex indices beside them, in the order
// of the tree's reference table (zeros for other primitives): a gathered run
// (gathered_runs.h) reads its triangles next to its references instead of
// through each one's primitive id, one dependent load less per block (the
// leaf keeps its triangles' indices, as Embree's Triangle4i leaves do). 12
// bytes a reference; the format of the trees whose leaves are charged per
// block (`stbvh`, `bvh-segments`) where it pays (docs/performance.md,
// "Leaves gathered into blocks through their indices").
#pragma once

#include <vector>

#include "core/cache_size.h"
#include "core/huge_pages.h"
#include "leaves/reference_leaves.h"

namespace mbrt::detail {

struct ReferenceTriangleLeaves {
  using RayState = LeafBlockRay;

  // Where it pays: the scene's triangles' indices take more than a core's
  // cache (core/cache_size.h), so that reading a triangle through its
  // primitive id waits on memory. On smaller scenes those indices stay
  // cached and the table only adds bytes to read.
  static constexpr size_t kPaysFromBytes = kCoreCacheBytes;
  static bool pays(const SceneContext& ctx) {
    size_t bytes = 0;
    for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id)
      if (ctx.geometry(id).type() == GeometryType::Triangles) bytes += ctx.geometry(id).triangles().size_bytes();
    return bytes > kPaysFromBytes;
  }

  ReferenceTriangleLeaves() = default;
  ReferenceTriangleLeaves(const SceneContext& ctx, const LeafTable& table) {
    const std::span<const PrimRef> prims = table.prims;
    ctx.budget().charge(prims.size() * sizeof(Triangle), "the tree's reference triangles");
    resizeOnHugePages(tris_, prims.size());
    for (size_t i = 0; i < prims.size(); ++i) {
      const Geometry& g = ctx.geometry(prims[i].geomID);
      if (g.type() == GeometryType::Triangles) tris_[i] = g.triangles()[prims[i].primID];
    }
  }

  RayState rayState(const RayQuery& ray) const { return LeafBlockRay(ray); }
  template <bool AnyHit, bool Count>
  bool test(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const RayState& r, Hit* hit,
            TraversalCounters* counters) const {
    const Triangle* indices = leaf.inTable() ? from(leaf.first) : nullptr;
    return testReferences<AnyHit, Count>(ctx, leaf, ray, r, hit, counters, indices);
  }
  size_t bytes() const { return tris_.size() * sizeof(Triangle); }
  // The triangles of the references from table entry `first` on.
  const Triangle* from(uint32_t first) const { return tris_.data() + first; }

 private:
  std::vector<Triangle> tris_;
};

}  // namespace mbrt::detail
