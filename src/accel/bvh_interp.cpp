#include "accel/bvh_interp.h"

#include "bvh/build_wide.h"
#include "bvh/inspect.h"
#include "bvh/sah_cost.h"
#include "bvh/traverse.h"
#include "geometry/primitive_bounds.h"

namespace mbrt::detail {
namespace {

// Linear bounds over the whole shutter (STBVH Fig. 4), global by construction.
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

template <int N>
class BvhInterp final : public Structure, public BvhInspect {
 public:
  explicit BvhInterp(const SceneContext& ctx) : ctx_(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    numPrims_ = prims.size();
    buildWideBvh(ctx, prims, ShutterRefs(ctx), bvh_);
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
    addTreeCost(bvh_, 1.0, [&](PrimRef p, TimeRange) { return activeSegments(ctx_, p, {0.0f, 1.0f}); }, sums);
    sums.fill(s, sceneArea_);
  }

  // Same topology, new bounds: leaves from the primitives, inner lanes from
  // their children, bottom-up.
  bool refit() override {
    if (bvh_.prims.size() != numPrims_) return false;  // a primitive was dropped: rebuild
    // Instance bounds come from the context's key boxes and the instanced
    // structures, which are made once: rebuild instead.
    for (uint32_t g = 0; g < ctx_.scene().numGeometries(); ++g)
      if (ctx_.geometry(g).type() == GeometryType::Instance) return false;
    if (bvh_.empty()) return true;
    bool ok = true;
    refitNode(0, ok);
    if (!ok) return false;
    sceneArea_ = sceneSahArea(ctx_);
    return true;
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkLanes(bvh_, 0, [&](const WideNode<N, true>& node, int lane, std::span<const PrimRef> below) {
      fn(LaneView{{0.0f, 1.0f}, [&node, lane](float t) { return node.boxAt(lane, t); }, below});
    });
  }
  std::vector<uint8_t> bytes() const override {
    std::vector<uint8_t> out;
    appendBytes(bvh_, out);
    return out;
  }

 private:
  LBounds refitNode(uint32_t index, bool& ok) {
    LBounds all;
    for (int i = 0; i < N; ++i) {
      auto& node = bvh_.nodes[index];
      if (node.isEmpty(i)) continue;
      LBounds b;
      if (node.isLeaf(i)) {
        for (uint32_t k = 0; k < node.count[i]; ++k)
          b.extend(linearBounds(ctx_, bvh_.prims[node.child[i] + k], {0.0f, 1.0f}));
        ok = ok && usableBounds(b);
      } else {
        b = refitNode(node.child[i], ok);
      }
      bvh_.nodes[index].setBounds(i, b);
      all.extend(b);
    }
    return all;
  }

  const SceneContext& ctx_;
  WideBvh<N, true> bvh_;
  size_t numPrims_ = 0;
  double sceneArea_ = 0.0;
};

}  // namespace

std::unique_ptr<Structure> makeBvhInterp(const SceneContext& context) {
  switch (context.options().branching) {
    case 2: return std::make_unique<BvhInterp<2>>(context);
    case 4: return std::make_unique<BvhInterp<4>>(context);
    default: return std::make_unique<BvhInterp<8>>(context);
  }
}

}  // namespace mbrt::detail
