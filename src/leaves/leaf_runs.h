// The one-by-one leaf test of a run: a leaf's references, sorted by
// geometry where the builder stores the leaf (bvh/build/builder.cpp), are
// tested one run of a geometry at a time. A run checks the geometry's mask
// and time range and finds the ray's motion segment once, then interpolates
// each primitive's vertices with the same arithmetic as `intersectPrimitive`
// (scene/primitive_intersect.h), so hits are bit-identical to testing the
// references one by one. Instances and geometries with a filter take the
// per-reference path. (STBVH §4: leaves are tested at the ray's time.)
#pragma once

#include <span>

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

// The hit of triangle `ref` (vertices v0, v1, v2) the triangle test found,
// as intersectPrimitive reports it.
inline Hit triangleHit(PrimRef ref, const TriangleHit& th, Vec3f v0, Vec3f v1, Vec3f v2) {
  Hit h;
  h.t = th.t;
  h.u = th.u;
  h.v = th.v;
  h.Ng = cross(v1 - v0, v2 - v0);
  h.geomID = ref.geomID;
  h.primID = ref.primID;
  h.instID = kInvalidId;
  return h;
}

// One triangle's candidate hit, as intersectPrimitive finds it.
template <class OnHit>
inline bool testOneTriangle(PrimRef ref, Vec3f v0, Vec3f v1, Vec3f v2, RayQuery& ray, OnHit&& onHit) {
  TriangleHit th;
  if (!intersectTriangle(ray, v0, v1, v2, th)) return false;
  return onHit(triangleHit(ref, th, v0, v1, v2));
}

// Where a run's triangle vertices come from: through the triangle's
// indices, interpolated at the ray's time (every kind) ...
struct IndexedTriangles {
  std::span<const Triangle> tris;
  const VerticesAt& at;
  [[gnu::always_inline]] void operator()(uint32_t primID, Vec3f& v0, Vec3f& v1, Vec3f& v2) const {
    const Triangle& tri = tris[primID];
    v0 = at[tri.v0];
    v1 = at[tri.v1];
    v2 = at[tri.v2];
  }
};
// ... or three consecutive vertices per primitive at a fixed time
// (FixedTimeTriangles, `frozen`).
struct StoredTriangles {
  const Vec3f* v;
  [[gnu::always_inline]] void operator()(uint32_t primID, Vec3f& v0, Vec3f& v1, Vec3f& v2) const {
    const Vec3f* p = v + 3 * size_t(primID);
    v0 = p[0];
    v1 = p[1];
    v2 = p[2];
  }
};

// The run's triangles one by one, in the order of the references: calls
// onHit(hit) for each candidate hit; stops when onHit returns true.
template <class Vertices, class OnHit>
inline bool testTriangles(const Vertices& vertices, const PrimRef* prims, uint32_t begin, uint32_t end,
                          RayQuery& ray, OnHit&& onHit) {
  for (uint32_t i = begin; i < end; ++i) {
    Vec3f v0, v1, v2;
    vertices(prims[i].primID, v0, v1, v2);
    if (testOneTriangle(prims[i], v0, v1, v2, ray, onHit)) return true;
  }
  return false;
}

// The run's triangles or segments, without filter: calls onHit(hit) for
// each candidate hit; stops when onHit returns true. `stored`: the
// geometry's triangles at the ray's time (FixedTimeTriangles), or null.
template <class OnHit>
inline bool testRun(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end, RayQuery& ray,
                    OnHit&& onHit, const Vec3f* stored) {
  if (stored) return testTriangles(StoredTriangles{stored}, prims, begin, end, ray, onHit);
  const VerticesAt at(g, ray.time);
  if (g.type() == GeometryType::Triangles)
    return testTriangles(IndexedTriangles{g.triangles(), at}, prims, begin, end, ray, onHit);
  const std::span<const Segment> segs = g.segments();
  const std::span<const float> radii = g.radii();
  for (uint32_t i = begin; i < end; ++i) {
    const Segment& seg = segs[prims[i].primID];
    SegmentHit sh;
    if (!intersectSegment(ray, at[seg.v0], at[seg.v1], radii[seg.v0], radii[seg.v1], sh)) continue;
    if (onHit(leaf_detail::segmentHit(prims[i], sh))) return true;
  }
  return false;
}

inline bool plainRun(const Geometry& g) { return g.type() != GeometryType::Instance && !g.hasFilter(); }

}  // namespace leaf_run

}  // namespace mbrt::detail
