#include "accel/stbvh.h"

#include "bvh/build_wide.h"
#include "bvh/inspect.h"
#include "bvh/sah_cost.h"
#include "bvh/temporal_split.h"
#include "bvh/traverse.h"
#include "geometry/primitive_bounds.h"

namespace mbrt::detail {
namespace {

// Root references: linear bounds over the whole shutter (Fig. 4).
struct ShutterRefs final : RefMaker {
  const SceneContext& ctx;
  explicit ShutterRefs(const SceneContext& c) : ctx(c) {}
  bool make(PrimRef prim, BuildRef& out) const override {
    out.prim = prim;
    out.bounds = linearBounds(ctx, prim, {0.0f, 1.0f});
    out.active = activeSegments(ctx, prim, {0.0f, 1.0f});
    out.total = totalSegments(ctx, prim);
    out.range = {0.0f, 1.0f};
    return true;
  }
};

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
class Stbvh final : public Structure, public BvhInspect {
 public:
  explicit Stbvh(const SceneContext& ctx) : ctx_(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    const SceneTiming timing(ctx);
    buildWideBvh(ctx, prims, ShutterRefs(ctx), bvh_, &timing);
    sceneArea_ = sceneSahArea(ctx);
  }

  bool intersect(RayQuery& ray, Hit& hit) const override {
    return traverse<false, false>(bvh_, ctx_, ray, ray.time, &hit, nullptr);
  }
  bool occluded(RayQuery& ray) const override {
    return traverse<true, false>(bvh_, ctx_, ray, ray.time, nullptr, nullptr);
  }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    return traverse<false, true>(bvh_, ctx_, ray, ray.time, &hit, &c);
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [&](PrimRef p, TimeRange r) { return activeSegments(ctx_, p, r); }, sums);
    sums.fill(s, sceneArea_);
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkTimedLanes(bvh_, 0, TimeRange{0.0f, 1.0f},
                   [&](const WideNode<N, true>& node, int lane, TimeRange range, std::span<const PrimRef> below) {
                     fn(LaneView{range, [&node, lane](float t) { return node.boxAt(lane, t); }, below});
                   });
  }
  std::vector<uint8_t> bytes() const override {
    std::vector<uint8_t> out;
    appendBytes(bvh_, out);
    return out;
  }

 private:
  const SceneContext& ctx_;
  WideBvh<N, true> bvh_;
  double sceneArea_ = 0.0;
};

}  // namespace

std::unique_ptr<Structure> makeStbvh(const SceneContext& context) {
  switch (context.options().branching) {
    case 2: return std::make_unique<Stbvh<2>>(context);
    case 4: return std::make_unique<Stbvh<4>>(context);
    default: return std::make_unique<Stbvh<8>>(context);
  }
}

}  // namespace mbrt::detail
