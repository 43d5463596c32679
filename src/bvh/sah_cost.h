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
// whole shutter [0,1]; the denominator shared by every kind. A pass over
// every primitive: computed when stats are asked for, not in the build.
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

template <int N, bool Motion, class SegOf>
void addLaneCosts(const WideBvh<N, Motion>& bvh, uint32_t index, TimeRange range, double T, const SegOf& segOf,
                  SahSums& sums) {
  const auto& node = bvh.nodes[index];
  for (int i = 0; i < N; ++i) {
    if (node.isEmpty(i)) continue;
    TimeRange r = range;
    if (node.hasTimes()) {
      const LaneTimes<N>& t = bvh.times[node.times];
      r = {std::max(range.lo, t.t0[i]), std::min(range.hi, t.t1[i])};
    }
    const double area = meanSurfaceArea(node.bounds(i), r.lo, r.hi) * T * double(r.size());
    if (node.isLeaf(i)) {
      double seg = 0.0;
      PrimRef one;
      for (const PrimRef& p : bvh.leafRefs(node, i, one)) seg += double(segOf(p, r));
      sums.leaves += area * seg;
      ++sums.leafNodes;
    } else {
      sums.inner += area;
      addLaneCosts(bvh, node.child[i], r, T, segOf, sums);
    }
  }
}

// Adds one tree whose nodes cover a time range of length T (tree parameter
// [0,1]); lanes of spatial-temporal nodes cover their part of it.
// segOf(prim, range) gives the active segment count of a reference in a leaf
// serving `range` (tree parameter). maxDepth counts the wide nodes on a path
// plus the leaf.
template <int N, bool Motion, class SegOf>
void addTreeCost(const WideBvh<N, Motion>& bvh, double T, const SegOf& segOf, SahSums& sums) {
  sums.bytes += bvh.bytes();
  sums.references += bvh.numReferences();
  if (bvh.empty()) return;
  sums.innerNodes += bvh.nodes.size();
  sums.maxDepth = std::max(sums.maxDepth, size_t(bvh.depth) + 1);
  // Node boxes: the root's is the union of its lanes (those serving the
  // time, for a spatial-temporal root), others are in the parent.
  const auto& root = bvh.nodes[0];
  double rootArea = 0.0;
  for (int k = 0; k < 8; ++k) {
    const float t = float(k) / 7.0f;
    Box3f box;
    for (int i = 0; i < N; ++i) {
      if (root.isEmpty(i)) continue;
      if (root.hasTimes() && !(bvh.times[root.times].t0[i] <= t && t <= bvh.times[root.times].t1[i])) continue;
      box.extend(root.bounds(i).at(t));
    }
    if (!box.empty()) rootArea += double(box.area());
  }
  sums.inner += rootArea / 8.0 * T;
  addLaneCosts(bvh, 0, TimeRange{0.0f, 1.0f}, T, segOf, sums);
}

}  // namespace mbrt::detail
