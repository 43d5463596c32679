// The split of a scene into decomposed clusters and world primitives
// (Günther et al. 2006 §3-4): every animated triangle mesh (>= 2 steps,
// enough triangles, every triangle with finite bounds) is decomposed
// (decompose/decompose.h) into clusters; a cluster with enough triangles and
// a usable fuzzy-box bound (fuzzy_boxes.h) gets its own tree (cluster.h).
// Everything else goes to the world tree: static meshes, segments,
// instances, small meshes, and the triangles of small or unsafe clusters.
#pragma once

#include <vector>

#include "fuzzykd/cluster.h"
#include "fuzzykd/fuzzykd.h"

namespace mbrt::detail {

struct SceneSplit {
  std::vector<Cluster> clusters;
  // World primitives: those of the geometries not decomposed, in geometry
  // order, then the triangles of the decomposed meshes' rejected clusters.
  std::vector<PrimRef> world;
};

// Fills the decomposition figures of `stats` (meshes, clusters that fell
// back, residual, sub-samples, the decompositions themselves).
SceneSplit splitScene(const SceneContext& ctx, FuzzyKdStats& stats);

}  // namespace mbrt::detail
