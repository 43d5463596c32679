#include "fuzzykd/scene_split.h"

#include <algorithm>

#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

constexpr uint32_t kMinMeshTriangles = 32;
constexpr uint32_t kMinClusterTriangles = 4;

class Splitter {
 public:
  Splitter(const SceneContext& ctx, FuzzyKdStats& stats) : ctx_(ctx), stats_(stats) {}

  SceneSplit run() {
    const Scene& scene = ctx_.scene();
    // Primitives with non-finite bounds can never be hit: dropped.
    std::vector<std::vector<PrimRef>> perGeometry(scene.numGeometries());
    Box3f sceneBox;
    for (uint32_t g = 0; g < scene.numGeometries(); ++g) {
      const Geometry& geo = ctx_.geometry(g);
      for (uint32_t p = 0; p < geo.numPrimitives(); ++p) {
        const LBounds b = linearBounds(ctx_, {g, p}, {0.0f, 1.0f});
        if (!isUsable(b)) continue;
        perGeometry[g].push_back({g, p});
        sceneBox.extend(b.hull());
      }
    }
    worldMag_ = sceneBox.empty() ? 1.0 : std::max(normInf(toD(sceneBox.lower)), normInf(toD(sceneBox.upper)));
    for (uint32_t g = 0; g < scene.numGeometries(); ++g)
      if (!decomposeMesh(g, ctx_.geometry(g), perGeometry[g]))
        out_.world.insert(out_.world.end(), perGeometry[g].begin(), perGeometry[g].end());
    out_.world.insert(out_.world.end(), rejected_.begin(), rejected_.end());
    return std::move(out_);
  }

 private:
  // Decomposes one geometry into clusters; false: all its primitives go to
  // the world tree. Small clusters and unsafe ones go there too (through
  // `rejected_`).
  bool decomposeMesh(uint32_t g, const Geometry& geo, const std::vector<PrimRef>& prims) {
    if (geo.type() != GeometryType::Triangles || geo.numSteps() < 2 || prims.size() < kMinMeshTriangles ||
        prims.size() != geo.numPrimitives())
      return false;
    DecomposeParams params;
    uint32_t pieces = 0;
    const auto tris = geo.triangles();
    connectedPieces(tris, uint32_t(geo.vertices(0).count), pieces);
    // Many pieces (unwelded seams, debris): start from one cluster instead.
    if (pieces > params.maxClusters) params.startFromPieces = false;
    Decomposition d = decomposeMotion(tris, geometryKeys(geo), params);
    stats_.decomposedMeshes++;
    stats_.rmsResidual = std::max(stats_.rmsResidual, d.rmsResidual);
    std::vector<std::vector<PrimRef>> members(d.numClusters);
    for (uint32_t p = 0; p < tris.size(); ++p) members[d.clusterOf[p]].push_back({g, p});
    for (uint32_t c = 0; c < d.numClusters; ++c) {
      const bool large = members[c].size() >= kMinClusterTriangles;
      Cluster cluster;
      if (large && makeCluster(ctx_, g, d.transforms[c], members[c], worldMag_, cluster, stats_.maxSubdivisions)) {
        out_.clusters.push_back(std::move(cluster));
        continue;
      }
      if (large) ++stats_.fallbackClusters;
      rejected_.insert(rejected_.end(), members[c].begin(), members[c].end());
    }
    stats_.decompositions.push_back(std::move(d));
    return true;
  }

  const SceneContext& ctx_;
  FuzzyKdStats& stats_;
  double worldMag_ = 1.0;
  SceneSplit out_;
  std::vector<PrimRef> rejected_;
};

}  // namespace

SceneSplit splitScene(const SceneContext& ctx, FuzzyKdStats& stats) { return Splitter(ctx, stats).run(); }

}  // namespace mbrt::detail
