#include "accel/brute.h"

#include "scene/primitive_intersect.h"

namespace mbrt::detail {
namespace {

class Brute final : public Structure {
 public:
  explicit Brute(const SceneContext& ctx) : ctx_(ctx), prims_(ctx.primitives()) {
    ctx.budget().charge(prims_.size() * sizeof(PrimRef), "the brute-force primitive list");
  }

  bool intersect(RayQuery& ray, Hit& hit) const override {
    bool found = false;
    for (const PrimRef& p : prims_) found |= intersectPrimitive(ctx_, p, ray, hit);
    return found;
  }

  bool occluded(RayQuery& ray) const override {
    for (const PrimRef& p : prims_)
      if (occludedPrimitive(ctx_, p, ray)) return true;
    return false;
  }

  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    bool found = false;
    for (const PrimRef& p : prims_) found |= intersectPrimitive(ctx_, p, ray, hit, &c);
    c.primitiveTests += prims_.size();
    return found;
  }

  void fillStats(AccelStats& s) const override {
    s.references = prims_.size();
    s.leafNodes = 1;
    s.bytes = prims_.size() * sizeof(PrimRef);
    s.sahCost = double(prims_.size());  // one leaf over the scene box, every primitive tested
  }

 private:
  const SceneContext& ctx_;
  std::vector<PrimRef> prims_;
};

}  // namespace

std::unique_ptr<Structure> makeBrute(const SceneContext& context) { return std::make_unique<Brute>(context); }

}  // namespace mbrt::detail
