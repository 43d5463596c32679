#include "geometry/primitive_bounds.h"

#include <cmath>

namespace mbrt::detail {
namespace {

// Relative widening: 2^-19 (a few float ulp, covering one lerp or fma each
// in vertex interpolation and in the node-box evaluation).
constexpr float kRelativeSlack = 1.0f / (1 << 19);

float slack(float a, float b) {
  return std::max(std::fabs(a), std::fabs(b)) * kRelativeSlack + 1e-30f;
}

Vec3f absVec(Vec3f v) { return {std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}; }

}  // namespace

Box3f widen(const Box3f& box) {
  if (box.empty()) return box;
  Box3f r = box;
  for (int a = 0; a < 3; ++a) {
    const float s = slack(box.lower[a], box.upper[a]);
    r.lower[a] -= s;
    r.upper[a] += s;
  }
  return r;
}

LBounds widen(const LBounds& bounds) {
  // One slack per axis for both ends: that of the largest magnitude among
  // the four corners (the slack grows with the magnitude), in three lanes.
  const Vec3f m = max(max(absVec(bounds.b0.lower), absVec(bounds.b0.upper)),
                      max(absVec(bounds.b1.lower), absVec(bounds.b1.upper)));
  const Vec3f s = m * kRelativeSlack + Vec3f(1e-30f);
  return {{bounds.b0.lower - s, bounds.b0.upper + s}, {bounds.b1.lower - s, bounds.b1.upper + s}};
}

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
  const Geometry& g = ctx.geometry(ref.geomID);
  const PrimKeys keys = ctx.keys(ref);
  if (g.numSteps() == 1) return widen(LBounds(keys(0)));
  // The ends interpolate keys s0, s0 + 1 and s1, s1 + 1 (as boxAt); the keys
  // inside the range lie among s0 .. s1 + 1. Each key box is made once.
  const TimeRange r = g.timeRange();
  uint32_t s0, s1;
  float f0, f1;
  g.segmentAt(std::clamp(range.lo, r.lo, r.hi), s0, f0);
  g.segmentAt(std::clamp(range.hi, r.lo, r.hi), s1, f1);
  const Box3f k00 = keys(s0), k01 = keys(s0 + 1);
  const Box3f k10 = s1 == s0 ? k00 : (s1 == s0 + 1 ? k01 : keys(s1));
  const Box3f k11 = s1 == s0 ? k01 : keys(s1 + 1);
  LBounds lb(lerp(k00, k01, f0), lerp(k10, k11, f1));
  if (range.hi > range.lo) {
    Vec3f pushLower(0.0f), pushUpper(0.0f);
    for (uint32_t k = s0; k <= s1 + 1; ++k) {
      const float tk = g.stepTime(k);
      if (!(tk > range.lo && tk < range.hi)) continue;
      const Box3f line = lb.at((tk - range.lo) / range.size());
      const Box3f key = k == s0 ? k00 : k == s0 + 1 ? k01 : k == s1 ? k10 : k == s1 + 1 ? k11 : keys(k);
      pushLower = min(pushLower, key.lower - line.lower);
      pushUpper = max(pushUpper, key.upper - line.upper);
    }
    lb.b0.lower += pushLower;
    lb.b1.lower += pushLower;
    lb.b0.upper += pushUpper;
    lb.b1.upper += pushUpper;
  }
  return widen(lb);
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

uint32_t totalSegments(const SceneContext& ctx, PrimRef ref) {
  return std::max(1u, ctx.geometry(ref.geomID).numSteps() - 1);
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
