#include "geometry/clip.h"

#include <algorithm>
#include <cmath>

#include "core/simd.h"

namespace mbrt::detail {
namespace {

// Keeps the part of `in` on the inner side of the plane x[axis] = value
// (side < 0: keep x <= value; side > 0: keep x >= value). Barycentrics are
// carried only when `Bary`; positions are the same either way.
template <bool Bary>
void clipPlane(const ClippedPolygon& in, int axis, float value, int side, ClippedPolygon& out) {
  out.count = 0;
  if (in.count == 0) return;
  auto inside = [&](const Vec3f& p) { return side < 0 ? p[axis] <= value : p[axis] >= value; };
  for (int i = 0; i < in.count; ++i) {
    const int j = (i + 1) % in.count;
    const Vec3f &a = in.pos[i], &b = in.pos[j];
    const bool ia = inside(a), ib = inside(b);
    if (ia) {
      out.pos[out.count] = a;
      if constexpr (Bary) out.bary[out.count] = in.bary[i];
      ++out.count;
    }
    if (ia != ib) {
      // Crossing point, computed from the inside vertex towards the outside
      // one; the coordinate on the plane is set exactly.
      const int from = ia ? i : j, to = ia ? j : i;
      const Vec3f &p = in.pos[from], &q = in.pos[to];
      const float s = std::clamp((value - p[axis]) / (q[axis] - p[axis]), 0.0f, 1.0f);
      Vec3f c = lerp(p, q, s);
      c[axis] = value;
      out.pos[out.count] = c;
      if constexpr (Bary) out.bary[out.count] = lerp(in.bary[from], in.bary[to], s);
      ++out.count;
    }
  }
}

// How a plane meets a polygon: every vertex inside (clipping copies it
// unchanged), none (clipping empties it), or some.
enum class Cut { None, All, Some };
Cut cutBy(const ClippedPolygon& p, int axis, float value, int side) {
  int in = 0;
  for (int i = 0; i < p.count; ++i) in += side < 0 ? p.pos[i][axis] <= value : p.pos[i][axis] >= value;
  return in == p.count ? Cut::None : in == 0 ? Cut::All : Cut::Some;
}

// Clips `poly` by the finite planes of `box`, skipping planes that cut
// nothing (they would copy the polygon unchanged).
template <bool Bary>
ClippedPolygon clipToBox(const ClippedPolygon& poly, const Box3f& box) {
  ClippedPolygon a = poly, b;
  ClippedPolygon* cur = &a;
  ClippedPolygon* nxt = &b;
  auto plane = [&](int axis, float value, int side) {
    if (!std::isfinite(value) || cur->count == 0) return;
    const Cut cut = cutBy(*cur, axis, value, side);
    if (cut == Cut::None) return;
    if (cut == Cut::All) {
      cur->count = 0;
      return;
    }
    clipPlane<Bary>(*cur, axis, value, side, *nxt);
    std::swap(cur, nxt);
  };
  for (int axis = 0; axis < 3; ++axis) {
    plane(axis, box.lower[axis], +1);
    plane(axis, box.upper[axis], -1);
  }
  return *cur;
}

ClippedPolygon triangle(Vec3f v0, Vec3f v1, Vec3f v2) {
  ClippedPolygon a;
  a.count = 3;
  a.pos[0] = v0;
  a.pos[1] = v1;
  a.pos[2] = v2;
  a.bary[0] = {1, 0, 0};
  a.bary[1] = {0, 1, 0};
  a.bary[2] = {0, 0, 1};
  return a;
}

}  // namespace

ClippedPolygon clipTriangle(Vec3f v0, Vec3f v1, Vec3f v2, const Box3f& box) {
  return clipToBox<true>(triangle(v0, v1, v2), box);
}

Box3f clipTriangleBounds(Vec3f v0, Vec3f v1, Vec3f v2, const Box3f& box) {
  return clipToBox<false>(triangle(v0, v1, v2), box).bounds();
}

namespace {

using P4 = Pack<4>;

// Box3f::extend(p) and intersect() in three lanes, the operands in the
// order that makes each lane pick as std::min / std::max do (same bits,
// signed zeros included).
struct LaneBox {
  P4 lo = P4::set1(kInf), hi = P4::set1(-kInf);
  void extend(P4 p) {
    lo = vmin(p, lo);
    hi = vmax(p, hi);
  }
  LaneBox intersect(const LaneBox& with) const { return {vmax(with.lo, lo), vmin(with.hi, hi)}; }
  Box3f get() const {
    alignas(16) float l[4], h[4];
    lo.store(l);
    hi.store(h);
    return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
  }
};

P4 lanesOf(Vec3f v) { return P4::of(v.x, v.y, v.z, 0.0f); }

}  // namespace

void chopTriangle(Vec3f v0, Vec3f v1, Vec3f v2, const Box3f& box, int axis, std::span<const float> planes,
                  Box3f* pieces) {
  const Vec3f v[3] = {v0, v1, v2};
  const P4 lanes[3] = {lanesOf(v0), lanesOf(v1), lanesOf(v2)};
  // The axis lane, and the others: an edge crossing is put on the plane.
  const P4 index = P4::of(0.0f, 1.0f, 2.0f, 3.0f), axisIndex = P4::set1(float(axis));
  const P4 onAxis = equalLanes(index, axisIndex), offAxis = lessLanes(index, axisIndex) | lessLanes(axisIndex, index);
  LaneBox rest{lanesOf(box.lower), lanesOf(box.upper)};
  for (size_t k = 0; k < planes.size(); ++k) {
    const float p = planes[k];
    LaneBox below, above;
    for (int e = 0; e < 3; ++e) {
      const int f = e == 2 ? 0 : e + 1;
      const float a = v[e][axis], b = v[f][axis];
      if (a <= p) below.extend(lanes[e]);
      if (a >= p) above.extend(lanes[e]);
      if ((a < p && b > p) || (a > p && b < p)) {
        const float t = std::clamp((p - a) / (b - a), 0.0f, 1.0f);  // lerp(v[e], v[f], t), then x[axis] = p
        const P4 c = ((lanes[e] * P4::set1(1.0f - t) + lanes[f] * P4::set1(t)) & offAxis) | (P4::set1(p) & onAxis);
        below.extend(c);
        above.extend(c);
      }
    }
    pieces[k] = below.intersect(rest).get();
    rest = above.intersect(rest);
  }
  pieces[planes.size()] = rest.get();
}

bool clipSegment(Vec3f a, Vec3f b, const Box3f& box, float& s0, float& s1) {
  s0 = 0.0f;
  s1 = 1.0f;
  const Vec3f d = b - a;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = box.lower[axis], hi = box.upper[axis];
    if (d[axis] == 0.0f) {
      if (a[axis] < lo || a[axis] > hi) return false;
      continue;
    }
    const float inv = 1.0f / d[axis];
    float t0 = (lo - a[axis]) * inv, t1 = (hi - a[axis]) * inv;
    if (t0 > t1) std::swap(t0, t1);
    // NaN (inf - inf) never narrows the interval.
    if (t0 > s0) s0 = t0;
    if (t1 < s1) s1 = t1;
  }
  return s0 <= s1;
}

}  // namespace mbrt::detail
