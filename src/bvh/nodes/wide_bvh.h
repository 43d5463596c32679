// One N-wide BVH: nodes in depth-first order (root = node 0) and the
// primitive references its leaves point into (one-reference leaves may keep
// theirs in the node: kInlineLeaf, wide_node.h).
#pragma once

#include <span>
#include <vector>

#include "bvh/nodes/wide_node.h"
#include "core/prim_ref.h"
#include "mbrt/math.h"

namespace mbrt::detail {

template <int N, bool Motion>
struct WideBvh {
  using Node = WideNode<N, Motion>;
  std::vector<Node> nodes;
  std::vector<PrimRef> prims;
  std::vector<LaneTimes<N>> times;  // lane time ranges of spatial-temporal nodes
  uint32_t depth = 0;       // wide nodes on the longest root-to-leaf path
  uint32_t stackSize = 1;   // traversal stack entries the tree can need
  size_t inlineRefs = 0;    // references kept in nodes, not in `prims`
  size_t paddingRefs = 0;   // entries of `prims` that only align leaves to blocks (layOut)

  bool empty() const { return nodes.empty(); }
  size_t numReferences() const { return prims.size() - paddingRefs + inlineRefs; }
  // The references of leaf lane `lane` of `node` (an inline one is made in `one`).
  std::span<const PrimRef> leafRefs(const Node& node, int lane, PrimRef& one) const {
    if (node.count[lane] == kInlineLeaf) {
      one = {node.leafGeom, node.child[lane]};
      return {&one, 1};
    }
    return {prims.data() + node.child[lane], node.count[lane]};
  }
  size_t bytes() const {
    return nodes.size() * sizeof(Node) + prims.size() * sizeof(PrimRef) + times.size() * sizeof(LaneTimes<N>);
  }
};

}  // namespace mbrt::detail
