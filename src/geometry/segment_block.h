// W round linear segments against one ray at once: the part of
// intersectSegment (segment_intersect.h) that decides most misses, over
// Pack<W>, lane by lane the same float operations in the same order (the
// build has no FMA contraction, cmake/Isa.cmake; sqrt rounds as std::sqrt):
// the line's distance from the segment's middle against its reach, then
// whether the line enters the solid at all (the cone or either cap). A lane
// that fails either misses exactly as intersectSegment says; the others,
// and the lanes whose reach is outside the float range (where the scalar
// test goes to double), are named for intersectSegment itself, which finds
// the hit and its distance. So a block finds exactly the hits of testing
// its segments one by one. (Embree's curve leaves likewise test several
// segments per SIMD pack.)
#pragma once

#include "core/simd.h"
#include "geometry/segment_intersect.h"

namespace mbrt::detail {

// W segments, structure of arrays: end points p[end][axis][lane] and radii
// r[end][lane].
template <int W>
struct alignas(4 * W) SegmentBlock {
  float p[2][3][W];
  float r[2][W];

  void set(int lane, Vec3f p0, Vec3f p1, float r0, float r1) {
    for (int a = 0; a < 3; ++a) {
      p[0][a][lane] = p0[a];
      p[1][a][lane] = p1[a];
    }
    r[0][lane] = r0;
    r[1][lane] = r1;
  }
  Vec3f end(int k, int lane) const { return {p[k][0][lane], p[k][1][lane], p[k][2][lane]}; }
  float radius(int k, int lane) const { return r[k][lane]; }
};

// The ray's origin and unit direction, broadcast once per ray; `usable` is
// false for a zero or NaN direction, which no segment test accepts.
template <int W>
struct SegmentBlockRay {
  Pack<W> org[3], d[3];
  bool usable = false;
  SegmentBlockRay() = default;  // no ray: no lane is ever a candidate
  explicit SegmentBlockRay(const RayQuery& ray) {
    const float len = length(ray.dir);
    usable = len > 0.0f;
    const Vec3f unit = ray.dir * (1.0f / len);  // as intersectSegment
    for (int a = 0; a < 3; ++a) {
      org[a] = Pack<W>::set1(ray.org[a]);
      d[a] = Pack<W>::set1(unit[a]);
    }
  }
};

namespace segment_block_detail {

template <int W>
struct V3 {
  Pack<W> x, y, z;
};
template <int W>
inline V3<W> operator-(const V3<W>& a, const V3<W>& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
template <int W>
inline Pack<W> dot(const V3<W>& a, const V3<W>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}

}  // namespace segment_block_detail

// The lanes of `valid` that intersectSegment must test (bit i: lane i); a
// lane left out has no hit. r is SegmentBlockRay(ray).
template <int W>
inline uint32_t segmentBlockCandidates(const SegmentBlockRay<W>& r, const SegmentBlock<W>& b, uint32_t valid) {
  using P = Pack<W>;
  using V = segment_block_detail::V3<W>;
  using segment_block_detail::dot;
  if (!r.usable || valid == 0) return 0;
  const P zero = P::set1(0.0f);
  const V p0{P::load(b.p[0][0]), P::load(b.p[0][1]), P::load(b.p[0][2])};
  const V p1{P::load(b.p[1][0]), P::load(b.p[1][1]), P::load(b.p[1][2])};
  const P ra = P::load(b.r[0]), rb = P::load(b.r[1]);
  valid &= ~(lessEqualMask(ra, zero) & lessEqualMask(rb, zero));  // no solid
  const V seg = p1 - p0;
  const P reach = P::set1(0.5f) * sqrt(dot(seg, seg)) + vmax(rb, ra);  // std::max(ra, rb)
  const uint32_t inRange = lessEqualMask(P::set1(1e-4f), reach) & lessEqualMask(reach, P::set1(1e5f));
  const uint32_t scalar = valid & ~inRange;
  uint32_t lanes = valid & inRange;
  if (lanes == 0) return scalar;
  // The point of the line closest to the middle, and the line's distance
  // from it against the reach (segment_detail::throughSolid).
  const P half = P::set1(0.5f);
  const V mid{(p0.x + p1.x) * half, (p0.y + p1.y) * half, (p0.z + p1.z) * half};
  const V d{r.d[0], r.d[1], r.d[2]};
  const V org{r.org[0], r.org[1], r.org[2]};
  const P tm = dot(mid - org, d);
  const V o{org.x + d.x * tm, org.y + d.y * tm, org.z + d.z * tm};
  const V off = o - mid;
  const P along = dot(off, d);
  lanes &= lessEqualMask(dot(off, off) - along * along, reach * reach);
  if (lanes == 0) return scalar;
  // Does the line enter the solid (segment_detail::entry): the cone, else
  // either cap.
  const V ba = p1 - p0, oa = o - p0, ob = o - p1;
  const P rr = ra - rb;
  const P m0 = dot(ba, ba), m1 = dot(ba, oa), m2 = dot(ba, d), m3 = dot(d, oa);
  const P m5 = dot(oa, oa), m6 = dot(ob, d), m7 = dot(ob, ob);
  const P d2 = m0 - rr * rr;
  const P k2 = d2 - m2 * m2;
  const P k1 = d2 * m3 - m1 * m2 + m2 * rr * ra;
  const P k0 = d2 * m5 - m1 * m1 + m1 * rr * ra * P::set1(2.0f) - m0 * ra * ra;
  const P h = k1 * k1 - k0 * k2;
  const P tc = (sqrt(h) * P::set1(-1.0f) - k1) / k2;  // -sqrt(h): * -1 flips the sign exactly
  const P y = m1 - ra * rr + tc * m2;
  const uint32_t cone = lessMask(zero, d2) & lessEqualMask(zero, h) & ~equalMask(k2, zero) & lessMask(zero, y) &
                        lessMask(y, d2);
  const P h1 = m3 * m3 - m5 + ra * ra;
  const P h2 = m6 * m6 - m7 + rb * rb;
  const uint32_t caps = (lessEqualMask(zero, h1) & lessMask(zero, ra)) | (lessEqualMask(zero, h2) & lessMask(zero, rb));
  return scalar | (lanes & (cone | caps));
}

}  // namespace mbrt::detail
