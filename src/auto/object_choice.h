// The per-object choice of structure (docs/auto.md, "Cost model"): a static
// object gets a static BVH; a moving one a trial build of each candidate
// kind, the lowest SAH cost weighed against memory winning.
#pragma once

#include <memory>
#include <string>

#include "scene/scene_context.h"

namespace mbrt::detail {

struct BuiltObject {
  std::unique_ptr<SceneContext> context;
  std::unique_ptr<Structure> structure;
  AccelKind kind = AccelKind::BvhInterp;
  std::string why;  // the reason for the choice, with the trial figures
  size_t bytes = 0;
  double sahCost = 0;
};

// Builds `scene`'s structure of the chosen kind (options.autoLeafKind when
// set) with `registry` (the kind registry); the structures of its
// instanced scenes are made by `children`.
BuiltObject buildObject(const Scene& scene, const BuildOptions& options, BuildBudget& budget,
                        const StructureFactory& registry, const StructureFactory& children);

// A structure owned elsewhere, traced through this one: instanced scenes
// whose structures the enclosing context already built.
class BorrowedStructure final : public Structure {
 public:
  explicit BorrowedStructure(const Structure& s) : s_(s) {}
  bool intersect(RayQuery& ray, Hit& hit) const override { return s_.intersect(ray, hit); }
  bool occluded(RayQuery& ray) const override { return s_.occluded(ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    return s_.intersectCounted(ray, hit, c);
  }
  void fillStats(AccelStats&) const override {}  // counted by its owner
  uint32_t clusterOf(PrimRef p) const override { return s_.clusterOf(p); }

 private:
  const Structure& s_;
};

// A structure with the context it was built on.
class OwningStructure final : public Structure {
 public:
  OwningStructure(std::unique_ptr<SceneContext> c, std::unique_ptr<Structure> s)
      : context_(std::move(c)), s_(std::move(s)) {}
  bool intersect(RayQuery& ray, Hit& hit) const override { return s_->intersect(ray, hit); }
  bool occluded(RayQuery& ray) const override { return s_->occluded(ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    return s_->intersectCounted(ray, hit, c);
  }
  void fillStats(AccelStats& s) const override {
    s_->fillStats(s);
    context_->addChildStats(s);
  }

 private:
  std::unique_ptr<SceneContext> context_;
  std::unique_ptr<Structure> s_;
};

}  // namespace mbrt::detail
