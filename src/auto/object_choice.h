// The per-object choice of structure (docs/auto.md, "Cost model"): trial
// builds of the candidate kinds, each traced on a fixed sample of rays with
// the counting traversal; the lowest measured cost (a structure's bytes
// weigh in through the cache factor of ray_cost.h) wins.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "auto/ray_cost.h"
#include "scene/scene_context.h"

namespace mbrt::detail {

struct BuiltObject {
  std::unique_ptr<BuildBudget> budget;  // what the object's build charged (its context charges it)
  std::unique_ptr<SceneContext> context;
  std::unique_ptr<Structure> structure;
  AccelKind kind = AccelKind::BvhInterp;
  std::string why;  // the reason for the choice, with the trial figures
  // Its statistics when built (with its context's instanced structures):
  // a refit changes its SAH cost, never its bytes, nodes or references,
  // which are all the top level's statistics read of it.
  AccelStats stats;
  double rayCost = 0;  // measured per sampled ray, in node visits (ray_cost.h)
  // Every trial's kind and measured cost (empty where no trial was made):
  // what a refit picks from when the kept kind cannot refit.
  std::vector<std::pair<AccelKind, double>> trials;
  uint32_t refits = 0;  // in place since it was built

  // Fills `stats` from the structure.
  void measure() {
    stats = AccelStats{};
    structure->fillStats(stats);
    if (context) context->addChildStats(stats);
  }
};

// The kinds whose Structure::refit updates a tree in place for new vertices
// (bvh-interp: bottom-up linear bounds; msbvh: re-clipped per-key bounds,
// its paper's §5) on scenes without instances.
bool refitsInPlace(AccelKind kind);

// The cheapest of b's trials whose kind refits in place (b's own kind when
// it refits or when none of its trials does).
AccelKind cheapestRefittingTrial(const BuiltObject& b);

// Builds `scene`'s structure of the chosen kind (options.autoLeafKind when
// set) with `registry` (the kind registry); the structures of its
// instanced scenes are made by `children`. Each trial is charged to a
// budget of its own, limited to what `budget` has left; only the kept one
// is charged to `budget` (and the peak of its build to its peak), so a
// trial that does not fit is skipped while another does.
BuiltObject buildObject(const Scene& scene, const BuildOptions& options, BuildBudget& budget,
                        const StructureFactory& registry, const StructureFactory& children);
// Builds `scene`'s structure of `kind` (no trials), charged to `budget`.
BuiltObject buildObjectOfKind(const Scene& scene, const BuildOptions& options, AccelKind kind, BuildBudget& budget,
                              const StructureFactory& registry, const StructureFactory& children);

// A budget for a trial build: limited to what `budget` has left.
std::unique_ptr<BuildBudget> trialBudget(const BuildBudget& budget);
// Charges what the kept trial's budget holds to `budget`, and its peak as
// a peak (the trials' budgets charge nothing until one is kept).
void chargeKept(const BuildBudget& kept, BuildBudget& budget);

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
