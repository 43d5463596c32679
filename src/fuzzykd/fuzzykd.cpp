#include "fuzzykd/fuzzykd.h"

#include <chrono>

#include "core/inspect.h"
#include "core/traced_structure.h"
#include "fuzzykd/fuzzykd_stats.h"
#include "fuzzykd/fuzzykd_trees.h"
#include "fuzzykd/scene_split.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

class FuzzyKd final : public TracedStructure<FuzzyKd>, public Inspect {
 public:
  explicit FuzzyKd(const SceneContext& ctx) : ctx_(ctx) {
    const auto t0 = Clock::now();
    SceneSplit split = splitScene(ctx, stats_);
    stats_.decomposeSeconds = since(t0);
    const auto t1 = Clock::now();
    trees_.clusters = std::move(split.clusters);
    trees_.world = WorldTree(ctx, std::move(split.world));
    std::vector<LBounds> items;
    for (const Cluster& c : trees_.clusters) {
      LBounds b;
      for (const PrimRef& p : c.prims) b.extend(linearBounds(ctx, p, {0.0f, 1.0f}));
      items.push_back(b);
    }
    if (!trees_.world.empty()) items.push_back(trees_.world.bounds(ctx));
    buildTopTree(ctx, items, trees_.top);
    stats_.treeSeconds = since(t1);
    mapClusters();
    countTrees(trees_, stats_);
    sahCost_ = fuzzySahCost(ctx, trees_);
  }

  template <bool AnyHit, bool Count>
  bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    return traceTrees<AnyHit, Count>(ctx_, trees_, ray, hit, counters);
  }

  void fillStats(AccelStats& s) const override { fillFuzzyStats(trees_, stats_, sahCost_, s); }

  std::any buildStats() const override { return &stats_; }
  uint32_t clusterOf(PrimRef p) const override {
    if (p.geomID >= clusterOfPrim_.size() || p.primID >= clusterOfPrim_[p.geomID].size()) return ~0u;
    return clusterOfPrim_[p.geomID][p.primID];
  }

 private:
  void mapClusters() {
    const Scene& scene = ctx_.scene();
    clusterOfPrim_.resize(scene.numGeometries());
    for (uint32_t g = 0; g < scene.numGeometries(); ++g)
      clusterOfPrim_[g].assign(ctx_.geometry(g).numPrimitives(), ~0u);
    for (uint32_t c = 0; c < trees_.clusters.size(); ++c)
      for (const PrimRef& p : trees_.clusters[c].prims) clusterOfPrim_[p.geomID][p.primID] = c;
  }

  const SceneContext& ctx_;
  FuzzyKdTrees trees_;
  std::vector<std::vector<uint32_t>> clusterOfPrim_;  // [geomID][primID]: cluster or ~0u (the world tree)
  FuzzyKdStats stats_;
  double sahCost_ = 0.0;
};

}  // namespace

std::unique_ptr<Structure> makeFuzzyKd(const SceneContext& context) { return std::make_unique<FuzzyKd>(context); }

}  // namespace mbrt::detail
