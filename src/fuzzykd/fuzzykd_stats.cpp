#include "fuzzykd/fuzzykd_stats.h"

#include <algorithm>

#include "bvh/sah_cost.h"
#include "scene/primitive_bounds.h"
#include "scene/scene_area.h"

namespace mbrt::detail {
namespace {

constexpr int kTimes = 8;

// Surface area of the parallelepiped a local box becomes under the map m.
double mappedArea(const Affine3f& m, const Box3f& box) {
  const Vec3f e = box.upper - box.lower;
  const Vec3f a = m.vx * e.x, b = m.vy * e.y, c = m.vz * e.z;
  return 2.0 * (double(length(cross(a, b))) + double(length(cross(b, c))) + double(length(cross(c, a))));
}

double clusterCost(const SceneContext& ctx, const Cluster& c) {
  const Geometry& geo = ctx.geometry(c.geomID);
  double sum = 0.0;
  Affine3f xfm[kTimes];
  for (int k = 0; k < kTimes; ++k) {
    const float t = float(k) / (kTimes - 1);
    xfm[k] = c.mapAt(geo, t);
    sum += double(c.boxAt(geo, t).area()) / kTimes;
  }
  forEachKdCell(c.tree.nodes, 0, c.tree.root, [&](uint32_t node, const Box3f& cell, int) {
    double area = 0.0;
    for (const Affine3f& m : xfm) area += mappedArea(m, cell) / kTimes;
    const KdNode& n = c.tree.nodes[node];
    double seg = 1.0;
    if (n.isLeaf()) {
      seg = 0.0;
      for (uint32_t i = 0; i < n.count(); ++i)
        seg += activeSegments(ctx, c.prims[c.tree.refs[n.first() + i]], {0.0f, 1.0f});
    }
    sum += area * seg;
  });
  return sum;
}

double worldCost(const SceneContext& ctx, const WorldTree& world) {
  const KdTree& tree = world.tree();
  if (tree.empty()) return 0.0;
  double sum = 0.0;
  forEachKdCell(tree.nodes, 0, tree.root, [&](uint32_t node, const Box3f& cell, int) {
    const KdNode& n = tree.nodes[node];
    double seg = 1.0;
    if (n.isLeaf()) {
      seg = 0.0;
      for (uint32_t i = 0; i < n.count(); ++i) {
        const KdLeafRef& r = tree.refs[n.first() + i];
        seg += activeSegments(ctx, world.prims()[r.prim], {r.t0, r.t1});
      }
    }
    sum += double(cell.area()) * seg;
  });
  return sum;
}

}  // namespace

void countTrees(const FuzzyKdTrees& trees, FuzzyKdStats& stats) {
  stats.clusters = trees.clusters.size();
  stats.worldPrims = trees.world.prims().size();
  stats.worldTreeBytes = trees.world.bytes();
  stats.fuzzyPrims = stats.fuzzyTreeBytes = stats.fuzzyNodes = stats.fuzzyRefs = 0;
  stats.topBytes = trees.top.bytes();
  for (const Cluster& c : trees.clusters) {
    stats.fuzzyPrims += c.prims.size();
    stats.fuzzyTreeBytes += c.tree.bytes();
    stats.fuzzyNodes += c.tree.nodes.size();
    stats.fuzzyRefs += c.tree.refs.size();
    stats.topBytes += c.topBytes();
  }
}

double fuzzySahCost(const SceneContext& ctx, const FuzzyKdTrees& trees) {
  const double sceneArea = sceneSahArea(ctx);
  if (!(sceneArea > 0.0)) return 0.0;
  SahSums top;
  addTreeCost(trees.top, 1.0, [](PrimRef, TimeRange) { return 1.0; }, top);
  double sum = top.inner + top.leaves;
  for (const Cluster& c : trees.clusters) sum += clusterCost(ctx, c);
  sum += worldCost(ctx, trees.world);
  return sum / sceneArea;
}

void fillFuzzyStats(const FuzzyKdTrees& trees, const FuzzyKdStats& stats, double sahCost, AccelStats& s) {
  const KdTree& world = trees.world.tree();
  s.references = world.refs.size();
  size_t nodes = world.nodes.size() + trees.top.nodes.size();
  size_t leaves = 0;
  auto countLeaves = [&](const std::vector<KdNode>& kd) {
    for (const KdNode& n : kd) leaves += n.isLeaf();
  };
  countLeaves(world.nodes);
  s.maxDepth = std::max<size_t>(s.maxDepth, world.depth);
  for (const Cluster& c : trees.clusters) {
    s.references += c.tree.refs.size();
    nodes += c.tree.nodes.size();
    s.maxDepth = std::max<size_t>(s.maxDepth, c.tree.depth);
    countLeaves(c.tree.nodes);
  }
  s.leafNodes = leaves;
  s.innerNodes = nodes - leaves;
  s.bytes = stats.fuzzyTreeBytes + stats.worldTreeBytes + stats.topBytes;
  s.sahCost = sahCost;
}

}  // namespace mbrt::detail
