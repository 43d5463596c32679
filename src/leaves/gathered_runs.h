// Runs of two or more triangles or segments of one geometry gathered four
// at a time into a block at the ray's time through their indices (as
// Embree's Triangle4i and Triangle4iMB leaves do) and tested in SIMD lanes
// (geometry/triangle_block.h, geometry/segment_block.h), with the hits of
// the one-by-one test (leaf_runs.h): candidates are taken in lane order
// against the shrinking tfar.
#pragma once

#include <algorithm>
#include <span>

#include "geometry/segment_block.h"
#include "geometry/triangle_block.h"
#include "leaves/leaf_runs.h"

namespace mbrt::detail {

// Leaves are tested four triangles at a time (triangle_block.h): the
// blocks a format lays out (triangle_blocks.h, motion_blocks.h) and the
// runs of the others, gathered through their indices (below).
inline constexpr int kLeafBlockWidth = 4;

// The ray as the gathered blocks take it, made once per ray by a traversal:
// the triangle block's ray, and the segment block's, made on first use (its
// unit direction costs a square root and a division that a ray meeting no
// segment run never needs).
struct LeafBlockRay : BlockRay<kLeafBlockWidth> {
  explicit LeafBlockRay(const RayQuery& ray) : BlockRay<kLeafBlockWidth>(ray) {}
  // Whether geometry geomID (g) can be hit by the ray (its mask and time
  // range), and the segment of its steps at the ray's time (s, f as
  // Geometry::segmentAt): the same for every leaf of g along the ray, so
  // worked out once per geometry met in a row (a motion tree's leaves are
  // mostly of one mesh).
  bool segmentOf(uint32_t geomID, const Geometry& g, const RayQuery& ray, uint32_t& s, float& f) const {
    if (geomID != segmentGeom_) {
      segmentGeom_ = geomID;
      segmentLive_ = (g.mask() & ray.mask) != 0 && g.timeRange().contains(ray.time);
      if (segmentLive_) g.segmentAt(ray.time, segment_, fraction_);
    }
    s = segment_;
    f = fraction_;
    return segmentLive_;
  }
  // Valid while the ray's origin and direction are unchanged.
  const SegmentBlockRay<kLeafBlockWidth>& segments(const RayQuery& ray) const {
    if (!segmentsMade_) {
      segments_ = SegmentBlockRay<kLeafBlockWidth>(ray);
      segmentsMade_ = true;
    }
    return segments_;
  }

 private:
  mutable SegmentBlockRay<kLeafBlockWidth> segments_;
  mutable bool segmentsMade_ = false;
  mutable uint32_t segmentGeom_ = 0xFFFFFFFFu;  // the geometry of segment_ (none yet)
  mutable bool segmentLive_ = false;
  mutable uint32_t segment_ = 0;
  mutable float fraction_ = 0.0f;
};

namespace leaf_block {

// The closest hit that test(onHit) reports, as intersectLeaf keeps it:
// each hit replaces `hit` and shrinks ray.tfar; true when there was one.
template <class Test>
inline bool closestOf(RayQuery& ray, Hit& hit, Test&& test) {
  bool found = false;
  test([&](const Hit& h) {
    hit = h;
    ray.tfar = h.t;
    found = true;
    return false;
  });
  return found;
}

// The lanes in `valid` of one block: onHit(hit) for each candidate hit in
// lane order, as testing the lanes' triangles one by one would call it;
// stops when onHit returns true. ref(lane) is the lane's reference; r is
// BlockRay(ray), made once per ray.
template <class Ref, class OnHit>
[[gnu::always_inline]] inline bool testBlock(const TriangleBlock<kLeafBlockWidth>& tri, uint32_t valid,
                                             const Ref& ref, RayQuery& ray, const BlockRay<kLeafBlockWidth>& r,
                                             OnHit&& onHit) {
  TriangleBlockResult<kLeafBlockWidth> res;
  intersectTriangleBlock(ray, r, tri, valid, res);
  for (uint32_t todo = res.candidates | res.scalar; todo != 0; todo &= todo - 1) {
    const int lane = __builtin_ctz(todo);
    if (res.scalar >> lane & 1u) {
      if (leaf_run::testOneTriangle(ref(lane), tri.vertex(0, lane), tri.vertex(1, lane), tri.vertex(2, lane), ray,
                                    onHit))
        return true;
      continue;
    }
    TriangleHit th;
    if (!res.accept(lane, ray, th)) continue;
    if (onHit(leaf_run::triangleHit(ref(lane), th, tri.vertex(0, lane), tri.vertex(1, lane), tri.vertex(2, lane))))
      return true;
  }
  return false;
}

// Lanes [0, n) of a block, n = the leaf's references left (at most W used).
inline uint32_t presentLanes(uint32_t left) {
  return left < uint32_t(kLeafBlockWidth) ? (1u << left) - 1u : (1u << kLeafBlockWidth) - 1u;
}

// The smallest run that is gathered into blocks; one triangle alone is
// cheaper tested by itself.
inline constexpr uint32_t kGatheredRunMin = 2;

// Whether every vertex of b may be read as 16 bytes, its x, y, z and the 4
// bytes after them: the buffer says it holds 4 bytes past its last vertex
// (VertexBuffer::padding; the scene pads the buffers it owns, the Embree
// drop-in reports what its buffers hold). A wide stride alone is not taken
// as leave to read past the last vertex.
inline bool wideReadable(const VertexBuffer& b) { return b.padding >= 4; }

// A geometry's vertices at the ray's time, one to a pack (lanes 0-2: x, y,
// z; lane 3 is not used), for the gathered blocks, the two steps
// interpolated as VerticesAt does (a * (1 - f) + b * f, the same operations
// lane by lane). Two forms, picked once per run (testGatheredRun,
// testGatheredSegments):
// - Lerped: two steps at one stride, both wideReadable: a vertex's offset
//   is worked out once and each step read with one 16-byte load.
// - General: one step or two, any strides; each vertex is one 12-byte load
//   per step at any alignment, never past the vertex.
template <bool Lerped>
struct PackedVerticesAt {
  using P = Pack<kLeafBlockWidth>;
  const char* d0;
  const char* d1;  // null: static geometry (General only)
  size_t s0, s1;
  P w0, w1;

  explicit PackedVerticesAt(const leaf_run::VerticesAt& at)
      : d0(static_cast<const char*>(at.v0->data)),
        d1(at.v1 ? static_cast<const char*>(at.v1->data) : nullptr),
        s0(at.v0->stride),
        s1(at.v1 ? at.v1->stride : 0),
        w0(P::set1(1.0f - at.f)),
        w1(P::set1(at.f)) {}
  [[gnu::always_inline]] P operator[](uint32_t i) const {
    if constexpr (Lerped) {
      const size_t offset = i * s0;  // s1 == s0
      return P::loadu(reinterpret_cast<const float*>(d0 + offset)) * w0 +
             P::loadu(reinterpret_cast<const float*>(d1 + offset)) * w1;
    } else {
      P p = P::load3(reinterpret_cast<const float*>(d0 + i * s0));
      if (d1) p = p * w0 + P::load3(reinterpret_cast<const float*>(d1 + i * s1)) * w1;
      return p;
    }
  }
};

// Four packed vertices (one per lane) as the x, y, z rows of a block's
// structure of arrays, transposed in registers.
[[gnu::always_inline]] inline void storeRows(const Pack<kLeafBlockWidth> (&v)[kLeafBlockWidth], float* x, float* y,
                                             float* z) {
  Pack<kLeafBlockWidth> px, py, pz;
  Pack<kLeafBlockWidth>::transposeXyz(v[0], v[1], v[2], v[3], px, py, pz);
  px.store(x);
  py.store(y);
  pz.store(z);
}

// Whether `at` may take PackedVerticesAt's Lerped form.
inline bool lerpedFits(const leaf_run::VerticesAt& at) {
  return at.v1 && at.v0->stride == at.v1->stride && wideReadable(*at.v0) && wideReadable(*at.v1);
}

// The blocks of a run's triangles, their vertices read through `at`
// (PackedVerticesAt): testGatheredRun below.
template <class At, class TriangleOf, class OnHit>
[[gnu::always_inline]] inline bool testTriangleBlocks(const At& at, const TriangleOf& triangleOf,
                                                      const PrimRef* prims, uint32_t begin, uint32_t end,
                                                      RayQuery& ray, const BlockRay<kLeafBlockWidth>& r,
                                                      OnHit& onHit) {
  constexpr int W = kLeafBlockWidth;
  TriangleBlock<W> block;
  for (uint32_t first = begin; first < end; first += W) {
    Pack<W> v[3][W];
    for (int lane = 0; lane < W; ++lane) {
      // Lanes past the run's end repeat its last triangle (not tested).
      const uint32_t i = std::min(first + uint32_t(lane), end - 1);
      const Triangle& t = triangleOf(i);
      v[0][lane] = at[t.v0];
      v[1][lane] = at[t.v1];
      v[2][lane] = at[t.v2];
    }
    for (int k = 0; k < 3; ++k) storeRows(v[k], block.p[k][0], block.p[k][1], block.p[k][2]);
    const auto ref = [prims, first](int lane) { return prims[first + uint32_t(lane)]; };
    if (testBlock(block, presentLanes(end - first), ref, ray, r, onHit)) return true;
  }
  return false;
}

// A run's triangles gathered into blocks of four at the ray's time through
// their indices, as Embree's Triangle4i and Triangle4iMB leaves do
// (PackedVerticesAt, in the form the geometry's buffers allow), and tested
// by testBlock. onHit(hit) for each candidate hit in reference order, as
// testRun would call it; stops when onHit returns true. `indices`, when
// given, holds the references' triangles (ReferenceTriangles, parallel to
// `prims`); else each is read through its primitive id.
template <class OnHit>
inline bool testGatheredRun(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end, RayQuery& ray,
                            const BlockRay<kLeafBlockWidth>& r, OnHit&& onHit, const Triangle* indices = nullptr) {
  const leaf_run::VerticesAt at(g, ray.time);
  const std::span<const Triangle> tris = g.triangles();
  const auto byIndex = [indices](uint32_t i) -> const Triangle& { return indices[i]; };
  const auto byPrim = [tris, prims](uint32_t i) -> const Triangle& { return tris[prims[i].primID]; };
  if (lerpedFits(at)) {
    if (indices) return testTriangleBlocks(PackedVerticesAt<true>(at), byIndex, prims, begin, end, ray, r, onHit);
    return testTriangleBlocks(PackedVerticesAt<true>(at), byPrim, prims, begin, end, ray, r, onHit);
  }
  if (indices) return testTriangleBlocks(PackedVerticesAt<false>(at), byIndex, prims, begin, end, ray, r, onHit);
  return testTriangleBlocks(PackedVerticesAt<false>(at), byPrim, prims, begin, end, ray, r, onHit);
}

// The blocks of a run's segments, their vertices read through `at`:
// testGatheredSegments below.
template <class At, class OnHit>
[[gnu::always_inline]] inline bool testSegmentBlocks(const At& at, const Geometry& g, const PrimRef* prims,
                                                     uint32_t begin, uint32_t end, RayQuery& ray,
                                                     const SegmentBlockRay<kLeafBlockWidth>& r, OnHit& onHit) {
  constexpr int W = kLeafBlockWidth;
  const std::span<const Segment> segs = g.segments();
  const std::span<const float> radii = g.radii();
  SegmentBlock<W> block;
  for (uint32_t first = begin; first < end; first += W) {
    Pack<W> v[2][W];
    for (int lane = 0; lane < W; ++lane) {
      // Lanes past the run's end repeat its last segment (not tested).
      const Segment& s = segs[prims[std::min(first + uint32_t(lane), end - 1)].primID];
      v[0][lane] = at[s.v0];
      v[1][lane] = at[s.v1];
      block.r[0][lane] = radii[s.v0];
      block.r[1][lane] = radii[s.v1];
    }
    for (int k = 0; k < 2; ++k) storeRows(v[k], block.p[k][0], block.p[k][1], block.p[k][2]);
    for (uint32_t todo = segmentBlockCandidates(r, block, presentLanes(end - first)); todo != 0; todo &= todo - 1) {
      const int lane = __builtin_ctz(todo);
      SegmentHit sh;
      if (!intersectSegment(ray, block.end(0, lane), block.end(1, lane), block.radius(0, lane),
                            block.radius(1, lane), sh))
        continue;
      if (onHit(leaf_detail::segmentHit(prims[first + uint32_t(lane)], sh))) return true;
    }
  }
  return false;
}

// A run's segments gathered four at a time into a block at the ray's time
// (geometry/segment_block.h) as the triangles are (PackedVerticesAt), the
// values `frozen`'s segment blocks hold at their time: the block sorts out
// four at a time the lanes whose line misses the solid, and the rest go to
// intersectSegment in reference order, so onHit(hit) is called as testRun
// would call it; stops when onHit returns true.
template <class OnHit>
inline bool testGatheredSegments(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end,
                                 RayQuery& ray, const SegmentBlockRay<kLeafBlockWidth>& r, OnHit&& onHit) {
  const leaf_run::VerticesAt at(g, ray.time);
  if (lerpedFits(at))
    return testSegmentBlocks(PackedVerticesAt<true>(at), g, prims, begin, end, ray, r, onHit);
  return testSegmentBlocks(PackedVerticesAt<false>(at), g, prims, begin, end, ray, r, onHit);
}

// A plain run of g with the block ray: gathered into blocks when it has two
// or more triangles or segments not stored at a fixed time (true, with
// `hit` = whether a test's onHit returned true), else false (test it by the
// one-by-one path).
template <class OnHit>
inline bool testGathered(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end, RayQuery& ray,
                         const LeafBlockRay& r, OnHit&& onHit, const Triangle* indices, bool& hit) {
  if (end - begin < kGatheredRunMin) return false;
  if (g.type() == GeometryType::Triangles)
    hit = testGatheredRun(g, prims, begin, end, ray, r, onHit, indices);
  else if (g.type() == GeometryType::Segments)
    hit = testGatheredSegments(g, prims, begin, end, ray, r.segments(ray), onHit);
  else
    return false;
  return true;
}

}  // namespace leaf_block

}  // namespace mbrt::detail
