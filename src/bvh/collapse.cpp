#include "bvh/collapse.h"

#include <algorithm>

namespace mbrt::detail {
namespace {

// The binary nodes that become the lanes of the wide node made for `id`.
template <int N>
int openChildren(const BinaryTree& tree, uint32_t id, uint32_t (&lanes)[N]) {
  const BinaryNode& node = tree.nodes[id];
  if (node.isLeaf()) {  // only a leaf root gets here
    lanes[0] = id;
    return 1;
  }
  int n = 2;
  lanes[0] = node.child[0];
  lanes[1] = node.child[1];
  while (n < N) {
    int best = -1;
    for (int i = 0; i < n; ++i) {
      const BinaryNode& c = tree.nodes[lanes[i]];
      if (!c.isLeaf() && (best < 0 || c.area > tree.nodes[lanes[best]].area)) best = i;
    }
    if (best < 0) break;
    const BinaryNode& open = tree.nodes[lanes[best]];
    for (int i = n; i > best + 1; --i) lanes[i] = lanes[i - 1];  // keep spatial order
    lanes[best] = open.child[0];
    lanes[best + 1] = open.child[1];
    ++n;
  }
  return n;
}

template <int N>
size_t countNodes(const BinaryTree& tree, uint32_t id) {
  uint32_t lanes[N];
  const int n = openChildren<N>(tree, id, lanes);
  size_t total = 1;
  for (int i = 0; i < n; ++i)
    if (!tree.nodes[lanes[i]].isLeaf()) total += countNodes<N>(tree, lanes[i]);
  return total;
}

template <int N, bool Motion>
uint32_t emit(const BinaryTree& tree, uint32_t id, WideBvh<N, Motion>& out, uint32_t depth) {
  const uint32_t index = uint32_t(out.nodes.size());
  out.nodes.emplace_back();
  out.nodes[index].clear();
  out.depth = std::max(out.depth, depth);
  uint32_t lanes[N];
  const int n = openChildren<N>(tree, id, lanes);
  // Stack bound: every level leaves at most N-1 siblings behind.
  out.stackSize = std::max(out.stackSize, (N - 1) * depth + 1);
  for (int i = 0; i < n; ++i) {
    const BinaryNode& c = tree.nodes[lanes[i]];
    out.nodes[index].setBounds(i, c.bounds);
    if (c.isLeaf()) {
      out.nodes[index].child[i] = c.begin;
      out.nodes[index].count[i] = uint8_t(c.count);
    } else {
      const uint32_t childIndex = emit(tree, lanes[i], out, depth + 1);
      out.nodes[index].child[i] = childIndex;
    }
  }
  return index;
}

}  // namespace

template <int N, bool Motion>
void collapse(const BinaryTree& tree, std::span<const BuildRef> refs, WideBvh<N, Motion>& out, BuildBudget& budget) {
  out = WideBvh<N, Motion>();
  if (tree.empty()) return;
  const size_t numNodes = countNodes<N>(tree, tree.root);
  budget.charge(numNodes * sizeof(WideNode<N, Motion>) + refs.size() * sizeof(PrimRef), "the BVH nodes");
  out.nodes.reserve(numNodes);
  out.prims.resize(refs.size());
  for (size_t i = 0; i < refs.size(); ++i) out.prims[i] = refs[i].prim;
  emit(tree, tree.root, out, 1);
}

template void collapse<2, true>(const BinaryTree&, std::span<const BuildRef>, WideBvh<2, true>&, BuildBudget&);
template void collapse<4, true>(const BinaryTree&, std::span<const BuildRef>, WideBvh<4, true>&, BuildBudget&);
template void collapse<8, true>(const BinaryTree&, std::span<const BuildRef>, WideBvh<8, true>&, BuildBudget&);
template void collapse<2, false>(const BinaryTree&, std::span<const BuildRef>, WideBvh<2, false>&, BuildBudget&);
template void collapse<4, false>(const BinaryTree&, std::span<const BuildRef>, WideBvh<4, false>&, BuildBudget&);
template void collapse<8, false>(const BinaryTree&, std::span<const BuildRef>, WideBvh<8, false>&, BuildBudget&);

}  // namespace mbrt::detail
