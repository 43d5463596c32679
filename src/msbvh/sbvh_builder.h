// The topology of the MSBVH: an SBVH (Stich et al. 2009) built for the
// geometry at t = 0.5 (MSBVH §3). At each node: the binned object split (the
// shared binner, bvh/heuristics/binned_sah.h); if the two object-split
// children overlap by more than alpha times the root's area (and
// nodeOverlap times the node's), also the binned spatial split with reference chopping and unsplitting
// (bvh/heuristics/spatial_split.h); the cheapest of these against the leaf
// cost. Reference growth is capped: the root may add maxGrowth * (primitives)
// references, and every split hands what is left to its children in
// proportion to their sizes (so the tree does not depend on thread timing).
//
// Storage: one reference array in which every subtree's references are
// followed by its growth room (the budget it was handed), so splits work in
// place, and the nodes in one growing array; no node allocates.
#pragma once

#include <span>
#include <vector>

#include <tbb/concurrent_vector.h>

#include "bvh/heuristics/spatial_split.h"
#include "core/huge_pages.h"

namespace mbrt::detail {

struct SbvhSettings {
  int maxLeafSize = 8;
  int objectBins = 32;         // at most; a node uses adaptiveObjectBins(objectBins, its references)
  int spatialBins = 32;        // at most; a node uses adaptiveObjectBins(spatialBins, its references)
  float traversalCost = 1.0f;  // C_T; C_I = 1
  float alpha = 1e-5f;         // overlap threshold (1 disables spatial splits)
  // Spatial splits are also tried only where the object split's children
  // overlap by more than this fraction of the node's own area: below it
  // they were almost never taken and the SAH barely moves
  // (docs/performance.md, "Builds"), and their binning, chopping every
  // reference on three axes, is most of the build.
  float nodeOverlap = 0.1f;
  // Spatial splits binned on the node box's longest axis only, not all
  // three: a third of the chopping for an SAH within a fraction of a
  // percent of binning all three (docs/performance.md, "Builds").
  bool spatialLongestAxisOnly = true;
  float maxGrowth = 0.3f;      // extra references, as a fraction of the primitives
  size_t parallelThreshold = 4096;
  int maxBinnedDepth = 48;     // deeper: median splits only
};

// A node the SAH made a leaf is still split down to single references, by
// object splits, and it and the nodes below it are marked `fill`: the N-wide
// collapse opens these only for lanes no inner node needs (Embree's node
// filling), so a half-full node's leaves get tested one lane each at no
// extra node.
struct SbvhNode {
  static constexpr uint32_t kNone = ~0u;
  Box3f box;                           // union of the references' boxes
  uint32_t child[2] = {kNone, kNone};  // indices in SbvhTree::nodes
  std::span<const SplitRef> refs;      // nodes without children only (in SbvhTree's arrays)
  bool fill = false;                   // an SAH leaf or below one
  bool isLeaf() const { return child[0] == kNone; }
};

struct SbvhTree {
  tbb::concurrent_vector<SbvhNode, HugePageAllocator<SbvhNode>> nodes;  // the root first
  std::vector<SplitRef> refs;  // the leaves' references, with the subtrees' growth room
  // Subtrees whose spatial split added more references than their room (the
  // binned counts are estimates): their references live here.
  tbb::concurrent_vector<std::vector<SplitRef>> overflow;

  bool empty() const { return nodes.empty(); }
  const SbvhNode& root() const { return nodes[0]; }
  const SbvhNode& child(const SbvhNode& n, int i) const { return nodes[n.child[i]]; }
};

SbvhTree buildSbvh(std::vector<SplitRef> refs, const SbvhSettings& settings, const RefClipper& clipper);

}  // namespace mbrt::detail
