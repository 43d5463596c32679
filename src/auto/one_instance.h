// A top level of one instance: the instance's test itself (mask, time
// range, the ray's transform into it, its structure and the normal's way
// back: scene/primitive_intersect.h), without a tree over it. A tree of one
// leaf would only add its traversal's set-up and one node visit per ray
// (~180 and ~280 instructions of a ray's ~3,400 on `rotate`, callgrind),
// and its box test culls nothing the instance's own root test would not.
#pragma once

#include "scene/primitive_intersect.h"

namespace mbrt::detail {

class OneInstance final : public Structure {
 public:
  // `context`'s scene holds exactly one geometry, an instance.
  explicit OneInstance(const SceneContext& context) : ctx_(context) {}
  bool intersect(RayQuery& ray, Hit& hit) const override { return intersectPrimitive(ctx_, kRef, ray, hit); }
  bool occluded(RayQuery& ray) const override { return occludedPrimitive(ctx_, kRef, ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& counters) const override {
    ++counters.primitiveTests;  // as a leaf counts its instance
    return intersectPrimitive(ctx_, kRef, ray, hit, &counters);
  }
  void fillStats(AccelStats& s) const override {
    s.references += 1;
    s.bytes += sizeof(*this);
  }

 private:
  static constexpr PrimRef kRef{0, 0};
  const SceneContext& ctx_;
};

}  // namespace mbrt::detail
