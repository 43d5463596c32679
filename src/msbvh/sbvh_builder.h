// The topology of the MSBVH: an SBVH (Stich et al. 2009) built for the
// geometry at t = 0.5 (MSBVH §3). At each node: the binned object split (the
// shared binner, bvh/heuristics/binned_sah.h); if the two object-split
// children overlap by more than alpha times the root's area, also the binned
// spatial split with reference chopping and unsplitting
// (bvh/heuristics/spatial_split.h); the cheapest of these against the leaf
// cost. Reference growth is capped: the root may add maxGrowth * (primitives)
// references, and every split hands what is left to its children in
// proportion to their sizes (so the tree does not depend on thread timing).
#pragma once

#include <memory>
#include <vector>

#include "bvh/heuristics/spatial_split.h"

namespace mbrt::detail {

struct SbvhSettings {
  int maxLeafSize = 8;
  int objectBins = 32;
  int spatialBins = 32;        // at most; a node uses adaptiveObjectBins(spatialBins, its references)
  float traversalCost = 1.0f;  // C_T; C_I = 1
  float alpha = 1e-5f;         // overlap threshold (1 disables spatial splits)
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
  Box3f box;                         // union of the references' boxes
  std::unique_ptr<SbvhNode> child[2];
  std::vector<SplitRef> refs;        // nodes without children only
  bool fill = false;                 // an SAH leaf or below one
  bool isLeaf() const { return !child[0]; }
};

struct SbvhStats {
  size_t spatialSplits = 0, objectSplits = 0;
};

std::unique_ptr<SbvhNode> buildSbvh(std::vector<SplitRef> refs, const SbvhSettings& settings,
                                    const RefClipper& clipper);

}  // namespace mbrt::detail
