// The one top-down build driver of the BVH family (STBVH §3.3, Algorithm 1):
// at each node it asks the split strategies for a split (object splits from
// binned_sah.h; temporal splits from temporal_split.h when the settings give
// a TemporalSource), compares the cheapest with the leaf cost and recurses,
// in parallel over subtrees. The result is a temporary binary tree that
// collapse.h turns into N-wide nodes. Without a TemporalSource this is the
// builder of bvh-interp, bvh-segments and frozen.
//
// Below a leaf decision the driver keeps splitting by objects, down to
// single references, and marks those nodes soft: collapse.h opens them only
// into spare lanes of a wide node and otherwise emits a soft node as one leaf
// (Embree's GeneralBVHBuilder fills a node by splitting its largest child
// whatever the SAH says; the SAH leaf decision stays with whole nodes).
//
// Extension point: `chooseSplit` in builder.cpp is where spatial splits
// (MSBVH/SBVH) would join; like temporal splits they produce two new
// reference sets, which the driver already handles.
#pragma once

#include <atomic>
#include <memory>
#include <span>
#include <vector>

#include <tbb/concurrent_vector.h>

#include "bvh/build_ref.h"
#include "core/build_budget.h"

namespace mbrt::detail {

class TemporalSource;

struct BuildSettings {
  int maxLeafSize = 8;
  int numBins = 32;
  float traversalCost = 1.0f;  // C_T; C_I = 1
  TimeRange range;             // the tree's time range (tree parameter)
  size_t parallelThreshold = 4096;  // subtrees larger than this run as tasks
  int maxBinnedDepth = 48;          // deeper: median splits (bounds the depth)
  const TemporalSource* temporal = nullptr;  // null: no temporal splits
  // Leaf-or-split in reference counts instead of MBSAH segment counts (the
  // choice between object and temporal splits stays MBSAH): our leaf test
  // costs one intersection per primitive whatever its segment count, so
  // leaves may keep several segments of a primitive (docs/stbvh.md).
  bool primitiveLeafCost = false;
  // With primitiveLeafCost: references counted in blocks of this many, so a
  // leaf of 2 costs what a leaf of 1 does (Embree counts blocks of 4): fewer,
  // fuller leaves and fewer nodes for a few more intersections per ray.
  int leafBlock = 1;
};

struct BinaryNode {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  LBounds bounds;         // linear bounds local to `range` (as BuildRef::bounds)
  TimeRange range;        // time range the node serves (tree parameter)
  float area = 0.0f;      // MBSAH area (half-area at the centre time) x range length
  uint32_t begin = 0;     // leaf or soft: primitives [begin, begin + count) of BinaryTree::prims
  uint32_t count = 0;
  uint32_t child[2] = {kNone, kNone};
  bool soft = false;      // below a leaf decision: a leaf unless opened to fill lanes
  bool isLeaf() const { return child[0] == kNone; }
};

// Memory charged by a tree in blocks as it grows; released with the tree.
class GrowingCharge {
 public:
  explicit GrowingCharge(BuildBudget& budget) : budget_(budget) {}
  ~GrowingCharge() { budget_.release(bytes_.load()); }
  void charge(size_t bytes, const char* what) {
    budget_.charge(bytes, what);
    bytes_ += bytes;
  }

 private:
  BuildBudget& budget_;
  std::atomic<size_t> bytes_{0};
};

// Node and primitive storage order depends on the thread count; the tree it
// describes does not (every decision depends only on the node's references).
struct BinaryTree {
  tbb::concurrent_vector<BinaryNode> nodes;
  tbb::concurrent_vector<PrimRef> prims;  // leaf primitives
  uint32_t root = BinaryNode::kNone;
  TimeRange range;  // the tree's time range (BuildSettings::range)
  std::unique_ptr<GrowingCharge> charge;
  bool empty() const { return root == BinaryNode::kNone; }

  // Built in place (concurrent_vector's moves are not to be relied on).
  BinaryTree() = default;
  BinaryTree(const BinaryTree&) = delete;
  BinaryTree& operator=(const BinaryTree&) = delete;
};

// Builds `tree` (empty) over `refs` (reordered; temporal splits work on copies). Charges the
// tree and the copies to `budget`, the tree for its lifetime.
void buildBinaryTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget, BinaryTree& tree);

}  // namespace mbrt::detail
