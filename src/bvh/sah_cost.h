// The SAH sums of a wide BVH (core/sah_sums.h gives the formula).
#pragma once

#include <algorithm>
#include <span>

#include "bvh/nodes/wide_bvh.h"
#include "core/sah_sums.h"
#include "scene/scene_area.h"

namespace mbrt::detail {

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
