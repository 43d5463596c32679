// The one top-down build driver of the BVH family (STBVH §3.3, Algorithm 1,
// without temporal splits yet): at each node it asks the split strategies
// for a split, compares the cheapest with the leaf cost and recurses, in
// parallel over subtrees. The result is a temporary binary tree that
// collapse.h turns into N-wide nodes.
//
// Extension points: `chooseSplit` in builder.cpp is where temporal splits
// (STBVH) and spatial splits (MSBVH/SBVH) join the object split; both
// produce two reference sets, which the driver already handles.
#pragma once

#include <atomic>
#include <memory>
#include <span>
#include <vector>

#include "bvh/build_ref.h"
#include "core/build_budget.h"

namespace mbrt::detail {

struct BuildSettings {
  int maxLeafSize = 8;
  int numBins = 32;
  float traversalCost = 1.0f;  // C_T; C_I = 1
  TimeRange range;             // the tree's time range (tree parameter)
  size_t parallelThreshold = 4096;  // subtrees larger than this run as tasks
  int maxBinnedDepth = 48;          // deeper: median splits (bounds the depth)
};

struct BinaryNode {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  LBounds bounds;
  float area = 0.0f;      // MBSAH area (half-area at the centre time)
  uint32_t begin = 0;     // references [begin, begin + count)
  uint32_t count = 0;
  uint32_t child[2] = {kNone, kNone};
  bool isLeaf() const { return child[0] == kNone; }
};

// Node storage order depends on the thread count; the tree it describes does
// not (every decision depends only on the references of the node).
struct BinaryTree {
  std::vector<BinaryNode> nodes;
  uint32_t root = BinaryNode::kNone;
  std::unique_ptr<ScopedCharge> charge;
  bool empty() const { return root == BinaryNode::kNone; }
};

// Builds over `refs`, reordering them so every leaf is a contiguous range.
// Charges the tree to `budget` for its lifetime.
BinaryTree buildBinaryTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget);

}  // namespace mbrt::detail
