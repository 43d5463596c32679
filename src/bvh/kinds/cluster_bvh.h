// The tree of a near-rigid cluster (Günther et al. 2006 §3-5, here for a
// BVH; docs/auto.md, "Near-rigid clusters"): triangles of one mesh whose
// motion is one affine map per vertex step plus a small residual. One
// static wide BVH over the triangles' fuzzy boxes in the cluster's frame
// (decompose/fuzzy_boxes.h: each box holds its triangle, taken into that
// frame, at every time of the shutter, with a proven bound between steps)
// serves every time. A ray's nodes are tested in the frame of the map
// interpolated at its time; its leaves test the world-space triangles at
// its time (motion leaf blocks), so its hits are those of `brute`.
//
// Not an instance: an instance of the residual vertices would not move as
// the mesh does between steps (lerp(A) lerp(r) differs from lerp(A r) by
// f(1-f) dA dr), the world-space leaves do.
#pragma once

#include <memory>
#include <span>

#include "scene/scene_context.h"

namespace mbrt::detail {

// `context`'s scene holds one triangle geometry with one map per vertex
// step (`maps`: the cluster's frame -> world, as the decomposition fitted
// them). Null when the fuzzy boxes have no usable bound (a map singular
// somewhere, or the residual too large for the frame: fuzzy_boxes.h).
std::unique_ptr<Structure> makeClusterBvh(const SceneContext& context, std::span<const Affine3f> maps);

}  // namespace mbrt::detail
