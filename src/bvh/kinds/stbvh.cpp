#include "bvh/kinds/stbvh.h"

#include "bvh/kinds/bvh_structure.h"
#include "bvh/sah_cost.h"

namespace mbrt::detail {
namespace {

template <int N>
class Stbvh final : public WideBvhStructure<N, true> {
  using Base = WideBvhStructure<N, true>;
  using Base::bvh_;
  using Base::ctx_;

 public:
  explicit Stbvh(const SceneContext& ctx) : Base(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    const SceneTemporalSource timing(ctx);
    const int leafBlock = triangleLeafBlockWidth(ctx);
    buildWideBvh(ctx, prims, ShutterRefs(ctx), bvh_, &timing, true, leafBlock);
    if (leafBlock > 1 && ReferenceTriangles::pays(ctx)) Base::refTriangles_ = ReferenceTriangles(ctx, bvh_.prims);
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [&](PrimRef p, TimeRange r) { return activeSegments(ctx_, p, r); }, sums);
    sums.bytes += Base::refTriangles_.bytes();
    sums.fill(s, sceneSahArea(ctx_));
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkTimedLanes(bvh_, 0, TimeRange{0.0f, 1.0f},
                   [&](const WideNode<N, true>& node, int lane, TimeRange range, std::span<const PrimRef> below) {
                     fn(LaneView{range, [&node, lane](float t) { return node.boxAt(lane, t); }, below, {}});
                   });
  }
};

}  // namespace

std::unique_ptr<Structure> makeStbvh(const SceneContext& context) {
  return makeForBranching<Stbvh>(context);
}

}  // namespace mbrt::detail
