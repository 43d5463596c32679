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

// stbvh's C_T relative to C_I: the builder fills spare lanes by splitting
// leaves (builder.h), so a leaf costs less than its segments say; 1.5 trades
// the nodes this saves for a few more intersections (docs/stbvh.md).
inline constexpr float kFilledTraversalScale = 1.5f;

// stbvh's λ against a leaf (BuildSettings::temporalLeafPenalty). With C_T =
// 1.5, a one-primitive leaf of straight motion over 5 segments (a temporal
// split halves its segments, not its area) is split in time only below
// λ = (1 - 1.5 / 5) / 0.52 = 1.35: 1.4 keeps such leaves whole, so linear
// bounds carry linear motion (docs/stbvh.md, "Quantised motion nodes and
// the MBSAH's own leaf test").
inline constexpr float kTemporalLeafPenalty = 1.4f;

// With a TemporalSource the builder also makes temporal splits (stbvh).
// `reuseTriedTemporalSplits`, `leafBlock`: BuildSettings' (tests turn the
// first off; `frozen` gives the second, for its leaf blocks).
template <int N, bool Motion>
void buildWideBvh(const SceneContext& ctx, std::span<const PrimRef> prims, const RefMaker& maker,
                  WideBvh<N, Motion>& out, const TemporalSource* temporal = nullptr,
                  bool reuseTriedTemporalSplits = true, int leafBlock = 1) {
  BuildBudget& budget = ctx.budget();
  ScopedCharge refCharge(budget, prims.size() * (sizeof(BuildRef) + 1), "the BVH build references");
  std::vector<BuildRef> refs = makeBuildRefs(prims, maker);
  BuildSettings settings = settingsFor(ctx.options(), {0.0f, 1.0f});
  settings.temporal = temporal;
  settings.reuseTriedTemporalSplits = reuseTriedTemporalSplits;
  settings.leafBlock = leafBlock;
  if (temporal) {  // stbvh (docs/stbvh.md)
    settings.traversalCost *= kFilledTraversalScale;
    settings.temporalLeafPenalty = kTemporalLeafPenalty;
  }
  buildWideTree(refs, settings, budget, out);
}

}  // namespace mbrt::detail
