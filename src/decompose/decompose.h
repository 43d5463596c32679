// Motion decomposition (Günther et al. 2006, §3): a triangle mesh animated
// over K keys (fixed connectivity) is split into clusters whose motion is
// one affine map per key plus a small residual.
//
//  - fit: per cluster and key, the least-squares affine map from the rest
//    pose to the key pose (centred moments, affine_fit.h); every triangle
//    adds its three vertices and a normal tip (centroid + n / sqrt|n|, as
//    in deformation transfer) so that a flat cluster still defines a frame;
//  - cluster (Algorithm 1): generalized Lloyd relaxation, alternating fits
//    and reassignment of every triangle to the cluster where its residual is
//    smallest, until the total residual improves by less than `lloydTol`;
//    then a new cluster seeded at the worst triangle and its neighbours,
//    existing clusters re-seeded with their best triangles (residual at most
//    their median), and again, until a new cluster lowers the residual by
//    less than `insertTol` (or it is ~0, or `maxClusters` is reached);
//  - the search runs on at most `searchKeys` evenly subsampled keys; the
//    rest pose is then chosen among those keys by Eq. 3 and a final Lloyd
//    pass and fit use every key;
//  - the start: one cluster per connected piece of the mesh;
//  - a per-cluster PCA frame of the fuzzy positions (§3.4): the transforms
//    returned map the cluster's local frame to world space at each key.
// Parallel over triangles (TBB).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "decompose/affine_fit.h"
#include "mbrt/scene.h"

namespace mbrt::detail {

struct DecomposeParams {
  uint32_t maxClusters = 64;
  uint32_t searchKeys = 8;
  double lloydTol = 1e-3;   // Lloyd stops below this relative improvement
  double insertTol = 0.02;  // clustering stops when a new cluster gains less
  int maxLloyd = 12;
  // Relative residual (to the motion's spread) below which the fit is exact.
  double exactTol = 1e-10;
  // Start from one cluster per connected piece (false: one cluster).
  bool startFromPieces = true;
};

// One row of the clustering curve (the paper's Fig. 7).
struct ClusterStep {
  uint32_t clusters = 0;
  double residual = 0;    // sum over search keys of squared vertex residuals
  double fuzzyArea = 0;   // sum of the triangles' fuzzy-box areas (rest space, search keys)
  double seconds = 0;     // since the start
};

struct Decomposition {
  uint32_t numClusters = 0;
  uint32_t restKey = 0;
  std::vector<uint32_t> clusterOf;               // per triangle
  std::vector<std::vector<Affine3d>> transforms;  // [cluster][key]: local -> world
  std::vector<ClusterStep> curve;
  double residual = 0;      // final, over every key (sum of squares)
  double rmsResidual = 0;   // sqrt(residual / (3 T K))
  double seconds = 0;
};

// keys[k][v]: vertex positions at key k (K >= 1 keys).
Decomposition decomposeMotion(std::span<const Triangle> triangles, const std::vector<std::vector<Vec3f>>& keys,
                              const DecomposeParams& params = {});

// The keys of a triangle geometry.
std::vector<std::vector<Vec3f>> geometryKeys(const Geometry& g);

// Connected pieces (triangles sharing a vertex): per triangle its piece.
std::vector<uint32_t> connectedPieces(std::span<const Triangle> triangles, uint32_t numVertices, uint32_t& count);

}  // namespace mbrt::detail
