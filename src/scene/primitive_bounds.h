// Bounds of a primitive over time.
//
// Every primitive has key boxes at its geometry's step times such that the
// linear interpolation of consecutive key boxes contains the primitive at
// every time between them (exact for triangles and segments, whose vertices
// move linearly between steps; conservative for instances). Outside its time
// range a primitive is bounded at the nearest time it is alive.
#pragma once

#include <algorithm>
#include <cmath>

#include "scene/scene_context.h"

namespace mbrt::detail {

// Relative widening: 2^-19 (a few float ulp, covering one lerp or fma each
// in vertex interpolation and in the node-box evaluation).
inline constexpr float kRelativeSlack = 1.0f / (1 << 19);

// Widens a box by a few ulp of its coordinates' magnitude, so interpolation
// and slab-test rounding never cut a primitive off. Inline: the spatial
// binning widens every chopped piece.
inline Box3f widen(const Box3f& box) {
  if (box.empty()) return box;
  Box3f r = box;
  for (int a = 0; a < 3; ++a) {
    const float s = std::max(std::fabs(box.lower[a]), std::fabs(box.upper[a])) * kRelativeSlack + 1e-30f;
    r.lower[a] -= s;
    r.upper[a] += s;
  }
  return r;
}
LBounds widen(const LBounds& bounds);

// The box at one time, interpolated from the key boxes.
Box3f boxAt(const SceneContext& ctx, PrimRef ref, float time);

// Linear bounds over [range.lo, range.hi] (STBVH paper §3.3, Fig. 4): the
// boxes at both ends, pushed out by the largest violation at the keys inside
// the range. b0 is the box at range.lo, b1 the box at range.hi.
LBounds linearBounds(const SceneContext& ctx, PrimRef ref, TimeRange range);

// Re-expresses bounds made for `range` at t = 0 and t = 1 (extrapolation),
// so that traversal needs no per-node time rescaling.
LBounds toGlobal(const LBounds& local, TimeRange range);

// The box of a box's corners under an affine map.
Box3f transformBox(const Affine3f& xfm, const Box3f& box);

// Number of the motion segments of the primitive's geometry (S - 1, at
// least 1 for the MBSAH counts) that overlap `range`.
uint32_t activeSegments(const SceneContext& ctx, PrimRef ref, TimeRange range);

}  // namespace mbrt::detail
