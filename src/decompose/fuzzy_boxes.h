// The fuzzy boxes of a cluster (Günther et al. 2006 §3.2, §4-5): per
// triangle, the box of its local positions q = W(t)^-1 x(t) over the whole
// shutter, in the cluster's frame.
//
// Between keys the world positions and the maps are linear in the fraction
// f, so for a vertex with local positions q_a, q_b at the ends of a
// (sub)segment with linear parts L_a, L_b (D = L_b - L_a):
//   q(f) = (1-f) q_a + f q_b + f(1-f) L(f)^-1 D (q_b - q_a),
// and |L(f)^-1|_inf <= |L_a^-1|_inf / (1 - |L_a^-1 D|_inf) (Neumann series;
// likewise from b). So the fuzzy box of a triangle is the box of its local
// positions at n sub-samples per key segment, padded by
//   1/4 * min(beta_a, beta_b) * max |D (q_b - q_a)|_inf
// (a proven bound) plus a numerical pad for the float inverse and lerps of
// traversal. n doubles (up to 16) until the bound applies (|L^-1 D| < 1/2)
// and the pad is small (docs/fuzzykd.md, "Motion blur: the bound").
#pragma once

#include <span>
#include <vector>

#include "scene/scene_context.h"

namespace mbrt::detail {

struct FuzzyBoxes {
  std::vector<Box3f> boxes;   // per triangle of the cluster: local, padded, widened
  uint32_t subdivisions = 0;  // sub-samples per key segment that made them
};

// The fuzzy boxes of the triangles `prims` of `geo` under the cluster maps
// `maps` (one per geometry step, local -> world, as traversal uses them).
// worldMag: the largest coordinate magnitude of the scene (numerical pad).
// False when no sub-sampling gives a usable bound: the cluster's map is
// singular somewhere, or the pad stays above a quarter of its extent.
bool fuzzyBoxes(const Geometry& geo, std::span<const Affine3f> maps, std::span<const PrimRef> prims,
                double worldMag, FuzzyBoxes& out);

}  // namespace mbrt::detail
