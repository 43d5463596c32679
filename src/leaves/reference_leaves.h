// Plain references, the format every leaf can take (leaf_format.h): a
// leaf's runs of one geometry are tested one run at a time (leaf_runs.h),
// runs of two or more triangles or segments gathered four at a time into
// blocks at the ray's time through their indices (gathered_runs.h).
// Nothing is laid out beside the tree. The other formats test the leaves
// they did not lay out through intersectLeaf / occludedLeaf below.
#pragma once

#include "leaves/gathered_runs.h"
#include "leaves/leaf_format.h"

namespace mbrt::detail {

// Where a run may read its triangles at a fixed time instead of through
// the indices (FixedTimeTriangles, fixed_time_triangles.h): nowhere.
struct NoStoredTriangles {
  static constexpr const Vec3f* of(uint32_t) { return nullptr; }
};

// Closest hit among a leaf's references (as intersectPrimitive on each).
// With `blockRay`, runs of two or more triangles or segments not stored are
// gathered into blocks (leaf_block::testGathered), reading the references'
// triangles from `indices` when given (ReferenceTriangles); counters count
// them as block tests. `stored.of(geomID)`: the geometry's triangles at the
// ray's time, laid out per primitive, or null.
template <class Stored = NoStoredTriangles>
inline bool intersectLeaf(const SceneContext& ctx, const PrimRef* prims, uint32_t count, RayQuery& ray, Hit& hit,
                          TraversalCounters* counters, const LeafBlockRay* blockRay = nullptr,
                          const Triangle* indices = nullptr, const Stored& stored = {}) {
  bool found = false;
  for (uint32_t begin = 0; begin < count;) {
    const uint32_t end = leaf_run::runEnd(prims, begin, count);
    const Geometry& g = ctx.geometry(prims[begin].geomID);
    if ((g.mask() & ray.mask) != 0 && g.timeRange().contains(ray.time)) {
      if (leaf_run::plainRun(g)) {
        const auto onHit = [&](const Hit& h) {
          hit = h;
          ray.tfar = h.t;
          found = true;
          return false;
        };
        const Vec3f* v = stored.of(prims[begin].geomID);
        bool unused;
        if (blockRay && !v && leaf_block::testGathered(g, prims, begin, end, ray, *blockRay, onHit, indices, unused)) {
          if (counters) counters->blockPrimitiveTests += end - begin;
        } else {
          leaf_run::testRun(g, prims, begin, end, ray, onHit, v);
        }
      } else {
        for (uint32_t i = begin; i < end; ++i) found |= intersectPrimitive(ctx, prims[i], ray, hit, counters);
      }
    }
    begin = end;
  }
  return found;
}

// Any hit among a leaf's references (as occludedPrimitive on each).
template <class Stored = NoStoredTriangles>
inline bool occludedLeaf(const SceneContext& ctx, const PrimRef* prims, uint32_t count, RayQuery& ray,
                         const LeafBlockRay* blockRay = nullptr, const Triangle* indices = nullptr,
                         const Stored& stored = {}) {
  for (uint32_t begin = 0; begin < count;) {
    const uint32_t end = leaf_run::runEnd(prims, begin, count);
    const Geometry& g = ctx.geometry(prims[begin].geomID);
    if ((g.mask() & ray.mask) != 0 && g.timeRange().contains(ray.time)) {
      if (leaf_run::plainRun(g)) {
        const Vec3f* v = stored.of(prims[begin].geomID);
        const auto onHit = [](const Hit&) { return true; };
        bool hit = false;
        if (!(blockRay && !v && leaf_block::testGathered(g, prims, begin, end, ray, *blockRay, onHit, indices, hit)))
          hit = leaf_run::testRun(g, prims, begin, end, ray, onHit, v);
        if (hit) return true;
      } else {
        for (uint32_t i = begin; i < end; ++i)
          if (occludedPrimitive(ctx, prims[i], ray)) return true;
      }
    }
    begin = end;
  }
  return false;
}

// The leaf test of plain references, with their triangles read through
// `indices` when given, `stored` as intersectLeaf.
template <bool AnyHit, bool Count, class Stored = NoStoredTriangles>
inline bool testReferences(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const LeafBlockRay& r,
                           Hit* hit, TraversalCounters* counters, const Triangle* indices = nullptr,
                           const Stored& stored = {}) {
  if constexpr (AnyHit) return occludedLeaf(ctx, leaf.prims, leaf.count, ray, &r, indices, stored);
  else return intersectLeaf(ctx, leaf.prims, leaf.count, ray, *hit, Count ? counters : nullptr, &r, indices, stored);
}

struct ReferenceLeaves {
  using RayState = LeafBlockRay;

  ReferenceLeaves() = default;
  ReferenceLeaves(const SceneContext&, const LeafTable&) {}
  RayState rayState(const RayQuery& ray) const { return LeafBlockRay(ray); }
  template <bool AnyHit, bool Count>
  bool test(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const RayState& r, Hit* hit,
            TraversalCounters* counters) const {
    return testReferences<AnyHit, Count>(ctx, leaf, ray, r, hit, counters);
  }
  size_t bytes() const { return 0; }
};

}  // namespace mbrt::detail
