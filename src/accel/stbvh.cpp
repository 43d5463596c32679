#include "accel/stbvh.h"

#include "bvh/bvh_structure.h"
#include "bvh/sah_cost.h"
#include "bvh/temporal_split.h"

namespace mbrt::detail {
namespace {

// References for a part of the shutter: the primitive's linear bounds over
// exactly that part (Fig. 4), local to it (the nodes get the global form).
struct SceneTiming final : TemporalSource {
  const SceneContext& ctx;
  explicit SceneTiming(const SceneContext& c) : ctx(c) {}
  TimeRange stepRange(PrimRef prim, uint32_t& segments) const override {
    const Geometry& g = ctx.geometry(prim.geomID);
    segments = g.numSteps() - 1;
    return g.timeRange();
  }
  bool remake(const BuildRef& ref, TimeRange range, BuildRef& out) const override {
    // Alive somewhere in the half-open range (a geometry range ending at 1
    // contains 1, but a half-open range starting at 1 is empty).
    const TimeRange alive = ctx.geometry(ref.prim.geomID).timeRange();
    if (!(alive.lo < range.hi && alive.hi > range.lo)) return false;
    out.prim = ref.prim;
    out.bounds = linearBounds(ctx, ref.prim, range);
    out.active = activeSegments(ctx, ref.prim, range);
    out.total = ref.total;
    out.range = range;
    return true;
  }
};

template <int N>
class Stbvh final : public WideBvhStructure<N, true> {
  using Base = WideBvhStructure<N, true>;
  using Base::bvh_;
  using Base::ctx_;

 public:
  explicit Stbvh(const SceneContext& ctx) : Base(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    const SceneTiming timing(ctx);
    buildWideBvh(ctx, prims, ShutterRefs(ctx), bvh_, &timing);
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [&](PrimRef p, TimeRange r) { return activeSegments(ctx_, p, r); }, sums);
    sums.fill(s, sceneSahArea(ctx_));
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkTimedLanes(bvh_, 0, TimeRange{0.0f, 1.0f},
                   [&](const WideNode<N, true>& node, int lane, TimeRange range, std::span<const PrimRef> below) {
                     fn(LaneView{range, [&node, lane](float t) { return node.boxAt(lane, t); }, below});
                   });
  }
};

}  // namespace

std::unique_ptr<Structure> makeStbvh(const SceneContext& context) {
  return makeForBranching<Stbvh>(context);
}

}  // namespace mbrt::detail
