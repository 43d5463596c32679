#include "bvh/kinds/stbvh.h"

#include "bvh/kinds/bvh_structure.h"
#include "bvh/kinds/stbvh_tuning.h"
#include "bvh/sah_cost.h"
#include "leaves/leaf_width.h"
#include "leaves/reference_triangles.h"

namespace mbrt::detail {
namespace {

// Leaves: references gathered into blocks at the ray's time, through their
// triangles' indices kept beside them where that pays (makeStbvh).
template <int N, class Leaves>
class Stbvh final : public WideBvhStructure<N, true, Leaves> {
  using Base = WideBvhStructure<N, true, Leaves>;
  using Base::bvh_;
  using Base::ctx_;

 public:
  explicit Stbvh(const SceneContext& ctx) : Base(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    const SceneTemporalSource timing(ctx);
    buildWideBvh(ctx, prims, ShutterRefs(ctx), bvh_, stbvhTuning(timing, triangleLeafBlockWidth(ctx)));
    Base::layOutLeaves();
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [&](PrimRef p, TimeRange r) { return activeSegments(ctx_, p, r); }, sums);
    sums.bytes += Base::leaves_.bytes();
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
  if (triangleLeafBlockWidth(context) > 1 && ReferenceTriangleLeaves::pays(context))
    return makeForBranching<Stbvh, ReferenceTriangleLeaves>(context);
  return makeForBranching<Stbvh, ReferenceLeaves>(context);
}

}  // namespace mbrt::detail
