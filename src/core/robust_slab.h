// Conservative far slab distances (Ize, JCGT 2013, "Robust BVH Ray
// Traversal"): the far distance of a slab test is enlarged by 2*gamma(3) of
// its magnitude, gamma(n) = n*eps / (1 - n*eps), eps = 2^-24, so rounding in
// (plane - org) * rdir never culls a box the ray passes through. Enlarged
// means towards +inf for either sign of t: rays may start at a negative
// tnear, and a far origin puts whole boxes at negative distances.
#pragma once

#include "core/simd.h"

namespace mbrt::detail {

inline constexpr float kRobustGamma2 = 2.0f * (3.0f * 0x1p-24f) / (1.0f - 3.0f * 0x1p-24f);

// Motion nodes (motion_node.h) evaluate (plane - org) * rdir as
// A + q0 * B0 + q1 * B1 with per-node scalars A, B0, B1 (traverse.h): five
// roundings relative to the distance instead of three (the rest, relative
// to the node's grid, is inside the margin its planes were moved out by).
inline constexpr float kRobustGammaGrid = 2.0f * (5.0f * 0x1p-24f) / (1.0f - 5.0f * 0x1p-24f);

template <int W>
inline Pack<W> robustFar(Pack<W> tf, float gamma = kRobustGamma2) {
  return vmax(tf * Pack<W>::set1(1.0f + gamma), tf * Pack<W>::set1(1.0f - gamma));
}

// The same for one distance and any relative slack (infinities stay put).
inline float enlargeFar(float t, float relative) { return t * (t >= 0.0f ? 1.0f + relative : 1.0f - relative); }

}  // namespace mbrt::detail
