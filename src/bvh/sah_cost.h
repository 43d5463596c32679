// The SAH cost of DESIGN.md, one formula for every kind (C_T = C_I = 1):
//   ( sum_inner A(n) T(n) + sum_leaves A(l) T(l) seg(l) ) / A(scene)
// A: surface area averaged over 8 times spread over the node's time range;
// T: length of that range; seg: active primitive segments (MBSAH, STBVH §3.2).
#pragma once

#include <algorithm>
#include <span>

#include "bvh/wide_bvh.h"
#include "core/scene_context.h"

namespace mbrt::detail {

// Surface area of lerp(b0, b1, t) averaged over t = lo + (hi - lo) * k / 7,
// k = 0..7 (t in the bounds' own parameter).
double meanSurfaceArea(const LBounds& b, float lo = 0.0f, float hi = 1.0f);

// A(scene): surface area of the union of every primitive's bounds over the
// whole shutter [0,1]; the denominator shared by every kind.
double sceneSahArea(const SceneContext& ctx);

// Sums of one or more trees, turned into AccelStats by `fill`.
struct SahSums {
  double inner = 0.0, leaves = 0.0;
  size_t innerNodes = 0, leafNodes = 0, references = 0, maxDepth = 0, bytes = 0;

  void fill(AccelStats& s, double sceneArea) const {
    s.innerNodes = innerNodes;
    s.leafNodes = leafNodes;
    s.references = references;
    s.maxDepth = maxDepth;
    s.bytes = bytes;
    s.sahCost = sceneArea > 0.0 ? (inner + leaves) / sceneArea : 0.0;
  }
};

// Adds one tree whose nodes cover a time range of length T (tree parameter
// [0,1]). segOf(prim) gives the active segment count of a reference.
// maxDepth counts the wide nodes on a path plus the leaf.
template <int N, bool Motion, class SegOf>
void addTreeCost(const WideBvh<N, Motion>& bvh, double T, const SegOf& segOf, SahSums& sums) {
  sums.bytes += bvh.bytes();
  sums.references += bvh.prims.size();
  if (bvh.empty()) return;
  sums.innerNodes += bvh.nodes.size();
  sums.maxDepth = std::max(sums.maxDepth, size_t(bvh.depth) + 1);
  // Node boxes: the root's is the union of its lanes, others are in the parent.
  LBounds root;
  for (int i = 0; i < N; ++i)
    if (!bvh.nodes[0].isEmpty(i)) root.extend(bvh.nodes[0].bounds(i));
  sums.inner += meanSurfaceArea(root) * T;
  for (const auto& node : bvh.nodes)
    for (int i = 0; i < N; ++i) {
      if (node.isEmpty(i)) continue;
      const double area = meanSurfaceArea(node.bounds(i)) * T;
      if (node.isLeaf(i)) {
        double seg = 0.0;
        for (uint32_t k = 0; k < node.count[i]; ++k) seg += double(segOf(bvh.prims[node.child[i] + k]));
        sums.leaves += area * seg;
        ++sums.leafNodes;
      } else {
        sums.inner += area;
      }
    }
}

}  // namespace mbrt::detail
