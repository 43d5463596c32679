#include "auto/auto_plan.h"

#include <algorithm>
#include <cmath>

#include "decompose/decompose.h"

namespace mbrt::detail {
namespace {

// The triangles `rest` of a deforming mesh (empty: all of them) decomposed
// into clusters of coherent affine motion: each cluster of at least
// kMinClusterTriangles becomes a part; the others' triangles stay in `rest`.
void planClusters(const Geometry& g, uint32_t geomID, uint32_t pieces, WorldPart& rest, AutoPlan& plan) {
  std::vector<uint32_t> ids = rest.prims;
  if (ids.empty())
    for (uint32_t t = 0; t < g.numPrimitives(); ++t) ids.push_back(t);
  if (ids.size() < kMinClusterMeshTriangles) return;
  std::vector<Triangle> tris;
  for (uint32_t t : ids) tris.push_back(g.triangles()[t]);
  DecomposeParams params;
  // Many pieces (unwelded seams, debris): start from one cluster instead.
  if (pieces > params.maxClusters) params.startFromPieces = false;
  const Decomposition d = decomposeMotion(tris, geometryKeys(g), params);
  std::vector<std::vector<uint32_t>> members(d.numClusters);
  for (size_t i = 0; i < ids.size(); ++i) members[d.clusterOf[i]].push_back(ids[i]);
  Box3f rest0;
  for (uint32_t v = 0; v < g.vertices(0).count; ++v) rest0.extend(g.vertices(0)[v]);
  const double diagonal = double(length(rest0.upper - rest0.lower));
  std::vector<uint32_t> left;
  const size_t before = plan.clusters.size();
  for (uint32_t c = 0; c < d.numClusters; ++c) {
    if (members[c].size() < kMinClusterTriangles) {
      left.insert(left.end(), members[c].begin(), members[c].end());
      continue;
    }
    ClusterPart part{geomID, std::move(members[c]), {}, diagonal > 0 ? d.rmsResidual / diagonal : 0.0};
    std::sort(part.prims.begin(), part.prims.end());
    for (const Affine3d& m : d.transforms[c]) part.maps.push_back(m.toFloat());
    plan.clusters.push_back(std::move(part));
  }
  if (plan.clusters.size() == before) return;  // no cluster large enough: the rest stays as it was
  std::sort(left.begin(), left.end());
  rest.prims = std::move(left);
  rest.why = "the triangles of no cluster large enough (of " + std::to_string(d.numClusters) + ")";
}

// The connected pieces of a mesh that no single key fits: each piece that
// moves rigidly becomes a part; the rest stays world-space.
void planPieces(const Geometry& g, uint32_t geomID, double tolerance, bool clusters, AutoPlan& plan) {
  uint32_t count = 0;
  const std::vector<uint32_t> pieceOf = connectedPieces(g.triangles(), uint32_t(g.vertices(0).count), count);
  WorldPart rest{geomID, {}, "deforms: no affine key per step fits it or its connected pieces"};
  if (count > 1) {
    std::vector<std::vector<uint32_t>> pieces(count);
    for (uint32_t t = 0; t < pieceOf.size(); ++t) pieces[pieceOf[t]].push_back(t);
    for (std::vector<uint32_t>& piece : pieces) {
      if (piece.size() >= kMinRigidPieceTriangles) {
        PartFit fit = fitPart(g, usedVertices(g, piece), tolerance);
        if (fit.fits && fit.moves) {
          plan.rigid.push_back({geomID, std::move(piece), std::move(fit)});
          continue;
        }
      }
      rest.prims.insert(rest.prims.end(), piece.begin(), piece.end());
    }
    if (rest.prims.empty()) return;
    if (rest.prims.size() == g.numPrimitives()) rest.prims.clear();  // nothing extracted
    else rest.why = "the pieces that no affine key per step fits";
  }
  if (clusters && g.numPrimitives() <= kMaxClusterMeshTriangles) {
    const size_t before = plan.clusters.size();
    planClusters(g, geomID, count, rest, plan);
    if (plan.clusters.size() != before && rest.prims.empty()) return;  // every triangle in a cluster
  }
  plan.world.push_back(std::move(rest));
}

}  // namespace

AutoPlan planDecomposition(const Scene& scene, double tolerance, bool clusters) {
  AutoPlan plan;
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Instance) {
      plan.userInstances.push_back(id);
      continue;
    }
    if (g.type() == GeometryType::Segments) {
      plan.world.push_back({id, {}, "segments"});
      continue;
    }
    if (g.numSteps() == 1) {
      plan.world.push_back({id, {}, "static"});
      continue;
    }
    if (g.hasFilter()) {  // a filter sees the ray in the geometry's space
      plan.world.push_back({id, {}, "has a filter (it sees world-space rays)"});
      continue;
    }
    std::vector<uint32_t> all(g.numPrimitives());
    for (uint32_t t = 0; t < all.size(); ++t) all[t] = t;
    PartFit whole = fitPart(g, usedVertices(g, all), tolerance);
    if (whole.fits && !whole.moves) {
      plan.world.push_back({id, {}, "moves less than the tolerance"});
    } else if (whole.fits && g.numPrimitives() >= kMinRigidTriangles) {
      plan.rigid.push_back({id, {}, std::move(whole)});
    } else if (whole.fits) {
      plan.world.push_back({id, {}, "rigid, but too few triangles to repay an instance"});
    } else {
      planPieces(g, id, tolerance, clusters, plan);
    }
  }
  return plan;
}

}  // namespace mbrt::detail
