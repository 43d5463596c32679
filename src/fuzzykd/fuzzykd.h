// `fuzzykd`: fuzzy kd-trees with motion decomposition (Günther et al. 2006).
//
// Every animated triangle mesh is decomposed into clusters with one affine
// map per key (local frame -> world; scene_split.h). Each cluster gets one
// SAH kd-tree over its triangles' fuzzy boxes (fuzzy_boxes.h: the box of a
// triangle's local positions over the whole shutter, with a proven pad for
// the motion between keys), built once (cluster.h). A ray at time t is taken
// into a cluster's local frame by the inverse of the element-wise
// interpolated map at t; its leaf triangles are tested in world space at t
// (cluster_traverse.h). Every other primitive goes into one world-space
// motion kd-tree (world_tree.h). The top level is a wide motion BVH over
// the clusters' and that tree's linear bounds over the shutter
// (top_tree.h); each cluster also checks its box at t (interpolated key
// boxes).
#pragma once

#include <memory>
#include <vector>

#include "scene/scene_context.h"
#include "decompose/decompose.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeFuzzyKd(const SceneContext& context);

// Its build figures, through core/inspect.h (statsOf<FuzzyKdStats>).
struct FuzzyKdStats {
  size_t decomposedMeshes = 0;
  size_t clusters = 0;          // clusters with a fuzzy tree
  size_t fallbackClusters = 0;  // clusters whose triangles went to the world tree
  size_t fuzzyPrims = 0, worldPrims = 0;
  size_t fuzzyTreeBytes = 0;    // all bottom-level fuzzy trees: 8-byte nodes, 4-byte references
  size_t fuzzyNodes = 0, fuzzyRefs = 0;  // their nodes and leaf references
  size_t worldTreeBytes = 0;
  size_t topBytes = 0;          // top tree, and per cluster its maps, key boxes and triangle list
  double decomposeSeconds = 0, treeSeconds = 0;
  uint32_t maxSubdivisions = 0;
  double rmsResidual = 0;       // of the decomposed meshes (largest)
  std::vector<Decomposition> decompositions;  // per decomposed mesh (curves, transforms)
};

}  // namespace mbrt::detail
