// Ray / round linear segment: the convex hull of the spheres (p0,r0) and
// (p1,r1), i.e. both spheres and the cone tangent to them, as Embree's round
// linear curves. The solid is convex, so a ray meets it in one interval
// [tin, tout]; the hit is tin, or tout when the ray starts inside.
#pragma once

#include <cmath>

#include "core/ray_query.h"

namespace mbrt::detail {

struct SegmentHit {
  float t, u;  // u: position along the segment in [0,1]
  Vec3f Ng;
};

namespace segment_detail {

// Entry distance of the line o + t*d (|d| = 1) into the solid; false if the
// line misses it. Rounded cone intersection after I. Quilez's derivation.
inline bool entry(Vec3f o, Vec3f d, Vec3f pa, Vec3f pb, float ra, float rb, float& t, float& u, Vec3f& n) {
  const Vec3f ba = pb - pa, oa = o - pa, ob = o - pb;
  const float rr = ra - rb;
  const float m0 = dot(ba, ba), m1 = dot(ba, oa), m2 = dot(ba, d), m3 = dot(d, oa);
  const float m5 = dot(oa, oa), m6 = dot(ob, d), m7 = dot(ob, ob);
  const float d2 = m0 - rr * rr;
  if (d2 > 0.0f) {
    const float k2 = d2 - m2 * m2;
    const float k1 = d2 * m3 - m1 * m2 + m2 * rr * ra;
    const float k0 = d2 * m5 - m1 * m1 + m1 * rr * ra * 2.0f - m0 * ra * ra;
    const float h = k1 * k1 - k0 * k2;
    if (h >= 0.0f && k2 != 0.0f) {
      const float tc = (-std::sqrt(h) - k1) / k2;
      const float y = m1 - ra * rr + tc * m2;
      if (y > 0.0f && y < d2) {
        t = tc;
        u = y / d2;
        n = (oa + d * tc) * d2 - ba * y;
        return true;
      }
    }
  }
  // Caps: the first sphere entry (or the bigger sphere when one holds the other).
  const float h1 = m3 * m3 - m5 + ra * ra;
  const float h2 = m6 * m6 - m7 + rb * rb;
  bool hit = false;
  if (h1 >= 0.0f && ra > 0.0f) {
    t = -m3 - std::sqrt(h1);
    u = 0.0f;
    n = oa + d * t;
    hit = true;
  }
  if (h2 >= 0.0f && rb > 0.0f) {
    const float t2 = -m6 - std::sqrt(h2);
    if (!hit || t2 < t) {
      t = t2;
      u = 1.0f;
      n = ob + d * t2;
      hit = true;
    }
  }
  return hit;
}

}  // namespace segment_detail

inline bool intersectSegment(const RayQuery& ray, Vec3f p0, Vec3f p1, float r0, float r1, SegmentHit& out) {
  const float len = length(ray.dir);
  if (!(len > 0.0f) || (r0 <= 0.0f && r1 <= 0.0f)) return false;
  const Vec3f d = ray.dir * (1.0f / len);
  // Start near the solid so that cancellation stays small.
  const Vec3f mid = (p0 + p1) * 0.5f;
  const float reach = 0.5f * length(p1 - p0) + std::max(r0, r1);
  const float tm = dot(mid - ray.org, d);
  const Vec3f o = ray.org + d * tm;
  float tin, u;
  Vec3f n;
  if (!segment_detail::entry(o, d, p0, p1, r0, r1, tin, u, n)) return false;
  // Exit: entry of the reversed line, started beyond the solid.
  const float far = reach * 2.0f + 1.0f;
  float tback, uback;
  Vec3f nback;
  if (!segment_detail::entry(o + d * far, -d, p0, p1, r0, r1, tback, uback, nback)) return false;
  const float tout = far - tback;
  const float enter = (tm + tin) / len, exit = (tm + tout) / len;
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
