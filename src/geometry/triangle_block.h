// W triangles against one ray at once: the watertight test of
// triangle_intersect.h (Woop, Benthin, Wald, JCGT 2013) evaluated over
// Pack<W>, lane by lane the same operations in the same order (the build
// has no FMA contraction, cmake/Isa.cmake), so every lane rounds exactly
// as intersectTriangle does. The rare lanes the scalar test would redo in
// double (an edge function exactly zero, T or det not finite) are flagged
// for intersectTriangle itself; the others come back with their t, u, v
// and the terms of the scalar test's tfar check, which the caller repeats
// lane by lane in order against the ray's current tfar (a hit in an earlier
// lane shrinks it), so a block finds exactly the hits that testing its
// triangles one by one finds. (Embree's Triangle4 leaves test four
// triangles per SIMD pack likewise, with Möller-Trumbore by default.)
#pragma once

#include "core/simd.h"
#include "geometry/triangle_intersect.h"

namespace mbrt::detail {

// The vertices of W triangles, structure of arrays in world axes:
// p[vertex][axis][lane]. The test picks the ray's permuted axes by index.
template <int W>
struct alignas(4 * W) TriangleBlock {
  float p[3][3][W];

  void set(int lane, Vec3f v0, Vec3f v1, Vec3f v2) {
    const Vec3f v[3] = {v0, v1, v2};
    for (int k = 0; k < 3; ++k)
      for (int a = 0; a < 3; ++a) p[k][a][lane] = v[k][a];
  }
  Vec3f vertex(int k, int lane) const { return {p[k][0][lane], p[k][1][lane], p[k][2][lane]}; }
};

template <int W>
struct TriangleBlockResult {
  uint32_t candidates = 0;  // lanes within [tnear, tfar] of the ray when tested
  uint32_t scalar = 0;      // lanes to test with intersectTriangle
  alignas(4 * W) float t[W], u[W], v[W], Ts[W], absDet[W];

  // Lane `lane` of `candidates` against the ray's current tfar, as
  // intersectTriangle's last checks.
  bool accept(int lane, const RayQuery& ray, TriangleHit& out) const {
    if (Ts[lane] > ray.tfar * absDet[lane]) return false;
    out.t = t[lane];
    if (!(out.t >= ray.tnear && out.t <= ray.tfar)) return false;
    out.u = u[lane];
    out.v = v[lane];
    return true;
  }
};

// What the block test needs of a ray that does not change along its
// traversal (all but tfar), broadcast once per ray: the origin in the
// permuted axes, the shear, and the permuted axes' rows of a block as byte
// offsets into a vertex's rows (so that a leaf works out no addresses).
template <int W>
struct BlockRay {
  Pack<W> org[3], Sx, Sy, Sz;
  size_t row[3];
  explicit BlockRay(const RayQuery& ray) {
    const int axis[3] = {ray.kx, ray.ky, ray.kz};
    const float o[3] = {ray.org.x, ray.org.y, ray.org.z};  // by index: no branch on the axes
    for (int c = 0; c < 3; ++c) {
      org[c] = Pack<W>::set1(o[axis[c]]);
      row[c] = size_t(axis[c]) * sizeof(TriangleBlock<W>::p[0][0]);
    }
    Sx = Pack<W>::set1(ray.Sx);
    Sy = Pack<W>::set1(ray.Sy);
    Sz = Pack<W>::set1(ray.Sz);
  }
};

// The lanes in `valid` of block b against the ray (its tnear and tfar now);
// r is BlockRay(ray). Inlined into each leaf format's loop (fewer
// instructions than the call, docs/performance.md).
template <int W>
[[gnu::always_inline]] inline void intersectTriangleBlock(const RayQuery& ray, const BlockRay<W>& r,
                                                          const TriangleBlock<W>& b, uint32_t valid,
                                                          TriangleBlockResult<W>& out) {
  using P = Pack<W>;
  P rel[3][3];  // vertex - org, per permuted component: (v - org)[k] as the scalar test
  for (int c = 0; c < 3; ++c)
    for (int k = 0; k < 3; ++k)
      rel[k][c] = P::load(reinterpret_cast<const float*>(reinterpret_cast<const char*>(b.p[k]) + r.row[c])) - r.org[c];
  const P Sx = r.Sx, Sy = r.Sy, Sz = r.Sz;
  const P Ax = rel[0][0] - Sx * rel[0][2], Ay = rel[0][1] - Sy * rel[0][2];
  const P Bx = rel[1][0] - Sx * rel[1][2], By = rel[1][1] - Sy * rel[1][2];
  const P Cx = rel[2][0] - Sx * rel[2][2], Cy = rel[2][1] - Sy * rel[2][2];
  const P U = Cx * By - Cy * Bx;
  const P V = Ax * Cy - Ay * Cx;
  const P Wt = Bx * Ay - By * Ax;
  const P zero = P::set1(0.0f);
  // The edge tests combined as lane masks, one bit mask each at the end.
  const uint32_t zeroEdge = laneBits(equalLanes(U, zero) | equalLanes(V, zero) | equalLanes(Wt, zero));
  const P negative = lessLanes(U, zero) | lessLanes(V, zero) | lessLanes(Wt, zero);
  const P positive = lessLanes(zero, U) | lessLanes(zero, V) | lessLanes(zero, Wt);
  const P det = U + V + Wt;
  const uint32_t edgesPass = valid & ~zeroEdge & ~laneBits((negative & positive) | equalLanes(det, zero));
  out.scalar = valid & zeroEdge;
  out.candidates = 0;
  if (edgesPass == 0) return;
  const P Az = Sz * rel[0][2], Bz = Sz * rel[1][2], Cz = Sz * rel[2][2];
  const P T = U * Az + V * Bz + Wt * Cz;
  const uint32_t finite = lessMask(abs(T + det), P::set1(kInf));  // NaN: not finite
  const P sign = (det & P::set1(-0.0f)) | P::set1(1.0f);  // det < 0 ? -1 : 1 (det is not 0 or NaN here)
  const P Ts = T * sign, absDet = det * sign;
  const uint32_t outside = lessMask(Ts, P::set1(ray.tnear) * absDet) | lessMask(P::set1(ray.tfar) * absDet, Ts);
  out.scalar |= edgesPass & ~finite;
  out.candidates = edgesPass & finite & ~outside;
  if (out.candidates == 0) return;
  const P rcpDet = P::set1(1.0f) / det;
  (T * rcpDet).store(out.t);
  (V * rcpDet).store(out.u);
  (Wt * rcpDet).store(out.v);
  Ts.store(out.Ts);
  absDet.store(out.absDet);
}

template <int W>
inline void intersectTriangleBlock(const RayQuery& ray, const TriangleBlock<W>& b, uint32_t valid,
                                   TriangleBlockResult<W>& out) {
  intersectTriangleBlock(ray, BlockRay<W>(ray), b, valid, out);
}

}  // namespace mbrt::detail
