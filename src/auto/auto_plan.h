// The decomposition of a scene's top level into objects (docs/auto.md):
//  - rigid parts: a moving mesh, or a connected piece of one, whose motion
//    one affine key per step reproduces (part_fit.h) becomes an instance of
//    its rest pose;
//  - near-rigid parts: a deforming mesh's triangles (those no single key
//    fits) are decomposed into clusters of coherent affine motion
//    (decompose.h, Günther et al. 2006 §4); each large enough cluster gets
//    a tree in its own frame over the residual motion (bvh/kinds/cluster_bvh.h);
//  - user instances stay instances (their scenes are built by `auto` too);
//  - everything else (static or deforming meshes, the pieces that fit no
//    key, segments, meshes with filters, which must see world-space rays)
//    stays world-space geometry, gathered into one object.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "auto/part_fit.h"
#include "mbrt/scene.h"

namespace mbrt::detail {

// Parts with fewer triangles stay world-space: an instance costs a ray
// transform per visit, which a handful of triangles does not repay. Pieces
// of a mesh need more: many small instances overlap in the top level where
// the mesh's own linear bounds serve them (measured: hairball and skinned
// slowed by pieces of 16-72 triangles, docs/auto.md).
constexpr uint32_t kMinRigidTriangles = 8;
constexpr uint32_t kMinRigidPieceTriangles = 256;

struct RigidPart {
  uint32_t geomID = 0;
  std::vector<uint32_t> prims;  // the part's triangles; empty: all of them
  PartFit fit;
};

// Clusters need enough triangles to repay the ray's transform into their
// frame; meshes need enough to be worth a decomposition.
constexpr uint32_t kMinClusterTriangles = 128;
constexpr uint32_t kMinClusterMeshTriangles = 512;
// Larger meshes are not decomposed: the clustering's Lloyd passes, the
// cluster trees and the flat trial that weighs them cost more than the
// build (deform's 199,712 triangles: 12.5 s against 2.5 s, for clusters
// its flat trial then refused; docs/auto.md, "Near-rigid clusters").
constexpr uint32_t kMaxClusterMeshTriangles = 32768;

struct ClusterPart {
  uint32_t geomID = 0;
  std::vector<uint32_t> prims;  // the cluster's triangles (sorted)
  std::vector<Affine3f> maps;   // per vertex step: the cluster's frame -> world
  double rmsResidual = 0;       // of the mesh's decomposition, relative to its diagonal
};

struct WorldPart {
  uint32_t geomID = 0;
  std::vector<uint32_t> prims;  // empty: all of the geometry's primitives
  std::string why;              // why it stays world-space
};

struct AutoPlan {
  std::vector<RigidPart> rigid;
  std::vector<ClusterPart> clusters;
  std::vector<uint32_t> userInstances;  // geometry ids
  std::vector<WorldPart> world;
  bool extracts() const { return !rigid.empty() || !clusters.empty(); }
};

// tolerance: relative to each part's diagonal (BuildOptions::autoFitTolerance);
// clusters: whether deforming meshes are decomposed into near-rigid clusters
// (not for an accel that will be refitted: BuildOptions::autoForRefits).
AutoPlan planDecomposition(const Scene& scene, double tolerance, bool clusters = true);

}  // namespace mbrt::detail
