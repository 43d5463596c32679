// Build references (STBVH paper §3.3, "build primitives"): the builders see
// only these, never triangles. A reference is a primitive id, its linear
// bounds over the time range of the node it is in (temporal splits give
// their halves' references narrower ranges, Fig. 4) and its MBSAH segment
// count in that range (§3.2). 60 bytes and nothing more: the binner and the
// partition stream through them at every level of the build.
#pragma once

#include <span>
#include <vector>

#include "core/prim_ref.h"
#include "mbrt/math.h"

namespace mbrt::detail {

struct BuildRef {
  // Local to the node's range: b0 is the box at its start, b1 at its end.
  // Merging local bounds of one range is tight; merging bounds extrapolated
  // to t = 0 and 1 is not (builder.cpp makes the nodes' global form).
  LBounds bounds;
  PrimRef prim{0, 0};
  uint32_t active = 1;  // primitive segments alive in the node's range (MBSAH |X|_s)

  // Binning key: centre of the box at the centre of the range (STBVH §3.3).
  Vec3f centroid() const { return bounds.at(0.5f).center(); }
};
static_assert(sizeof(BuildRef) == 60);


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
