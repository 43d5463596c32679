#include "scene/primitive_bounds.h"

#include <cmath>
#include <cstring>

#include "core/simd.h"

namespace mbrt::detail {
namespace {


// A Vec3f in the first three lanes of a 4-lane pack (the fourth unused).
// Each operation rounds as its Vec3f twin, and minOf / maxOf pick as
// std::min / std::max do (the first operand on ties and NaN), so the bounds
// are those of the Vec3f arithmetic, bit for bit.
using P4 = Pack<4>;
inline P4 xyz(const void* p) { return P4::load3(static_cast<const float*>(p)); }  // any alignment
inline P4 xyz(const Vec3f& p) { return P4::load3(&p.x); }
inline P4 minOf(P4 a, P4 b) { return vmin(b, a); }
inline P4 maxOf(P4 a, P4 b) { return vmax(b, a); }

struct BoxPack {
  P4 lower, upper;
  static BoxPack of(const Box3f& b) { return {xyz(b.lower), xyz(b.upper)}; }
};

BoxPack lerp(const BoxPack& a, const BoxPack& b, float t) {
  const P4 u = P4::set1(1.0f - t), w = P4::set1(t);
  return {a.lower * u + b.lower * w, a.upper * u + b.upper * w};
}

// PrimKeys::operator() in lanes.
inline BoxPack keyBox(const PrimKeys& keys, uint32_t key) {
  if (keys.instance) return BoxPack::of(keys.instance[key]);
  const VertexBuffer& vb = keys.geometry->vertices(key);
  auto vertex = [&](uint32_t i) { return xyz(static_cast<const char*>(vb.data) + i * vb.stride); };
  const P4 a = vertex(keys.v[0]), b = vertex(keys.v[1]), c = vertex(keys.v[2]);
  const P4 r = P4::set1(keys.radius);
  return {minOf(minOf(a, b), c) - r, maxOf(maxOf(a, b), c) + r};
}

// The LBounds b0 -> b1: its 12 floats go out in one storeXyz.
LBounds packed(const BoxPack& b0, const BoxPack& b1) {
  static_assert(sizeof(LBounds) == 12 * sizeof(float));
  float f[12];
  P4::storeXyz(b0.lower, b0.upper, b1.lower, b1.upper, f);
  LBounds out;
  std::memcpy(&out, f, sizeof(out));
  return out;
}

// widen(LBounds) of the linear bounds b0 -> b1.
LBounds widened(const BoxPack& b0, const BoxPack& b1) {
  // One slack per axis for both ends: that of the largest magnitude among
  // the four corners (the slack grows with the magnitude), in three lanes.
  const P4 m = maxOf(maxOf(abs(b0.lower), abs(b0.upper)), maxOf(abs(b1.lower), abs(b1.upper)));
  const P4 s = m * P4::set1(kRelativeSlack) + P4::set1(1e-30f);
  return packed({b0.lower - s, b0.upper + s}, {b1.lower - s, b1.upper + s});
}

}  // namespace

LBounds widen(const LBounds& bounds) { return widened(BoxPack::of(bounds.b0), BoxPack::of(bounds.b1)); }

Box3f boxAt(const SceneContext& ctx, PrimRef ref, float time) {
  const Geometry& g = ctx.geometry(ref.geomID);
  const PrimKeys keys = ctx.keys(ref);
  if (g.numSteps() == 1) return keys(0);
  const TimeRange r = g.timeRange();
  uint32_t s;
  float f;
  g.segmentAt(std::clamp(time, r.lo, r.hi), s, f);
  return lerp(keys(s), keys(s + 1), f);
}

LBounds linearBounds(const SceneContext& ctx, PrimRef ref, TimeRange range) {
  const PrimKeys keys = ctx.keys(ref);
  const Geometry& g = *keys.geometry;
  if (g.numSteps() == 1) return widen(LBounds(keys(0)));
  // The ends interpolate keys s0, s0 + 1 and s1, s1 + 1 (as boxAt); the keys
  // inside the range lie among s0 .. s1 + 1. Each key box is made once.
  const TimeRange r = g.timeRange();
  uint32_t s0, s1;
  float f0, f1;
  g.segmentAt(std::clamp(range.lo, r.lo, r.hi), s0, f0);
  g.segmentAt(std::clamp(range.hi, r.lo, r.hi), s1, f1);
  const BoxPack k00 = keyBox(keys, s0), k01 = keyBox(keys, s0 + 1);
  const BoxPack k10 = s1 == s0 ? k00 : (s1 == s0 + 1 ? k01 : keyBox(keys, s1));
  const BoxPack k11 = s1 == s0 ? k01 : keyBox(keys, s1 + 1);
  BoxPack b0 = lerp(k00, k01, f0), b1 = lerp(k10, k11, f1);
  if (range.hi > range.lo) {
    P4 pushLower = P4::set1(0.0f), pushUpper = P4::set1(0.0f);
    for (uint32_t k = s0; k <= s1 + 1; ++k) {
      const float tk = keys.stepTimes[k];
      if (!(tk < range.hi)) break;  // step times grow with k
      if (!(tk > range.lo)) continue;
      const BoxPack line = lerp(b0, b1, (tk - range.lo) / range.size());
      const BoxPack key = k == s0       ? k00
                           : k == s0 + 1 ? k01
                           : k == s1     ? k10
                           : k == s1 + 1 ? k11
                                         : keyBox(keys, k);
      pushLower = minOf(pushLower, key.lower - line.lower);
      pushUpper = maxOf(pushUpper, key.upper - line.upper);
    }
    b0 = {b0.lower + pushLower, b0.upper + pushUpper};
    b1 = {b1.lower + pushLower, b1.upper + pushUpper};
  }
  return widened(b0, b1);
}

LBounds toGlobal(const LBounds& local, TimeRange range) {
  if (range.lo == 0.0f && range.hi == 1.0f) return local;
  const float inv = 1.0f / range.size();
  auto extrapolate = [&](Vec3f a, Vec3f b, float t) { return a + (b - a) * ((t - range.lo) * inv); };
  LBounds g;
  g.b0 = {extrapolate(local.b0.lower, local.b1.lower, 0.0f), extrapolate(local.b0.upper, local.b1.upper, 0.0f)};
  g.b1 = {extrapolate(local.b0.lower, local.b1.lower, 1.0f), extrapolate(local.b0.upper, local.b1.upper, 1.0f)};
  return widen(g);
}

Box3f transformBox(const Affine3f& xfm, const Box3f& box) {
  if (box.empty()) return box;
  Box3f r;
  for (int c = 0; c < 8; ++c) {
    const Vec3f p{(c & 1) ? box.upper.x : box.lower.x, (c & 2) ? box.upper.y : box.lower.y,
                  (c & 4) ? box.upper.z : box.lower.z};
    r.extend(xfm.xfmPoint(p));
  }
  return widen(r);
}

uint32_t activeSegments(const SceneContext& ctx, PrimRef ref, TimeRange range) {
  const Geometry& g = ctx.geometry(ref.geomID);
  if (g.numSteps() <= 1) return 1;
  const TimeRange r = g.timeRange();
  const float a = std::max(range.lo, r.lo), b = std::min(range.hi, r.hi);
  if (b < a) return 1;  // not alive in the range: bounded by its nearest pose
  const float scale = float(g.numSteps() - 1) / r.size();
  const int first = std::clamp(int(std::floor((a - r.lo) * scale)), 0, int(g.numSteps()) - 2);
  const int last = std::clamp(int(std::ceil((b - r.lo) * scale)) - 1, first, int(g.numSteps()) - 2);
  return uint32_t(last - first + 1);
}

}  // namespace mbrt::detail
