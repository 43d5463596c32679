// The triangles of a scene at one time, three vertices each, in primitive
// order per geometry: the leaves of a static tree (`frozen`) read a triangle
// in one place instead of through its indices and the vertex buffers (as
// Embree's static leaves keep their vertices). The values are those
// VerticesAt computes at that time, so hits are unchanged. Geometries with
// a filter, segments and instances are not stored (their runs take the
// other paths of the reference test). `frozen`'s format where its leaves
// are not charged per block (leaf_width.h); the block formats lay
// themselves out from it.
#pragma once

#include <vector>

#include "leaves/reference_leaves.h"

namespace mbrt::detail {

struct FixedTimeTriangles {
  static constexpr uint32_t kNotStored = 0xFFFFFFFFu;
  std::vector<uint32_t> first;  // per geometry: the index in `vertices` of its triangle 0's v0, or kNotStored
  std::vector<Vec3f> vertices;

  // A plain triangle mesh (no filter) alive at `time`: its triangles are stored.
  static bool stores(const Geometry& g, float time) {
    return g.type() == GeometryType::Triangles && !g.hasFilter() && g.timeRange().contains(time) &&
           3 * g.triangles().size() < kNotStored;
  }
  // The triangles FixedTimeTriangles(ctx, time) stores.
  static size_t countStored(const SceneContext& ctx, float time) {
    size_t n = 0;
    for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id)
      if (stores(ctx.geometry(id), time)) n += ctx.geometry(id).triangles().size();
    return n;
  }

  FixedTimeTriangles() = default;
  FixedTimeTriangles(const SceneContext& ctx, float time) {
    const uint32_t count = ctx.scene().numGeometries();
    first.assign(count, kNotStored);
    const size_t total = 3 * countStored(ctx, time);
    if (total >= kNotStored) {  // beyond 32-bit offsets: nothing stored, the leaves interpolate
      first.clear();
      return;
    }
    ctx.budget().charge(total * sizeof(Vec3f), "the frozen tree's stored triangles");
    vertices.reserve(total);
    for (uint32_t id = 0; id < count; ++id) {
      const Geometry& g = ctx.geometry(id);
      if (!stores(g, time)) continue;
      first[id] = uint32_t(vertices.size());
      const leaf_run::VerticesAt at(g, time);
      for (const Triangle& tri : g.triangles())
        for (uint32_t v : {tri.v0, tri.v1, tri.v2}) vertices.push_back(at[v]);
    }
  }
  // The stored triangles of geometry geomID, or null.
  const Vec3f* of(uint32_t geomID) const {
    return first.empty() || first[geomID] == kNotStored ? nullptr : vertices.data() + first[geomID];
  }
  size_t bytes() const { return first.size() * sizeof(uint32_t) + vertices.size() * sizeof(Vec3f); }
};

// The format: the references' runs read their triangles from the stored
// ones where they are (the tree's every ray is at the table's fixedTime).
struct FixedTimeLeaves {
  using RayState = LeafBlockRay;

  FixedTimeLeaves() = default;
  FixedTimeLeaves(const SceneContext& ctx, const LeafTable& table) : stored_(ctx, table.fixedTime.value()) {}

  RayState rayState(const RayQuery& ray) const { return LeafBlockRay(ray); }
  template <bool AnyHit, bool Count>
  bool test(const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray, const RayState& r, Hit* hit,
            TraversalCounters* counters) const {
    return testReferences<AnyHit, Count>(ctx, leaf, ray, r, hit, counters, nullptr, stored_);
  }
  size_t bytes() const { return stored_.bytes(); }

 private:
  FixedTimeTriangles stored_;
};

}  // namespace mbrt::detail
