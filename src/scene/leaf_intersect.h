// The leaf test of every kind with leaves (the BVH kinds, msbvh, and the
// kd kinds' surviving references): a leaf's references, sorted by geometry
// where the builder stores the leaf (bvh/build/builder.cpp), are tested one
// run of a geometry at a time. A run checks the geometry's mask and time range and
// finds the ray's motion segment once, then interpolates each primitive's
// vertices with the same arithmetic as `intersectPrimitive`
// (primitive_intersect.h), so hits are bit-identical to testing the
// references one by one. Instances and geometries with a filter take the
// per-reference path. (STBVH §4: leaves are tested at the ray's time.)
// A static tree (`frozen`) reads its triangles from FixedTimeTriangles,
// the vertices at its one time laid out per primitive, instead of
// interpolating them through the indices (docs/performance.md).
// Where the traversal gives a LeafBlockRay, a run of two or more triangles
// or segments is gathered four at a time into a block at the ray's time and
// tested in SIMD lanes (leaf_block::testGathered), with the same hits.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "core/huge_pages.h"
#include "geometry/segment_block.h"
#include "geometry/triangle_block.h"
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

// Leaves are tested four triangles at a time (triangle_block.h): the
// blocks a structure keeps (leaf_blocks.h, motion_leaf_blocks.h) and the
// runs of the others, gathered through their indices (below).
inline constexpr int kLeafBlockWidth = 4;

// The ray as the gathered blocks take it, made once per ray by a traversal:
// the triangle block's ray, and the segment block's, made on first use (its
// unit direction costs a square root and a division that a ray meeting no
// segment run never needs).
struct LeafBlockRay : BlockRay<kLeafBlockWidth> {
  explicit LeafBlockRay(const RayQuery& ray) : BlockRay<kLeafBlockWidth>(ray) {}
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

// A geometry's vertices at the ray's time, one to a pack (lanes 0-2: x, y,
// z), for the gathered blocks: each vertex is one 12-byte load per step
// (at any alignment, never past the vertex), the two steps interpolated as
// VerticesAt does (a * (1 - f) + b * f, the same operations lane by lane).
struct PackedVerticesAt {
  using P = Pack<kLeafBlockWidth>;
  const char* d0;
  const char* d1;  // null: static geometry
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
    P p = P::load3(reinterpret_cast<const float*>(d0 + i * s0));
    if (d1) p = p * w0 + P::load3(reinterpret_cast<const float*>(d1 + i * s1)) * w1;
    return p;
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

// A run's triangles gathered into blocks of four at the ray's time through
// their indices, as Embree's Triangle4i and Triangle4iMB leaves do
// (PackedVerticesAt), and tested by testBlock. onHit(hit) for each
// candidate hit in reference order, as testRun would call it; stops when
// onHit returns true. `indices`, when given, holds the references'
// triangles (ReferenceTriangles, parallel to `prims`); else each is read
// through its primitive id.
template <class OnHit>
inline bool testGatheredRun(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end, RayQuery& ray,
                            const BlockRay<kLeafBlockWidth>& r, OnHit&& onHit, const Triangle* indices = nullptr) {
  constexpr int W = kLeafBlockWidth;
  const PackedVerticesAt at(leaf_run::VerticesAt(g, ray.time));
  const std::span<const Triangle> tris = g.triangles();
  TriangleBlock<W> block;
  for (uint32_t first = begin; first < end; first += W) {
    Pack<W> v[3][W];
    for (int lane = 0; lane < W; ++lane) {
      // Lanes past the run's end repeat its last triangle (not tested).
      const uint32_t i = std::min(first + uint32_t(lane), end - 1);
      const Triangle& t = indices ? indices[i] : tris[prims[i].primID];
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

// A run's segments gathered four at a time into a block at the ray's time
// (geometry/segment_block.h) as the triangles are (PackedVerticesAt), the
// values `frozen`'s segment blocks hold at their time: the block sorts out
// four at a time the lanes whose line misses the solid, and the rest go to
// intersectSegment in reference order, so onHit(hit) is called as testRun
// would call it; stops when onHit returns true.
template <class OnHit>
inline bool testGatheredSegments(const Geometry& g, const PrimRef* prims, uint32_t begin, uint32_t end,
                                 RayQuery& ray, const SegmentBlockRay<kLeafBlockWidth>& r, OnHit&& onHit) {
  constexpr int W = kLeafBlockWidth;
  const PackedVerticesAt at(leaf_run::VerticesAt(g, ray.time));
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

// The triangles of a scene at one time, three vertices each, in primitive
// order per geometry: `frozen`'s leaves read a triangle in one place
// instead of through its indices and the vertex buffers (as Embree's
// static leaves keep their vertices). The values are those VerticesAt
// computes at that time, so hits are unchanged. Geometries with a filter,
// segments and instances are not stored (their runs take the other paths).
struct FixedTimeTriangles {
  static constexpr uint32_t kNotStored = 0xFFFFFFFFu;
  std::vector<uint32_t> first;  // per geometry: the index in `vertices` of its triangle 0's v0, or kNotStored
  std::vector<Vec3f> vertices;

  FixedTimeTriangles() = default;
  FixedTimeTriangles(const SceneContext& ctx, float time) {
    const uint32_t count = ctx.scene().numGeometries();
    first.assign(count, kNotStored);
    size_t total = 0;
    for (uint32_t id = 0; id < count; ++id)
      if (stores(ctx.geometry(id), time)) total += 3 * ctx.geometry(id).triangles().size();
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

 private:
  static bool stores(const Geometry& g, float time) {
    return g.type() == GeometryType::Triangles && !g.hasFilter() && g.timeRange().contains(time) &&
           3 * g.triangles().size() < kNotStored;
  }
};

// The vertex indices of each reference's triangle, in the order of a
// tree's reference table (zeros for other primitives): a gathered run reads
// its triangles next to its references instead of through each one's
// primitive id, one dependent load less per block (the leaf keeps its
// triangles' indices, as Embree's Triangle4i leaves do). 12 bytes a
// reference; kept by the trees whose leaves are charged per block
// (`stbvh`, `bvh-segments`) where it pays (docs/performance.md, "Leaves
// gathered into blocks through their indices").
struct ReferenceTriangles {
  // Where it pays: the scene's triangles' indices take more than a core's
  // second-level cache (1 MB here, as RayCostWeights::cacheBytes), so that
  // reading a triangle through its primitive id waits on memory. On smaller
  // scenes those indices stay cached and the table only adds bytes to read.
  static constexpr size_t kPaysFromBytes = size_t(1) << 20;
  static bool pays(const SceneContext& ctx) {
    size_t bytes = 0;
    for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id)
      if (ctx.geometry(id).type() == GeometryType::Triangles) bytes += ctx.geometry(id).triangles().size_bytes();
    return bytes > kPaysFromBytes;
  }

  std::vector<Triangle> tris;

  ReferenceTriangles() = default;
  ReferenceTriangles(const SceneContext& ctx, std::span<const PrimRef> prims) {
    ctx.budget().charge(prims.size() * sizeof(Triangle), "the tree's reference triangles");
    resizeOnHugePages(tris, prims.size());
    for (size_t i = 0; i < prims.size(); ++i) {
      const Geometry& g = ctx.geometry(prims[i].geomID);
      if (g.type() == GeometryType::Triangles) tris[i] = g.triangles()[prims[i].primID];
    }
  }
  bool empty() const { return tris.empty(); }
  // The triangles of the references from table entry `begin` on.
  const Triangle* from(uint32_t begin) const { return tris.data() + begin; }
  size_t bytes() const { return tris.size() * sizeof(Triangle); }
};

// Closest hit among a leaf's references (as intersectPrimitive on each).
// Stored: the leaf may read triangles from `stored` (static trees only).
// With `blockRay`, runs of two or more triangles or segments not stored are
// gathered into blocks (leaf_block::testGathered), reading the references'
// triangles from `indices` when given (ReferenceTriangles); counters count
// them as block tests.
template <bool Stored = false>
inline bool intersectLeaf(const SceneContext& ctx, const PrimRef* prims, uint32_t count, RayQuery& ray, Hit& hit,
                          TraversalCounters* counters, const FixedTimeTriangles* stored = nullptr,
                          const LeafBlockRay* blockRay = nullptr, const Triangle* indices = nullptr) {
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
        const Vec3f* v = Stored && stored ? stored->of(prims[begin].geomID) : nullptr;
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
template <bool Stored = false>
inline bool occludedLeaf(const SceneContext& ctx, const PrimRef* prims, uint32_t count, RayQuery& ray,
                         const FixedTimeTriangles* stored = nullptr, const LeafBlockRay* blockRay = nullptr,
                         const Triangle* indices = nullptr) {
  for (uint32_t begin = 0; begin < count;) {
    const uint32_t end = leaf_run::runEnd(prims, begin, count);
    const Geometry& g = ctx.geometry(prims[begin].geomID);
    if ((g.mask() & ray.mask) != 0 && g.timeRange().contains(ray.time)) {
      if (leaf_run::plainRun(g)) {
        const Vec3f* v = Stored && stored ? stored->of(prims[begin].geomID) : nullptr;
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

}  // namespace mbrt::detail
