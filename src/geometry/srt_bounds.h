// Conservative bounds of an SRT instance over one key segment.
#pragma once

#include "mbrt/quaternion.h"

namespace mbrt::detail {

// A box containing M(u) x for every u in [0,1] and every x in `box`, where
// M(u) is the SRT interpolation of keys a and b (Geometry::transformAt).
//
// Why it is conservative. An affine map sends the box to the convex hull of
// its 8 mapped corners, so it suffices to bound the corners' paths
// f(u) = T(u) + R(u) (s(u) * x). T and s are linear in u; slerp turns at a
// constant angular speed w (the keys' rotation angle) about a fixed axis, so
// |R'v| <= w|v| and |R''v| <= w^2|v|, and
//   |f''(u)| <= w^2 max(|s_a*x|, |s_b*x|) + 2 w |(s_b - s_a)*x| =: K.
// On a piece of length h, a C^2 curve stays within h^2 K / 8 of its chord
// (componentwise: the error of linear interpolation). The segment is cut
// into n pieces with n the smallest count whose bound is below a tolerance
// (1e-4 of the box's size; at most 256 pieces), the piece ends are
// evaluated exactly as transformAt does, and the box of them is padded by
// the bound (plus a few float ulp of the magnitudes involved).
Box3f srtSegmentBounds(const SRTKey& a, const SRTKey& b, const Box3f& box);

}  // namespace mbrt::detail
