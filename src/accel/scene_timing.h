// What temporal splits need of a scene (STBVH §3.3): each primitive's steps,
// and its reference remade for part of the shutter with linear bounds over
// exactly that part (Fig. 4), local to it (the nodes get the global form).
#pragma once

#include "bvh/build_ref.h"
#include "bvh/temporal_split.h"
#include "geometry/primitive_bounds.h"

namespace mbrt::detail {

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

}  // namespace mbrt::detail
