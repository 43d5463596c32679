#include "auto/auto_plan.h"

#include "decompose/decompose.h"

namespace mbrt::detail {
namespace {

// The connected pieces of a mesh that no single key fits: each piece that
// moves rigidly becomes a part; the rest stays world-space.
void planPieces(const Geometry& g, uint32_t geomID, double tolerance, AutoPlan& plan) {
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
  plan.world.push_back(std::move(rest));
}

}  // namespace

AutoPlan planDecomposition(const Scene& scene, double tolerance) {
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
      planPieces(g, id, tolerance, plan);
    }
  }
  return plan;
}

}  // namespace mbrt::detail
