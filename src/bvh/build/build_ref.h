// Build references (STBVH paper §3.3, "build primitives"): the builders see
// only these, never triangles. A reference is a primitive id, its linear
// bounds over its time range, its MBSAH segment counts (§3.2) and the time
// range itself (temporal splits give references narrower ranges).
#pragma once

#include <span>
#include <vector>

#include "scene/scene_context.h"

namespace mbrt::detail {

struct BuildRef {
  // Local to `range`: b0 is the box at range.lo, b1 at range.hi. Merging
  // local bounds of one range is tight; merging bounds extrapolated to
  // t = 0 and 1 is not (builder.cpp makes the nodes' global form).
  LBounds bounds;
  PrimRef prim{0, 0};
  uint32_t active = 1;   // primitive segments alive in `range` (MBSAH |X|_s)
  uint32_t total = 1;    // all primitive segments of the primitive
  TimeRange range;       // time range the bounds were made for (tree parameter)

  // Binning key: centre of the box at the centre of the range (STBVH §3.3).
  Vec3f centroid() const { return bounds.at(0.5f).center(); }
};

// True for bounds a ray can hit: non-empty and finite at both ends.
bool usableBounds(const LBounds& b);

// How each reference of a build is made from its primitive.
struct RefMaker {
  virtual ~RefMaker() = default;
  // False drops the primitive from this build (e.g. not alive in the range).
  virtual bool make(PrimRef prim, BuildRef& out) const = 0;
};

// References for `prims` (in parallel, order preserved), without those the
// maker drops and those with unusable bounds (they can never be hit).
std::vector<BuildRef> makeBuildRefs(std::span<const PrimRef> prims, const RefMaker& maker);

}  // namespace mbrt::detail
