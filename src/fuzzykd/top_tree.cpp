#include "fuzzykd/top_tree.h"

#include <vector>

#include "bvh/build/build_wide.h"

namespace mbrt::detail {

void buildTopTree(const SceneContext& ctx, std::span<const LBounds> items, TopTree& out) {
  std::vector<BuildRef> refs(items.size());
  for (size_t i = 0; i < items.size(); ++i) {
    BuildRef& r = refs[i];
    r.bounds = items[i];
    r.prim = {0, uint32_t(i)};
    r.active = 1;  // an item costs one entry into its tree
  }
  BuildSettings settings = settingsFor(ctx.options(), {0.0f, 1.0f});
  settings.maxLeafSize = 1;  // one item per leaf: each has its own transform and tree
  buildWideTree(refs, settings, ctx.budget(), out);
}

}  // namespace mbrt::detail
