// The world tree of the fuzzy kd-tree: the primitives no cluster takes
// (scene_split.h) in one world-space motion kd-tree (the mbkd core over
// key-box paths, kd/kd_builder.h), whose references also check their
// primitive's box at the ray's time before the primitive test.
#pragma once

#include <vector>

#include "kd/kd_motion.h"
#include "kd/kd_traverse.h"

namespace mbrt::detail {

class WorldTree {
 public:
  WorldTree() = default;
  WorldTree(const SceneContext& ctx, std::vector<PrimRef> prims);

  bool empty() const { return prims_.empty(); }
  const KdTree& tree() const { return tree_; }
  const std::vector<PrimRef>& prims() const { return prims_; }
  // Linear bounds of all its primitives over the shutter.
  LBounds bounds(const SceneContext& ctx) const;
  size_t bytes() const { return tree_.bytes() + paths_.bytes() + prims_.size() * sizeof(PrimRef); }

  template <bool AnyHit, bool Count, LeafFormat Leaves>
  bool traverse(const Leaves& leaves, const SceneContext& ctx, RayQuery& ray, Hit* hit,
                TraversalCounters* counters) const {
    return kdTraverse<AnyHit, Count>(tree_, leaves, ctx, prims_.data(), ray, hit, counters, BoxFilter{paths_});
  }

 private:
  struct BoxFilter {
    static constexpr bool kActive = true;
    const KdPaths& paths;
    bool operator()(uint32_t prim, const RayQuery& ray) const { return rayHitsBox(ray, paths.boxAt(prim, ray.time)); }
  };

  std::vector<PrimRef> prims_;
  KdPaths paths_;
  KdTree tree_;
};

}  // namespace mbrt::detail
