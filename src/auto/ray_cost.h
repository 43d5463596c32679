// The measured traversal cost of a structure (docs/auto.md, "Cost model"):
// a fixed sample of rays through its scene's bounds at random times, traced
// with the counting traversal; the cost per ray is the work counted, in units
// of one node visit. The SAH prices a tree alone; these counts also see what
// the SAH does not: instance entries (a ray transform and a second traversal
// set-up each), references split into several leaves, overlapping objects.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "scene/scene_context.h"

namespace mbrt::detail {

// Weights per counted event, in node visits, from callgrind instruction
// counts of the kernel (docs/performance.md): ~220 instructions per 8-wide
// node visit, ~300 per triangle test (~210 in `frozen`, whose leaves hold
// their triangles), ~550 per entry into an instanced structure
// (toInstanceSpace and the child traversal's set-up).
// `msbvh` does the same counted work in ~0.85 of the instructions of the
// other BVH kinds (callgrind, same rays and near-equal counts: hairball
// 47.0 M against `bvh-segments`' 55.0 M, CesiumMan 10.4 M against 12.6 M,
// translate 11.5 M against `bvh-interp`'s 13.7 M).
struct RayCostWeights {
  double node = 1.0;
  double primitive = 1.4;
  double frozenPrimitive = 1.0;
  double entry = 2.5;
  double msbvhFactor = 0.85;
};

// kSampleRays rays from a sphere around the scene's bounds (sceneBounds) towards
// points inside them, at times in [0, 1], from a fixed seed (the choice a
// build makes does not change from run to run).
constexpr uint32_t kSampleRays = 2048;
std::vector<RayQuery> sampleRays(const SceneContext& context);

// Counts the calls into a structure traced through an instance, while
// counting is on (only the choice's own sample; off afterwards, so that
// concurrent tracing never writes).
class EntryCounting final : public Structure {
 public:
  EntryCounting(std::unique_ptr<Structure> s, std::atomic<uint64_t>& entries, const std::atomic<bool>& on)
      : s_(std::move(s)), entries_(entries), on_(on) {}
  bool intersect(RayQuery& ray, Hit& hit) const override { return s_->intersect(ray, hit); }
  bool occluded(RayQuery& ray) const override { return s_->occluded(ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& c) const override {
    if (on_.load(std::memory_order_relaxed)) entries_.fetch_add(1, std::memory_order_relaxed);
    return s_->intersectCounted(ray, hit, c);
  }
  void fillStats(AccelStats& s) const override { s_->fillStats(s); }
  uint32_t clusterOf(PrimRef p) const override { return s_->clusterOf(p); }

 private:
  std::unique_ptr<Structure> s_;
  std::atomic<uint64_t>& entries_;
  const std::atomic<bool>& on_;
};

struct RayCost {
  double nodes = 0, primitives = 0, entries = 0;  // per ray
  double total(const RayCostWeights& w, AccelKind kind) const {
    const double work = w.node * nodes + (kind == AccelKind::Frozen ? w.frozenPrimitive : w.primitive) * primitives +
                        w.entry * entries;
    return kind == AccelKind::Msbvh ? work * w.msbvhFactor : work;
  }
};

// Traces `rays` through s with counting; `entries` (may be null) is read
// before and after, for structures whose children are EntryCounting.
RayCost measureRayCost(const Structure& s, const std::vector<RayQuery>& rays,
                       const std::atomic<uint64_t>* entries = nullptr);

}  // namespace mbrt::detail
