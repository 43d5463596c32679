// Ray / round linear segment: the convex hull of the spheres (p0,r0) and
// (p1,r1), i.e. both spheres and the cone tangent to them, as Embree's round
// linear curves. The solid is convex, so a ray meets it in one interval
// [tin, tout]; the hit is tin, or tout when the ray starts inside.
//
// The entry test multiplies up to six lengths of the solid's size (k1*k1),
// so float covers solids of size 1e-4 to 1e5 (products within 1e-24..1e30);
// outside that range the same arithmetic runs in double, which covers every
// size up to the coordinate limit (1e18: products near 1e108).
#pragma once

#include <cmath>

#include "core/ray_query.h"
#include "core/vec3d.h"

namespace mbrt::detail {

struct SegmentHit {
  float t, u;  // u: position along the segment in [0,1]
  Vec3f Ng;
};

namespace segment_detail {

// The test below runs in float and, for its retry, in double (Vec3d).
inline Vec3f narrow(Vec3d v) { return toF(v); }
inline Vec3f narrow(Vec3f v) { return v; }

// Entry distance of the line o + t*d (|d| = 1) into the solid; false if the
// line misses it. Rounded cone intersection after I. Quilez's derivation.
template <typename V, typename F>
inline bool entry(V o, V d, V pa, V pb, F ra, F rb, F& t, F& u, V& n) {
  using std::sqrt;
  const V ba = pb - pa, oa = o - pa, ob = o - pb;
  const F rr = ra - rb;
  const F m0 = dot(ba, ba), m1 = dot(ba, oa), m2 = dot(ba, d), m3 = dot(d, oa);
  const F m5 = dot(oa, oa), m6 = dot(ob, d), m7 = dot(ob, ob);
  const F d2 = m0 - rr * rr;
  if (d2 > F(0)) {
    const F k2 = d2 - m2 * m2;
    const F k1 = d2 * m3 - m1 * m2 + m2 * rr * ra;
    const F k0 = d2 * m5 - m1 * m1 + m1 * rr * ra * F(2) - m0 * ra * ra;
    const F h = k1 * k1 - k0 * k2;
    if (h >= F(0) && k2 != F(0)) {
      const F tc = (-sqrt(h) - k1) / k2;
      const F y = m1 - ra * rr + tc * m2;
      if (y > F(0) && y < d2) {
        t = tc;
        u = y / d2;
        n = (oa + d * tc) * d2 - ba * y;
        return true;
      }
    }
  }
  // Caps: the first sphere entry (or the bigger sphere when one holds the other).
  const F h1 = m3 * m3 - m5 + ra * ra;
  const F h2 = m6 * m6 - m7 + rb * rb;
  bool hit = false;
  if (h1 >= F(0) && ra > F(0)) {
    t = -m3 - sqrt(h1);
    u = F(0);
    n = oa + d * t;
    hit = true;
  }
  if (h2 >= F(0) && rb > F(0)) {
    const F t2 = -m6 - sqrt(h2);
    if (!hit || t2 < t) {
      t = t2;
      u = F(1);
      n = ob + d * t2;
      hit = true;
    }
  }
  return hit;
}

// The test in scalar F on vectors V, from the ray's origin and unit
// direction in V; t of the entry and exit along the unit direction.
template <typename V, typename F>
inline bool throughSolid(V org, V d, V p0, V p1, F r0, F r1, F reach, F& tin, F& tout, F& u, F& uback, V& n,
                         V& nback) {
  using std::sqrt;
  // Start near the solid so that cancellation stays small: o is the point
  // of the line closest to the middle (up to the rounding of org + d*tm,
  // which moves it along the line only); a line passing farther than
  // `reach` from the middle misses.
  const V mid = (p0 + p1) * F(0.5);
  const F tm = dot(mid - org, d);
  const V o = org + d * tm;
  const V off = o - mid;
  const F along = dot(off, d);
  if (!(dot(off, off) - along * along <= reach * reach)) return false;
  if (!entry(o, d, p0, p1, r0, r1, tin, u, n)) return false;
  // Exit: entry of the reversed line, started beyond the solid (every point
  // of the solid on the line is within reach of o).
  const F far = reach * F(2);
  F tback;
  if (!entry(o + d * far, -d, p0, p1, r0, r1, tback, uback, nback)) return false;
  tout = tm + far - tback;
  tin = tm + tin;
  return true;
}

}  // namespace segment_detail

inline bool intersectSegment(const RayQuery& ray, Vec3f p0, Vec3f p1, float r0, float r1, SegmentHit& out) {
  using namespace segment_detail;
  const float len = length(ray.dir);
  if (!(len > 0.0f) || (r0 <= 0.0f && r1 <= 0.0f)) return false;
  const Vec3f d = ray.dir * (1.0f / len);
  const float reach = 0.5f * length(p1 - p0) + std::max(r0, r1);
  float tin, tout, u, uback;
  Vec3f n, nback;
  if (reach >= 1e-4f && reach <= 1e5f) {
    if (!throughSolid(ray.org, d, p0, p1, r0, r1, reach, tin, tout, u, uback, n, nback)) return false;
  } else {
    double tin64, tout64, u64, uback64;
    Vec3d n64, nback64;
    const Vec3d d64 = toD(ray.dir) * (1.0 / std::sqrt(dot(toD(ray.dir), toD(ray.dir))));
    const double reach64 = 0.5 * std::sqrt(dot(toD(p1) - toD(p0), toD(p1) - toD(p0))) + std::max(r0, r1);
    if (!throughSolid(toD(ray.org), d64, toD(p0), toD(p1), double(r0), double(r1), reach64, tin64, tout64,
                      u64, uback64, n64, nback64))
      return false;
    tin = float(tin64), tout = float(tout64), u = float(u64), uback = float(uback64);
    n = narrow(n64), nback = narrow(nback64);
  }
  const float enter = tin / len, exit = tout / len;
  if (enter >= ray.tnear && enter <= ray.tfar) {
    out = {enter, u, n};
    return true;
  }
  if (exit >= ray.tnear && exit <= ray.tfar && exit >= enter) {
    out = {exit, uback, nback};
    return true;
  }
  return false;
}

}  // namespace mbrt::detail
