#include "bvh/kinds/cluster_bvh.h"

#include <algorithm>
#include <vector>

#include "bvh/build/build_wide.h"
#include "bvh/sah_cost.h"
#include "bvh/leaf_table.h"
#include "bvh/traverse.h"
#include "core/traced_structure.h"
#include "decompose/fuzzy_boxes.h"
#include "leaves/leaf_width.h"
#include "leaves/motion_blocks.h"
#include "scene/instance_space.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

// Each triangle's reference is its fuzzy box, static over the shutter.
struct FuzzyRefs final : RefMaker {
  const std::vector<Box3f>& boxes;  // per primitive id
  explicit FuzzyRefs(const std::vector<Box3f>& b) : boxes(b) {}
  bool make(PrimRef prim, BuildRef& out) const override {
    out.prim = prim;
    out.bounds = LBounds(boxes[prim.primID]);
    out.active = 1;
    return true;
  }
};

template <int N>
class ClusterBvh final : public TracedStructure<ClusterBvh<N>> {
 public:
  ClusterBvh(const SceneContext& ctx, std::span<const Affine3f> maps, const std::vector<PrimRef>& prims,
             const std::vector<Box3f>& fuzzy)
      : ctx_(ctx), maps_(maps.begin(), maps.end()) {
    buildWideBvh(ctx, prims, FuzzyRefs(fuzzy), bvh_, {.leafBlock = leafBlockWidth(prims.size(), prims.size())});
    leaves_ = MotionBlockLeaves(ctx, leafTable(bvh_));
  }

  template <bool AnyHit, bool Count>
  bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    const Geometry& g = ctx_.geometry(0);
    if ((g.mask() & ray.mask) == 0 || !g.timeRange().contains(ray.time)) return false;
    uint32_t s;
    float f;
    g.segmentAt(ray.time, s, f);
    RayQuery local;  // the ray in the cluster's frame, the same parameter t
    if (!toLocalSpace(lerp(maps_[s], maps_[s + 1], f), ray, local, nullptr)) return false;
    return traverse<AnyHit, Count>(bvh_, leaves_, ctx_, local, ray, 0.0f, hit, counters);
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [](PrimRef, TimeRange) { return 1u; }, sums);
    sums.bytes += leaves_.bytes() + maps_.size() * sizeof(Affine3f);
    sums.fill(s, sceneSahArea(ctx_));
    s.leafBlockBytes = leaves_.bytes();
  }

 private:
  const SceneContext& ctx_;
  std::vector<Affine3f> maps_;
  WideBvh<N, false> bvh_;
  MotionBlockLeaves leaves_;  // motion blocks: the leaves' triangles move in world space
};

template <int N>
std::unique_ptr<Structure> make(const SceneContext& ctx, std::span<const Affine3f> maps,
                                const std::vector<PrimRef>& prims, const std::vector<Box3f>& fuzzy) {
  return std::make_unique<ClusterBvh<N>>(ctx, maps, prims, fuzzy);
}

}  // namespace

std::unique_ptr<Structure> makeClusterBvh(const SceneContext& context, std::span<const Affine3f> maps) {
  const Scene& scene = context.scene();
  if (scene.numGeometries() != 1 || scene.geometry(0).type() != GeometryType::Triangles ||
      scene.geometry(0).numSteps() != maps.size() || maps.size() < 2)
    throw Error("a cluster tree needs a scene of one moving triangle mesh and one map per vertex step");
  const Geometry& g = scene.geometry(0);
  // Triangles with non-finite bounds can never be hit: left out. The
  // numerical pad of the fuzzy boxes scales with the largest coordinate.
  std::vector<PrimRef> prims;
  Box3f all;
  for (uint32_t p = 0; p < g.numPrimitives(); ++p) {
    const LBounds b = linearBounds(context, {0, p}, {0.0f, 1.0f});
    if (!isUsable(b)) continue;
    prims.push_back({0, p});
    all.extend(b.hull());
  }
  if (prims.empty()) return nullptr;
  const double worldMag = std::max(normInf(toD(all.lower)), normInf(toD(all.upper)));
  FuzzyBoxes fuzzy;
  if (!fuzzyBoxes(g, maps, prims, worldMag, fuzzy)) return nullptr;
  std::vector<Box3f> byPrim(g.numPrimitives());
  for (size_t i = 0; i < prims.size(); ++i) byPrim[prims[i].primID] = fuzzy.boxes[i];
  switch (context.options().branching) {
    case 2: return make<2>(context, maps, prims, byPrim);
    case 4: return make<4>(context, maps, prims, byPrim);
    default: return make<8>(context, maps, prims, byPrim);
  }
}

}  // namespace mbrt::detail
