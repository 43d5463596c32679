// The top level of the fuzzy kd-tree (Günther et al. 2006 §3: a BVH over the
// clusters, each with its own transform): a wide motion BVH made by the BVH
// family's driver (bvh/build/builder.h) over one reference per item, a
// cluster or the world tree, with the item's linear bounds over the shutter.
// Every leaf holds one item; a ray visits the items whose node boxes it
// enters at its time, nearest box first (bvh/traverse.h).
#pragma once

#include <span>

#include "bvh/nodes/wide_bvh.h"
#include "bvh/traverse.h"

namespace mbrt::detail {

// Few items (tens to hundreds of clusters): 4 lanes, one SSE pack a node.
inline constexpr int kTopWidth = 4;
using TopTree = WideBvh<kTopWidth, true>;

// The tree over items[i] (the primID of leaf references is i).
void buildTopTree(const SceneContext& ctx, std::span<const LBounds> items, TopTree& out);

// visit(i) for every item i whose leaf the ray enters at ray.time, nearest
// first; visit returns true on a hit (AnyHit: the walk stops), and may
// shorten ray.tfar. Count adds the top nodes visited and their box tests.
template <bool AnyHit, bool Count, class Visit>
bool traverseTop(const TopTree& top, RayQuery& ray, TraversalCounters* counters, Visit&& visit) {
  if (top.empty()) return false;
  constexpr int N = kTopWidth;
  const NodeRay<packWidth<N>()> r(ray, ray.time);
  const auto nodeAt = [&](uint32_t i) -> const TopTree::Node& { return top.nodes[i]; };
  return wideTraverse<AnyHit, Count, N>(
      top.stackSize, ray, counters, nodeAt,
      [&](const TopTree::Node& node, uint32_t, float* dist) {
        const LaneTimes<N>* times = node.hasTimes() ? &top.times[node.times] : nullptr;
        return intersectNode<packWidth<N>()>(node, r, ray.tfar, dist, times);
      },
      [&](const TraversalItem& item) {
        // wideTraverse counts a leaf's references as primitive tests; an
        // item's own tree counts its tests.
        if constexpr (Count) counters->primitiveTests -= item.leafSize();
        PrimRef one;
        const PrimRef* refs = item.references(top.prims.data(), one);
        bool found = false;
        for (uint32_t i = 0, n = item.leafSize(); i < n; ++i)
          if (visit(refs[i].primID)) {
            if constexpr (AnyHit) return true;
            found = true;
          }
        return found;
      },
      NodeLines<decltype(nodeAt)>{nodeAt, prefetchPays(top.nodes.size() * sizeof(TopTree::Node))});
}

}  // namespace mbrt::detail
