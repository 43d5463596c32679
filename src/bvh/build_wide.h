// Builds one WideBvh from primitives: references (charged as scratch), the
// binary tree (builder.h), the N-wide collapse (collapse.h).
#pragma once

#include <span>

#include "bvh/build_ref.h"
#include "bvh/builder.h"
#include "bvh/collapse.h"

namespace mbrt::detail {

inline BuildSettings settingsFor(const BuildOptions& o, TimeRange range) {
  BuildSettings s;
  s.maxLeafSize = o.maxLeafSize;
  s.numBins = o.sahBins;
  s.traversalCost = o.traversalCost;
  s.range = range;
  return s;
}

template <int N, bool Motion>
void buildWideBvh(const SceneContext& ctx, std::span<const PrimRef> prims, const RefMaker& maker,
                  WideBvh<N, Motion>& out) {
  BuildBudget& budget = ctx.budget();
  ScopedCharge refCharge(budget, prims.size() * (sizeof(BuildRef) + 1), "the BVH build references");
  std::vector<BuildRef> refs = makeBuildRefs(prims, maker);
  const BinaryTree tree = buildBinaryTree(refs, settingsFor(ctx.options(), {0.0f, 1.0f}), budget);
  collapse(tree, refs, out, budget);
}

}  // namespace mbrt::detail
