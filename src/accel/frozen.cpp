#include "accel/frozen.h"

#include "bvh/build_wide.h"
#include "bvh/inspect.h"
#include "bvh/sah_cost.h"
#include "bvh/traverse.h"
#include "geometry/primitive_bounds.h"

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
    out.total = 1;
    out.range = {0.0f, 1.0f};
    return true;
  }
};

template <int N>
class Frozen final : public Structure, public BvhInspect {
 public:
  explicit Frozen(const SceneContext& ctx) : ctx_(ctx), time_(ctx.options().frozenTime) {
    const std::vector<PrimRef> prims = ctx.primitives();
    buildWideBvh(ctx, prims, FrozenRefs(ctx, time_), bvh_);
    sceneArea_ = sceneSahArea(ctx);
  }

  // Every ray sees the scene at the frozen time.
  bool intersect(RayQuery& ray, Hit& hit) const override {
    ray.time = time_;
    return traverse<false, false>(bvh_, ctx_, ray, 0.0f, &hit, nullptr);
  }
  bool occluded(RayQuery& ray) const override {
    ray.time = time_;
    return traverse<true, false>(bvh_, ctx_, ray, 0.0f, nullptr, nullptr);
  }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    ray.time = time_;
    return traverse<false, true>(bvh_, ctx_, ray, 0.0f, &hit, &c);
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [](PrimRef, TimeRange) { return 1u; }, sums);
    sums.fill(s, sceneArea_);
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkLanes(bvh_, 0, [&](const WideNode<N, false>& node, int lane, std::span<const PrimRef> below) {
      fn(LaneView{{time_, time_}, [&node, lane](float) { return node.boxAt(lane, 0.0f); }, below});
    });
  }
  std::vector<uint8_t> bytes() const override {
    std::vector<uint8_t> out;
    appendBytes(bvh_, out);
    return out;
  }

 private:
  const SceneContext& ctx_;
  float time_;
  WideBvh<N, false> bvh_;
  double sceneArea_ = 0.0;
};

}  // namespace

std::unique_ptr<Structure> makeFrozen(const SceneContext& context) {
  switch (context.options().branching) {
    case 2: return std::make_unique<Frozen<2>>(context);
    case 4: return std::make_unique<Frozen<4>>(context);
    default: return std::make_unique<Frozen<8>>(context);
  }
}

}  // namespace mbrt::detail
