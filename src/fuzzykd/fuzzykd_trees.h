// What a fuzzy kd-tree is made of (fuzzykd.h): the clusters with their
// fuzzy trees, the world tree, and the top tree over both; and the walk of
// a ray through them.
#pragma once

#include <vector>

#include "fuzzykd/cluster.h"
#include "fuzzykd/cluster_traverse.h"
#include "fuzzykd/top_tree.h"
#include "fuzzykd/world_tree.h"
#include "leaves/reference_leaves.h"

namespace mbrt::detail {

struct FuzzyKdTrees {
  std::vector<Cluster> clusters;
  WorldTree world;
  TopTree top;  // item i < clusters.size(): cluster i; item clusters.size(): the world tree
  ReferenceLeaves leaves;  // the leaf format of the clusters' and the world's trees

  uint32_t worldItem() const { return uint32_t(clusters.size()); }
};

// Closest hit (AnyHit = false: `hit` updated, ray.tfar shrinks) or any hit.
template <bool AnyHit, bool Count>
bool traceTrees(const SceneContext& ctx, const FuzzyKdTrees& trees, RayQuery& ray, Hit* hit,
                TraversalCounters* counters) {
  const ReferenceLeaves::RayState state = trees.leaves.rayState(ray);
  return traverseTop<AnyHit, Count>(trees.top, ray, counters, [&](uint32_t item) {
    if (item != trees.worldItem())
      return traverseCluster<AnyHit, Count>(ctx, trees.clusters[item], ray, hit, counters, trees.leaves, state);
    if constexpr (Count) ++counters->boxTests;
    return trees.world.traverse<AnyHit, Count>(trees.leaves, ctx, ray, hit, counters);
  });
}

}  // namespace mbrt::detail
