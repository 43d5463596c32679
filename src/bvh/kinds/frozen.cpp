#include "bvh/kinds/frozen.h"

#include <algorithm>

#include "bvh/kinds/bvh_structure.h"
#include "bvh/sah_cost.h"

namespace mbrt::detail {
namespace {

// The (widened) box of each primitive at the frozen time.
struct FrozenRefs final : RefMaker {
  const SceneContext& ctx;
  float time;
  FrozenRefs(const SceneContext& c, float t) : ctx(c), time(t) {}
  bool make(PrimRef prim, BuildRef& out) const override {
    if (!ctx.geometry(prim.geomID).timeRange().contains(time)) return false;  // not there at T
    out.prim = prim;
    out.bounds = LBounds(widen(boxAt(ctx, prim, time)));
    out.active = 1;  // a static scene: one segment per primitive
    return true;
  }
};

template <int N>
class Frozen final : public WideBvhStructure<N, false> {
  using Base = WideBvhStructure<N, false>;
  using Base::bvh_;
  using Base::ctx_;

 public:
  // Every ray sees the scene at the frozen time.
  explicit Frozen(const SceneContext& ctx) : Base(ctx, ctx.options().frozenTime), time_(ctx.options().frozenTime) {
    const std::vector<PrimRef> prims = ctx.primitives();
    Base::stored_ = FixedTimeTriangles(ctx, time_);
    // Leaves charged per block of four (Embree's Triangle4 SAH) and laid
    // out as blocks when most primitives are stored triangles
    // (leaf_blocks.h) or segments (segment_leaf_blocks.h).
    const size_t triangles = Base::stored_.vertices.size() / 3;
    const size_t segments = size_t(std::count_if(prims.begin(), prims.end(), [&](PrimRef p) {
      return blocksSegments(ctx.geometry(p.geomID), time_);
    }));
    const bool segmentTree = segments > triangles;
    const int leafBlock = leafBlockWidth(std::max(triangles, segments), prims.size());
    buildWideBvh(ctx, prims, FrozenRefs(ctx, time_), bvh_, nullptr, true, leafBlock);
    if (segmentTree) Base::segmentBlocks_ = SegmentLeafBlocks(ctx, bvh_, time_);
    else Base::blocks_ = TriangleLeafBlocks(ctx, bvh_, Base::stored_, time_);
    if (leafBlock > 1) {
      // No leaf is kept in a node (wide_layout.h), so every leaf of stored
      // triangles reads its blocks; the few others (a geometry with a filter
      // beside them) interpolate at the frozen time through the indices, to
      // the same values. The stored triangles are not needed any more.
      ctx.budget().release(Base::stored_.vertices.size() * sizeof(Vec3f));
      Base::stored_ = FixedTimeTriangles();
    }
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [](PrimRef, TimeRange) { return 1u; }, sums);
    const size_t leafBytes = Base::stored_.bytes() + Base::blocks_.bytes() + Base::segmentBlocks_.bytes();
    sums.bytes += leafBytes;
    sums.fill(s, sceneSahArea(ctx_));
    s.leafBlockBytes = leafBytes;
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkLanes(bvh_, 0, [&](const WideNode<N, false>& node, int lane, std::span<const PrimRef> below) {
      fn(LaneView{{time_, time_}, [&node, lane](float) { return node.boxAt(lane, 0.0f); }, below, {}});
    });
  }

 private:
  float time_;
};

}  // namespace

std::unique_ptr<Structure> makeFrozen(const SceneContext& context) {
  return makeForBranching<Frozen>(context);
}

}  // namespace mbrt::detail
