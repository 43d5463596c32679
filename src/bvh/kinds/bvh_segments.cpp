#include "bvh/kinds/bvh_segments.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "bvh/build/build_wide.h"
#include "bvh/inspect.h"
#include "bvh/leaf_table.h"
#include "bvh/sah_cost.h"
#include "bvh/traverse.h"
#include "core/isolated_work.h"
#include "core/traced_structure.h"
#include "scene/branching.h"
#include "leaves/leaf_width.h"
#include "leaves/reference_triangles.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

TimeRange segmentRange(uint32_t i, uint32_t n) { return {float(i) / float(n), float(i + 1) / float(n)}; }

// Segment of a ray time and the time inside it, clamped to [0,1].
inline uint32_t segmentOf(float time, uint32_t n, float& local) {
  const float scaled = time * float(n);
  const uint32_t i = std::min(n - 1, uint32_t(std::max(0.0f, std::floor(scaled))));
  local = std::clamp(scaled - float(i), 0.0f, 1.0f);
  return i;
}

// Linear bounds local to segment [i/N, (i+1)/N]: b0 at i/N, b1 at (i+1)/N.
// Primitives whose geometry is not alive anywhere near the segment are left
// out (the leaf test would reject them anyway).
struct SegmentRefs final : RefMaker {
  const SceneContext& ctx;
  TimeRange range;
  SegmentRefs(const SceneContext& c, TimeRange r) : ctx(c), range(r) {}
  bool make(PrimRef prim, BuildRef& out) const override {
    const TimeRange alive = ctx.geometry(prim.geomID).timeRange();
    const float slack = 1e-6f;
    if (alive.hi < range.lo - slack || alive.lo > range.hi + slack) return false;
    out.prim = prim;
    out.bounds = linearBounds(ctx, prim, range);
    out.active = activeSegments(ctx, prim, range);
    return true;
  }
};

// Leaves: references gathered into blocks at the ray's time, through their
// triangles' indices kept beside them where that pays (makeBvhSegments).
template <int N, class Leaves>
class BvhSegments final : public TracedStructure<BvhSegments<N, Leaves>>, public Inspect {
 public:
  explicit BvhSegments(const SceneContext& ctx) : ctx_(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    const uint32_t n = std::max(1u, ctx.scene().maxSegments());
    trees_.resize(n);
    leaves_.resize(n);
    // Independent trees: built side by side (each is deterministic), each
    // isolated so that one running out of budget cannot cut another short.
    const int leafBlock = triangleLeafBlockWidth(ctx);
    tbb::parallel_for(0u, n, [&](uint32_t i) {
      runIsolatedFromCancellation([&] {
        buildWideBvh(ctx, prims, SegmentRefs(ctx, segmentRange(i, n)), trees_[i], {.leafBlock = leafBlock});
        leaves_[i] = Leaves(ctx, leafTable(trees_[i]));
      });
    });
  }

  template <bool AnyHit, bool Count>
  bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    float local;
    const uint32_t i = segmentOf(ray.time, uint32_t(trees_.size()), local);
    return traverse<AnyHit, Count>(trees_[i], leaves_[i], ctx_, ray, local, hit, counters);
  }

  // All trees summed, each covering T = 1/N.
  void fillStats(AccelStats& s) const override {
    SahSums sums;
    const uint32_t n = uint32_t(trees_.size());
    for (uint32_t i = 0; i < n; ++i) {
      const TimeRange r = segmentRange(i, n);
      addTreeCost(trees_[i], 1.0 / n, [&](PrimRef p, TimeRange) { return activeSegments(ctx_, p, r); }, sums);
      sums.bytes += leaves_[i].bytes();
    }
    sums.fill(s, sceneSahArea(ctx_));
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    const uint32_t n = uint32_t(trees_.size());
    for (uint32_t i = 0; i < n; ++i) {
      if (trees_[i].empty()) continue;
      walkLanes(trees_[i], 0, [&](const WideNode<N, true>& node, int lane, std::span<const PrimRef> below) {
        auto box = [&node, lane, n, i](float t) {
          return node.boxAt(lane, std::clamp(t * float(n) - float(i), 0.0f, 1.0f));
        };
        fn(LaneView{segmentRange(i, n), box, below, {}});
      });
    }
  }
  std::vector<uint8_t> bytes() const override {
    std::vector<uint8_t> out;
    for (const auto& t : trees_) appendBytes(t, out);
    return out;
  }

 private:
  const SceneContext& ctx_;
  std::vector<WideBvh<N, true>> trees_;
  std::vector<Leaves> leaves_;  // per tree
};

}  // namespace

std::unique_ptr<Structure> makeBvhSegments(const SceneContext& context) {
  if (triangleLeafBlockWidth(context) > 1 && ReferenceTriangleLeaves::pays(context))
    return makeForBranching<BvhSegments, ReferenceTriangleLeaves>(context);
  return makeForBranching<BvhSegments, ReferenceLeaves>(context);
}

}  // namespace mbrt::detail
