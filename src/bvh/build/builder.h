// The one top-down build driver of the BVH family (STBVH §3.3, Algorithm 1):
// at each node it asks the split strategies for a split (object splits from
// binned_sah.h; temporal splits from temporal_split.h when the settings give
// a TemporalSource), compares the cheapest with the leaf cost and recurses,
// in parallel over subtrees. Without a TemporalSource this is the builder of
// bvh-interp, bvh-segments and frozen.
//
// Wide nodes are made as the build goes (§3.3, last paragraph): a node
// starts with the two children of its split and repeatedly splits the inner
// child with the largest area until it has N. Lanes still free then split
// the largest leaf by objects (Embree's GeneralBVHBuilder fills a node by
// splitting its largest child whatever the SAH says; the SAH's leaf decision
// stays with whole nodes). Such splits are made only where a lane takes
// them, so a leaf costs no nodes and no binning below it.
//
// The split strategies meet in heuristics/split_choice.h; a spatial split
// (MSBVH/SBVH) would join there, producing two new reference sets as a
// temporal split does (docs/architecture.md says why msbvh keeps its own
// driver for now).
#pragma once

#include <atomic>
#include <span>

#include "bvh/build/build_ref.h"
#include "bvh/nodes/wide_bvh.h"
#include "core/build_budget.h"

namespace mbrt::detail {

class TemporalSource;

struct BuildSettings {
  int maxLeafSize = 8;
  int numBins = 32;
  float traversalCost = 1.0f;  // C_T; C_I = 1
  // References a leaf tests at once (leaf blocks, `frozen`'s
  // triangle_block.h): the SAH charges a leaf per block (leafBlocks,
  // binned_sah.h), and filling a wide node's spare lanes leaves leaves of at
  // most this many whole (Embree's GeneralBVHBuilder: logBlockSize, and no
  // child of minLeafSize or fewer split to fill a node). 1: per reference.
  int leafBlock = 1;
  TimeRange range;             // the tree's time range (tree parameter)
  size_t parallelThreshold = 1024;  // subtrees larger than this run as tasks (Embree: 1024)
  int maxBinnedDepth = 48;          // deeper: median splits (bounds the depth)
  const TemporalSource* temporal = nullptr;  // null: no temporal splits
  // λ against a leaf: a temporal split replaces a leaf only when this many
  // times its cost, plus C_T, still beats the leaf (STBVH §3.2 penalises
  // temporal splits by λ = 1.25 against object splits for the references
  // they duplicate; docs/stbvh.md, "Quantised motion nodes and the
  // MBSAH's own leaf test").
  float temporalLeafPenalty = 1.0f;
  // A temporal split an ancestor tried and rejected is reused by its
  // object-split children (split_choice.h); off only to check, in tests,
  // that the trees are those of recomputing every trial.
  bool reuseTriedTemporalSplits = true;
};

// Memory charged by a growing structure in blocks; released with it.
class GrowingCharge {
 public:
  explicit GrowingCharge(BuildBudget& budget) : budget_(budget) {}
  ~GrowingCharge() { budget_.release(bytes_.load()); }
  GrowingCharge(const GrowingCharge&) = delete;
  GrowingCharge& operator=(const GrowingCharge&) = delete;
  void charge(size_t bytes, const char* what) {
    budget_.charge(bytes, what);
    bytes_ += bytes;
  }

 private:
  BuildBudget& budget_;
  std::atomic<size_t> bytes_{0};
};

// Builds `out` over `refs` (reordered; temporal splits work on copies). The
// result is bit-identical whatever the thread count (wide_layout.h). Charges
// the scratch to `budget` while it lives and the tree for good.
template <int N, bool Motion>
void buildWideTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget,
                   WideBvh<N, Motion>& out);

}  // namespace mbrt::detail
