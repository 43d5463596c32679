// The top level's boxes of a rigid part's instance: per key, the box of the
// part's own vertices at that step (the mesh it was fitted to), widened by
// the fit's residual. The instance's point of a rest vertex x at a time f
// into a step is lerp(A_k x, A_k+1 x, f) (element-wise key interpolation,
// part_fit.h), and A_k x is within the residual of the vertex at step k, so
// the lerp of consecutive boxes holds the instance, as the transformed rest
// bounds (the MSBVH paper's §3.3 corner bounds) do; but a turned box's
// corners reach beyond the turned mesh (crowd's hero, one full turn: its
// corner boxes have 1.75x the surface area of these).
#pragma once

#include <span>
#include <vector>

#include "auto/auto_plan.h"

namespace mbrt::detail {

std::vector<Box3f> partKeyBoxes(const Geometry& g, const RigidPart& part);

// Per vertex step, the box of the vertices of the triangles `prims` of g
// (empty: all), widened by `margin`: the lerp of consecutive boxes holds
// the lerped vertices (a near-rigid cluster's world-space triangles).
std::vector<Box3f> trianglesKeyBoxes(const Geometry& g, std::span<const uint32_t> prims, float margin);
// The same from the vertices those triangles use (usedVertices).
std::vector<Box3f> verticesKeyBoxes(const Geometry& g, std::span<const uint32_t> vertices, float margin);
// A rigid part's boxes (partKeyBoxes) from its used vertices.
std::vector<Box3f> partKeyBoxes(const Geometry& g, std::span<const uint32_t> vertices, const PartFit& fit);

}  // namespace mbrt::detail
