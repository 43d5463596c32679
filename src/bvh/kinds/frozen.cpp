#include "bvh/kinds/frozen.h"

#include <algorithm>

#include "bvh/kinds/bvh_structure.h"
#include "bvh/sah_cost.h"
#include "leaves/fixed_time_triangles.h"
#include "leaves/segment_blocks.h"
#include "leaves/triangle_blocks.h"

namespace mbrt::detail {
namespace {

// The leaf block the frozen tree's SAH charges (leaf_width.h): four when
// most primitives are triangles stored at the frozen time
// (FixedTimeTriangles) or plain segments alive then, whichever are more.
struct FrozenLeafBlock {
  int width;
  bool segments;  // the blocks are of segments
};
FrozenLeafBlock frozenLeafBlock(const SceneContext& ctx) {
  const float time = ctx.options().frozenTime;
  const std::vector<PrimRef> prims = ctx.primitives();
  size_t triangles = FixedTimeTriangles::countStored(ctx, time);
  if (3 * triangles >= FixedTimeTriangles::kNotStored) triangles = 0;  // too many to store: none are
  const size_t segments = size_t(std::count_if(prims.begin(), prims.end(), [&](PrimRef p) {
    return blocksSegments(ctx.geometry(p.geomID), time);
  }));
  return {leafBlockWidth(std::max(triangles, segments), prims.size()), segments > triangles};
}

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

// Leaves (makeFrozen): triangle blocks at the frozen time where the leaves
// are charged per block of four triangles, segment blocks where they are
// charged per block of four segments, else the triangles stored at the
// frozen time, one by one.
template <int N, class Leaves>
class Frozen final : public WideBvhStructure<N, false, Leaves> {
  using Base = WideBvhStructure<N, false, Leaves>;
  using Base::bvh_;
  using Base::ctx_;

 public:
  // Every ray sees the scene at the frozen time.
  explicit Frozen(const SceneContext& ctx) : Base(ctx, ctx.options().frozenTime), time_(ctx.options().frozenTime) {
    const std::vector<PrimRef> prims = ctx.primitives();
    buildWideBvh(ctx, prims, FrozenRefs(ctx, time_), bvh_, {.leafBlock = frozenLeafBlock(ctx).width});
    Base::layOutLeaves();
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [](PrimRef, TimeRange) { return 1u; }, sums);
    sums.bytes += Base::leaves_.bytes();
    sums.fill(s, sceneSahArea(ctx_));
    s.leafBlockBytes = Base::leaves_.bytes();
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
  const FrozenLeafBlock block = frozenLeafBlock(context);
  if (block.width == 1) return makeForBranching<Frozen, FixedTimeLeaves>(context);
  if (block.segments) return makeForBranching<Frozen, SegmentBlockLeaves>(context);
  return makeForBranching<Frozen, TriangleBlockLeaves>(context);
}

}  // namespace mbrt::detail
