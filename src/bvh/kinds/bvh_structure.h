// What the wide-BVH kinds (`bvh-interp`, `stbvh`, `frozen`) have in common:
// one WideBvh traced by traverse.h with its leaves in one leaf format, and
// its bytes. Each kind only says how it builds the tree, which format its
// leaves take, and how it counts its SAH.
#pragma once

#include <memory>

#include "bvh/build/build_wide.h"
#include "bvh/inspect.h"
#include "bvh/heuristics/temporal_split.h"
#include "bvh/leaf_table.h"
#include "bvh/traverse.h"
#include "core/traced_structure.h"
#include "scene/branching.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {

// Linear bounds of each primitive over the whole shutter (STBVH Fig. 4),
// global by construction: the root references of `bvh-interp` and `stbvh`.
struct ShutterRefs final : RefMaker {
  const SceneContext& ctx;
  explicit ShutterRefs(const SceneContext& c) : ctx(c) {}
  bool make(PrimRef prim, BuildRef& out) const override {
    out.prim = prim;
    out.bounds = linearBounds(ctx, prim, {0.0f, 1.0f});
    out.active = activeSegments(ctx, prim, {0.0f, 1.0f});
    return true;
  }
};

// What temporal splits need of a scene (STBVH §3.3): each primitive's steps,
// and its reference remade for part of the shutter with linear bounds over
// exactly that part (Fig. 4), local to it (the nodes get the global form):
// `stbvh`'s TemporalSource.
struct SceneTemporalSource final : TemporalSource {
  const SceneContext& ctx;
  explicit SceneTemporalSource(const SceneContext& c) : ctx(c) {}
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
    return true;
  }
};

// Motion trees interpolate the node boxes at the ray's time; a static tree
// (`frozen`) sees every ray at its one time `frozenTime`. `Leaves` is the
// leaf format (leaves/), laid out by the kind once its tree is built
// (layOutLeaves).
template <int N, bool Motion, LeafFormat Leaves>
class WideBvhStructure : public TracedStructure<WideBvhStructure<N, Motion, Leaves>>, public Inspect {
 public:
  template <bool AnyHit, bool Count>
  bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    if constexpr (Motion) {
      return traverse<AnyHit, Count>(bvh_, leaves_, ctx_, ray, ray.time, hit, counters);
    } else {
      ray.time = frozenTime_;  // every ray sees the scene at the frozen time; the nodes have no time
      return traverse<AnyHit, Count>(bvh_, leaves_, ctx_, ray, 0.0f, hit, counters);
    }
  }
  std::vector<uint8_t> bytes() const override {
    std::vector<uint8_t> out;
    appendBytes(bvh_, out);
    return out;
  }

 protected:
  explicit WideBvhStructure(const SceneContext& ctx, float frozenTime = 0.0f)
      : ctx_(ctx), frozenTime_(frozenTime) {}

  // The leaves laid out over the tree as it is now (after a build or refit).
  void layOutLeaves() {
    std::optional<float> fixed;
    if constexpr (!Motion) fixed = frozenTime_;
    leaves_ = Leaves(ctx_, leafTable(bvh_, fixed));
  }

  const SceneContext& ctx_;
  WideBvh<N, Motion> bvh_;
  Leaves leaves_;
  float frozenTime_;
};

}  // namespace mbrt::detail
