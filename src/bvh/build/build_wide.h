// Builds one WideBvh from primitives: references (charged as scratch), then
// the wide tree over them (builder.h).
#pragma once

#include <span>

#include "bvh/build/build_ref.h"
#include "bvh/build/builder.h"
#include "scene/scene_context.h"

namespace mbrt::detail {

inline BuildSettings settingsFor(const BuildOptions& o, TimeRange range) {
  BuildSettings s;
  s.maxLeafSize = o.maxLeafSize;
  s.numBins = o.sahBins;
  s.traversalCost = o.traversalCost;
  s.range = range;
  return s;
}

// What a kind sets of a build besides the options (BuildSettings' fields):
// with a TemporalSource the builder also makes temporal splits (stbvh);
// `leafBlock` (the leaf formats' block width, leaves/leaf_width.h);
// `traversalScale` multiplies the options' C_T; `temporalLeafPenalty` is
// λ against a leaf; `reuseTriedTemporalSplits` is off only in tests.
struct WideBuildTuning {
  const TemporalSource* temporal = nullptr;
  int leafBlock = 1;
  float traversalScale = 1.0f;
  float temporalLeafPenalty = 1.0f;
  bool reuseTriedTemporalSplits = true;
};

template <int N, bool Motion>
void buildWideBvh(const SceneContext& ctx, std::span<const PrimRef> prims, const RefMaker& maker,
                  WideBvh<N, Motion>& out, const WideBuildTuning& tuning = {}) {
  BuildBudget& budget = ctx.budget();
  ScopedCharge refCharge(budget, prims.size() * (sizeof(BuildRef) + 1), "the BVH build references");
  std::vector<BuildRef> refs = makeBuildRefs(prims, maker);
  BuildSettings settings = settingsFor(ctx.options(), {0.0f, 1.0f});
  settings.temporal = tuning.temporal;
  settings.reuseTriedTemporalSplits = tuning.reuseTriedTemporalSplits;
  settings.leafBlock = tuning.leafBlock;
  settings.traversalCost *= tuning.traversalScale;
  settings.temporalLeafPenalty = tuning.temporalLeafPenalty;
  buildWideTree(refs, settings, budget, out);
}

}  // namespace mbrt::detail
