#include "fuzzykd/cluster.h"

#include <algorithm>
#include <cmath>

#include "decompose/fuzzy_boxes.h"
#include "kd/kd_builder.h"

namespace mbrt::detail {
namespace {

// Depth limit of a cluster's tree: the kd core's 8 + 1.3 log2(N) less three
// levels. A fuzzy box holds its triangle in every frame, so it is larger
// than the triangle in any one: the deepest cells of a static tree, which
// separate neighbouring triangles, cannot separate their fuzzy boxes and
// only duplicate references. Cutting them bounds the fuzzy trees' memory
// near a per-frame tree's at a small cost in work per ray (the sweep's
// figures: docs/fuzzykd.md).
constexpr int kFuzzyDepthCut = 3;
int fuzzyTreeDepth(size_t prims) {
  return std::max(1, int(8.0 + 1.3 * std::log2(double(std::max<size_t>(prims, 1)))) - kFuzzyDepthCut);
}

}  // namespace

bool makeCluster(const SceneContext& ctx, uint32_t g, const std::vector<Affine3d>& maps, std::vector<PrimRef>& prims,
                 double worldMag, Cluster& out, uint32_t& subdivisions) {
  Cluster c;
  c.geomID = g;
  for (const Affine3d& w : maps) c.xfm.push_back(w.toFloat());
  const Geometry& geo = ctx.geometry(g);
  FuzzyBoxes fuzzy;
  if (!fuzzyBoxes(geo, c.xfm, prims, worldMag, fuzzy)) return false;
  subdivisions = std::max(subdivisions, fuzzy.subdivisions);
  // A static SAH kd-tree over the fuzzy boxes (the kd core with one key per
  // box): it serves every time of the shutter.
  const KdPaths paths = KdPaths::fromBoxes(fuzzy.boxes);
  Box3f root;
  for (const Box3f& b : fuzzy.boxes) root.extend(b);
  KdBuildParams params;
  params.sah.traversal = ctx.options().traversalCost;
  params.maxDepth = fuzzyTreeDepth(paths.size());
  KdBuildStats stats;
  KdTree tree;
  buildKdTree(paths, root, params, ctx.budget(), tree, stats);
  c.tree = FuzzyTree(tree);
  const uint32_t K = uint32_t(c.xfm.size());
  c.keyBoxes.assign(K, Box3f{});
  for (const PrimRef& p : prims)
    for (uint32_t k = 0; k < K; ++k) c.keyBoxes[k].extend(ctx.keyBox(p, k));
  c.prims = std::move(prims);
  out = std::move(c);
  return true;
}

}  // namespace mbrt::detail
