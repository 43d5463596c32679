// The leaf test of the BVH kinds: a leaf's references, sorted by geometry
// when the builder stores the leaf (builder.cpp), are tested one run of a
// geometry at a time. A run checks the geometry's mask and time range and
// finds the ray's motion segment once, then interpolates each primitive's
// vertices with the same arithmetic as `intersectPrimitive`
// (primitive_intersect.h), so hits are bit-identical to testing the
// references one by one. Instances and geometries with a filter take the
// per-reference path. (STBVH §4: leaves are tested at the ray's time.)
#pragma once

#include "scene/primitive_intersect.h"

namespace mbrt::detail {

namespace leaf_run {

// References [begin, end) of the run of one geometry starting at begin.
inline uint32_t runEnd(const PrimRef* prims, uint32_t begin, uint32_t count) {
  uint32_t end = begin + 1;
  while (end < count && prims[end].geomID == prims[begin].geomID) ++end;
  return end;
}

// A geometry's vertices at the ray's time, as leaf_detail::candidate
// computes them.
struct VerticesAt {
  const VertexBuffer* v0;
  const VertexBuffer* v1;  // null: static geometry
  float f;

  VerticesAt(const Geometry& g, float time) {
    uint32_t s;
    g.segmentAt(time, s, f);
    if (g.numSteps() > 1) {
      v0 = &g.vertices(s);
      v1 = &g.vertices(s + 1);
    } else {
      v0 = &g.vertices(0);
      v1 = nullptr;
    }
  }
  [[gnu::always_inline]] Vec3f operator[](uint32_t i) const { return v1 ? lerp((*v0)[i], (*v1)[i], f) : (*v0)[i]; }
};

// The run's triangles or segments, without filter: calls onHit(hit) for
// each candidate hit; stops when onHit returns true.
template <class OnHit>
inline bool testRun(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end, RayQuery& ray,
                    OnHit&& onHit) {
  const VerticesAt at(g, ray.time);
  if (g.type() == GeometryType::Triangles) {
    const std::span<const Triangle> tris = g.triangles();
    for (uint32_t i = begin; i < end; ++i) {
      const Triangle& tri = tris[prims[i].primID];
      const Vec3f v0 = at[tri.v0], v1 = at[tri.v1], v2 = at[tri.v2];
      TriangleHit th;
      if (!intersectTriangle(ray, v0, v1, v2, th)) continue;
      Hit h;
      h.t = th.t;
      h.u = th.u;
      h.v = th.v;
      h.Ng = cross(v1 - v0, v2 - v0);
      h.geomID = prims[i].geomID;
      h.primID = prims[i].primID;
      h.instID = kInvalidId;
      if (onHit(h)) return true;
    }
    return false;
  }
  const std::span<const Segment> segs = g.segments();
  const std::span<const float> radii = g.radii();
  for (uint32_t i = begin; i < end; ++i) {
    const Segment& seg = segs[prims[i].primID];
    SegmentHit sh;
    if (!intersectSegment(ray, at[seg.v0], at[seg.v1], radii[seg.v0], radii[seg.v1], sh)) continue;
    Hit h;
    h.t = sh.t;
    h.u = sh.u;
    h.v = 0.0f;
    h.Ng = sh.Ng;
    h.geomID = prims[i].geomID;
    h.primID = prims[i].primID;
    h.instID = kInvalidId;
    if (onHit(h)) return true;
  }
  return false;
}

inline bool plainRun(const Geometry& g) { return g.type() != GeometryType::Instance && !g.hasFilter(); }

}  // namespace leaf_run

// Closest hit among a leaf's references (as intersectPrimitive on each).
inline bool intersectLeaf(const SceneContext& ctx, const PrimRef* prims, uint32_t count, RayQuery& ray, Hit& hit,
                          TraversalCounters* counters) {
  bool found = false;
  for (uint32_t begin = 0; begin < count;) {
    const uint32_t end = leaf_run::runEnd(prims, begin, count);
    const Geometry& g = ctx.geometry(prims[begin].geomID);
    if ((g.mask() & ray.mask) != 0 && g.timeRange().contains(ray.time)) {
      if (leaf_run::plainRun(g)) {
        leaf_run::testRun(g, prims, begin, end, ray, [&](const Hit& h) {
          hit = h;
          ray.tfar = h.t;
          found = true;
          return false;
        });
      } else {
        for (uint32_t i = begin; i < end; ++i) found |= intersectPrimitive(ctx, prims[i], ray, hit, counters);
      }
    }
    begin = end;
  }
  return found;
}

// Any hit among a leaf's references (as occludedPrimitive on each).
inline bool occludedLeaf(const SceneContext& ctx, const PrimRef* prims, uint32_t count, RayQuery& ray) {
  for (uint32_t begin = 0; begin < count;) {
    const uint32_t end = leaf_run::runEnd(prims, begin, count);
    const Geometry& g = ctx.geometry(prims[begin].geomID);
    if ((g.mask() & ray.mask) != 0 && g.timeRange().contains(ray.time)) {
      if (leaf_run::plainRun(g)) {
        if (leaf_run::testRun(g, prims, begin, end, ray, [](const Hit&) { return true; })) return true;
      } else {
        for (uint32_t i = begin; i < end; ++i)
          if (occludedPrimitive(ctx, prims[i], ray)) return true;
      }
    }
    begin = end;
  }
  return false;
}

}  // namespace mbrt::detail
