// The compact kd-tree layout shared by the static kd-tree, `mbkd` and the
// fuzzy kd-tree: 8-byte nodes in depth-first order (the left child follows
// its parent) and leaf references that carry a time interval.
#pragma once

#include <bit>
#include <cstdint>
#include <vector>

#include "mbrt/math.h"

namespace mbrt::detail {

// Inner: word = split position (float bits), bits = right child << 2 | axis.
// Leaf:  word = first reference,             bits = count << 2 | 3.
struct KdNode {
  uint32_t word = 0;
  uint32_t bits = 3;

  static KdNode inner(int axis, float split, uint32_t rightChild) {
    return {std::bit_cast<uint32_t>(split), (rightChild << 2) | uint32_t(axis)};
  }
  static KdNode leaf(uint32_t first, uint32_t count) { return {first, (count << 2) | 3u}; }

  bool isLeaf() const { return (bits & 3u) == 3u; }
  int axis() const { return int(bits & 3u); }
  float split() const { return std::bit_cast<float>(word); }
  uint32_t rightChild() const { return bits >> 2; }
  uint32_t first() const { return word; }
  uint32_t count() const { return bits >> 2; }
};
static_assert(sizeof(KdNode) == 8);

// Largest child index / leaf count a node can hold.
inline constexpr uint32_t kKdMaxIndex = (1u << 30) - 1;

// A leaf reference: primitive index and the closed time interval during which
// the primitive can be inside the leaf's cell (conservative). A static tree
// stores [0, 1] (or the primitive's time range).
struct KdLeafRef {
  uint32_t prim;
  float t0, t1;
};
static_assert(sizeof(KdLeafRef) == 12);

struct KdTree {
  std::vector<KdNode> nodes;    // nodes[0] is the root
  std::vector<KdLeafRef> refs;  // leaves' references, contiguous per leaf
  Box3f root;                   // the root cell
  uint32_t depth = 0;           // levels of the deepest leaf (root = 1)

  bool empty() const { return nodes.empty(); }
  size_t bytes() const { return nodes.size() * sizeof(KdNode) + refs.size() * sizeof(KdLeafRef); }
};

// Calls fn(node, cell, depth) for `node` and every node below it, cells
// split at the nodes' planes (depth: the node's level, root = 1).
template <class Fn>
void forEachKdCell(const std::vector<KdNode>& nodes, uint32_t node, const Box3f& cell, const Fn& fn, int depth = 1) {
  fn(node, cell, depth);
  const KdNode& n = nodes[node];
  if (n.isLeaf()) return;
  Box3f l = cell, r = cell;
  l.upper[n.axis()] = n.split();
  r.lower[n.axis()] = n.split();
  forEachKdCell(nodes, node + 1, l, fn, depth + 1);
  forEachKdCell(nodes, n.rightChild(), r, fn, depth + 1);
}

}  // namespace mbrt::detail
