// `fuzzykd`: fuzzy kd-trees with motion decomposition (Günther et al. 2006).
//
// Every animated triangle mesh (S >= 2 steps, enough triangles, few
// connected pieces) is decomposed (decompose/decompose.h) into clusters with
// one affine map per key (local frame -> world). Each cluster gets one SAH
// kd-tree over its triangles' fuzzy boxes, built once. A ray at time t is
// taken into a cluster's local frame by the inverse of the element-wise
// interpolated map at t; its leaf triangles are tested in world space at t
// (primitive_intersect.h).
//
// Motion blur. Between keys the world positions and the maps are linear in
// the fraction f, so for a vertex with local positions q_a, q_b at the ends
// of a (sub)segment with linear parts L_a, L_b (D = L_b - L_a):
//   q(f) = (1-f) q_a + f q_b + f(1-f) L(f)^-1 D (q_b - q_a),
// and |L(f)^-1|_inf <= |L_a^-1|_inf / (1 - |L_a^-1 D|_inf) (Neumann series;
// likewise from b). So the fuzzy box of a triangle is the box of its local
// positions at n sub-samples per key segment, padded by
//   1/4 * min(beta_a, beta_b) * max |D (q_b - q_a)|_inf
// (a proven bound) plus a numerical pad. n doubles (up to 16) until the
// bound applies (|L^-1 D| < 1/2) and the pad is small; clusters where it
// never does, and every other primitive (static meshes, segments,
// instances, small or fragmented meshes), go into one world-space motion
// kd-tree (the mbkd core over key-box paths, boxes checked at the ray's
// time). The top level is a binary BVH over the clusters' (and that tree's)
// linear bounds over the shutter; each cluster also checks its box at t
// (interpolated key boxes).
#pragma once

#include <memory>
#include <vector>

#include "scene/scene_context.h"
#include "decompose/decompose.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeFuzzyKd(const SceneContext& context);

struct FuzzyKdStats {
  size_t decomposedMeshes = 0;
  size_t clusters = 0;          // clusters with a fuzzy tree
  size_t fallbackClusters = 0;  // clusters whose triangles went to the world tree
  size_t fuzzyPrims = 0, worldPrims = 0;
  size_t fuzzyTreeBytes = 0;    // all bottom-level fuzzy trees: 8-byte nodes, 4-byte references
  size_t fuzzyNodes = 0, fuzzyRefs = 0;  // their nodes and leaf references
  size_t worldTreeBytes = 0;
  size_t topBytes = 0;          // top-level nodes, transforms, key boxes
  double fuzzyBoxArea = 0;      // sum of the triangles' fuzzy-box areas (local, padded)
  double decomposeSeconds = 0, treeSeconds = 0;
  uint32_t maxSubdivisions = 0;
  double rmsResidual = 0;       // of the decomposed meshes (largest)
  std::vector<Decomposition> decompositions;  // per decomposed mesh (curves, transforms)
  std::vector<uint32_t> decomposedGeometry;   // their geometry ids
};

class FuzzyKdInspect {
 public:
  virtual ~FuzzyKdInspect() = default;
  virtual const FuzzyKdStats& fuzzyStats() const = 0;
  // The cluster of a primitive (~0u: in the world tree).
  virtual uint32_t clusterOf(PrimRef prim) const = 0;
};

}  // namespace mbrt::detail
