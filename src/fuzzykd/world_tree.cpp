#include "fuzzykd/world_tree.h"

#include "kd/kd_builder.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {

WorldTree::WorldTree(const SceneContext& ctx, std::vector<PrimRef> prims) : prims_(std::move(prims)) {
  if (prims_.empty()) return;
  paths_ = KdPaths::fromContext(ctx, prims_);
  Box3f root;
  for (uint32_t i = 0; i < paths_.size(); ++i) root.extend(paths_.hull(i));
  KdBuildParams params;
  params.sah.traversal = ctx.options().traversalCost;
  KdBuildStats stats;
  buildKdTree(paths_, root, params, ctx.budget(), tree_, stats);
}

LBounds WorldTree::bounds(const SceneContext& ctx) const {
  LBounds b;
  for (const PrimRef& p : prims_) b.extend(linearBounds(ctx, p, {0.0f, 1.0f}));
  return b;
}

}  // namespace mbrt::detail
