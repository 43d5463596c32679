// A wide BVH's leaves as the leaf formats lay them out (leaves/leaf_format.h):
// its reference table and every leaf kept there, in node order.
#pragma once

#include <optional>

#include "bvh/nodes/wide_bvh.h"
#include "leaves/leaf_format.h"

namespace mbrt::detail {

template <int N, bool Motion>
LeafTable leafTable(const WideBvh<N, Motion>& bvh, std::optional<float> fixedTime = {}) {
  LeafTable t;
  t.prims = bvh.prims;
  t.someInNodes = bvh.inlineRefs != 0;
  t.fixedTime = fixedTime;
  for (const auto& node : bvh.nodes)
    for (int lane = 0; lane < N; ++lane)
      if (node.isLeaf(lane) && node.count[lane] != kInlineLeaf) t.leaves.push_back({node.child[lane], node.count[lane]});
  return t;
}

}  // namespace mbrt::detail
