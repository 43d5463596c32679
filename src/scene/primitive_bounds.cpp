#include "scene/primitive_bounds.h"

#include <cmath>
#include <cstring>

#if defined(__SSE2__) || defined(_M_X64)
#include <immintrin.h>
#define MBRT_BOUNDS_SSE 1
#endif

namespace mbrt::detail {
namespace {

// Relative widening: 2^-19 (a few float ulp, covering one lerp or fma each
// in vertex interpolation and in the node-box evaluation).
constexpr float kRelativeSlack = 1.0f / (1 << 19);

float slack(float a, float b) {
  return std::max(std::fabs(a), std::fabs(b)) * kRelativeSlack + 1e-30f;
}

// A Vec3f in the lanes of one SSE register (the fourth lane unused), or the
// Vec3f itself without SSE. Each operation rounds as its Vec3f twin, and
// min / max pick as std::min / std::max do (the first operand on ties and
// NaN), so the bounds are bit-identical either way.
struct Lanes {
#ifdef MBRT_BOUNDS_SSE
  __m128 v;
  // x, y, z from memory of any alignment (no read past z).
  static Lanes load(const void* p) {
    const float* f = static_cast<const float*>(p);
    return {_mm_movelh_ps(_mm_loadl_pi(_mm_setzero_ps(), static_cast<const __m64*>(p)), _mm_load_ss(f + 2))};
  }
  static Lanes of(const Vec3f& p) { return load(&p.x); }
  static Lanes all(float s) { return {_mm_set1_ps(s)}; }
  friend Lanes operator+(Lanes a, Lanes b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Lanes operator-(Lanes a, Lanes b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Lanes operator*(Lanes a, Lanes b) { return {_mm_mul_ps(a.v, b.v)}; }
  // _mm_min_ps(x, y) is x < y ? x : y, std::min(a, b) is b < a ? b : a.
  friend Lanes min(Lanes a, Lanes b) { return {_mm_min_ps(b.v, a.v)}; }
  friend Lanes max(Lanes a, Lanes b) { return {_mm_max_ps(b.v, a.v)}; }
  friend Lanes abs(Lanes a) { return {_mm_andnot_ps(_mm_set1_ps(-0.0f), a.v)}; }
#else
  Vec3f v;
  static Lanes load(const void* p) {
    Vec3f xyz;
    std::memcpy(&xyz, p, sizeof(Vec3f));
    return {xyz};
  }
  static Lanes of(const Vec3f& p) { return {p}; }
  static Lanes all(float s) { return {Vec3f(s)}; }
  Vec3f vec() const { return v; }
  friend Lanes operator+(Lanes a, Lanes b) { return {a.v + b.v}; }
  friend Lanes operator-(Lanes a, Lanes b) { return {a.v - b.v}; }
  friend Lanes operator*(Lanes a, Lanes b) { return {a.v * b.v}; }
  friend Lanes min(Lanes a, Lanes b) { return {mbrt::min(a.v, b.v)}; }
  friend Lanes max(Lanes a, Lanes b) { return {mbrt::max(a.v, b.v)}; }
  friend Lanes abs(Lanes a) { return {{std::fabs(a.v.x), std::fabs(a.v.y), std::fabs(a.v.z)}}; }
#endif
};

struct BoxLanes {
  Lanes lower, upper;
  static BoxLanes of(const Box3f& b) { return {Lanes::of(b.lower), Lanes::of(b.upper)}; }
};

BoxLanes lerp(const BoxLanes& a, const BoxLanes& b, float t) {
  const Lanes u = Lanes::all(1.0f - t), w = Lanes::all(t);
  return {a.lower * u + b.lower * w, a.upper * u + b.upper * w};
}

// PrimKeys::operator() in lanes.
inline BoxLanes keyBox(const PrimKeys& keys, uint32_t key) {
  if (keys.instance) return BoxLanes::of(keys.instance[key]);
  const VertexBuffer& vb = keys.geometry->vertices(key);
  auto vertex = [&](uint32_t i) {
    return Lanes::load(static_cast<const char*>(vb.data) + i * vb.stride);
  };
  const Lanes a = vertex(keys.v[0]), b = vertex(keys.v[1]), c = vertex(keys.v[2]);
  const Lanes r = Lanes::all(keys.radius);
  return {min(min(a, b), c) - r, max(max(a, b), c) + r};
}

// The LBounds b0 -> b1; with SSE its 12 floats go out as three shuffled
// registers (no 3-float stores read back piecewise).
LBounds packed(const BoxLanes& b0, const BoxLanes& b1) {
#ifdef MBRT_BOUNDS_SSE
  static_assert(sizeof(LBounds) == 12 * sizeof(float));
  const __m128 l0 = b0.lower.v, u0 = b0.upper.v, l1 = b1.lower.v, u1 = b1.upper.v;
  const __m128 l0zu0x = _mm_shuffle_ps(l0, u0, _MM_SHUFFLE(0, 0, 2, 2));
  const __m128 l1zu1x = _mm_shuffle_ps(l1, u1, _MM_SHUFFLE(0, 0, 2, 2));
  float f[12];
  _mm_storeu_ps(f, _mm_shuffle_ps(l0, l0zu0x, _MM_SHUFFLE(2, 0, 1, 0)));      // l0.xyz u0.x
  _mm_storeu_ps(f + 4, _mm_shuffle_ps(u0, l1, _MM_SHUFFLE(1, 0, 2, 1)));      // u0.yz l1.xy
  _mm_storeu_ps(f + 8, _mm_shuffle_ps(l1zu1x, u1, _MM_SHUFFLE(2, 1, 2, 0)));  // l1.z u1.xyz
  LBounds out;
  std::memcpy(&out, f, sizeof(out));
  return out;
#else
  return {{b0.lower.vec(), b0.upper.vec()}, {b1.lower.vec(), b1.upper.vec()}};
#endif
}

// widen(LBounds) of the linear bounds b0 -> b1.
LBounds widened(const BoxLanes& b0, const BoxLanes& b1) {
  // One slack per axis for both ends: that of the largest magnitude among
  // the four corners (the slack grows with the magnitude), in three lanes.
  const Lanes m = max(max(abs(b0.lower), abs(b0.upper)), max(abs(b1.lower), abs(b1.upper)));
  const Lanes s = m * Lanes::all(kRelativeSlack) + Lanes::all(1e-30f);
  return packed({b0.lower - s, b0.upper + s}, {b1.lower - s, b1.upper + s});
}

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

LBounds widen(const LBounds& bounds) { return widened(BoxLanes::of(bounds.b0), BoxLanes::of(bounds.b1)); }

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
  const BoxLanes k00 = keyBox(keys, s0), k01 = keyBox(keys, s0 + 1);
  const BoxLanes k10 = s1 == s0 ? k00 : (s1 == s0 + 1 ? k01 : keyBox(keys, s1));
  const BoxLanes k11 = s1 == s0 ? k01 : keyBox(keys, s1 + 1);
  BoxLanes b0 = lerp(k00, k01, f0), b1 = lerp(k10, k11, f1);
  if (range.hi > range.lo) {
    Lanes pushLower = Lanes::all(0.0f), pushUpper = Lanes::all(0.0f);
    for (uint32_t k = s0; k <= s1 + 1; ++k) {
      const float tk = keys.stepTimes[k];
      if (!(tk < range.hi)) break;  // step times grow with k
      if (!(tk > range.lo)) continue;
      const BoxLanes line = lerp(b0, b1, (tk - range.lo) / range.size());
      const BoxLanes key = k == s0       ? k00
                           : k == s0 + 1 ? k01
                           : k == s1     ? k10
                           : k == s1 + 1 ? k11
                                         : keyBox(keys, k);
      pushLower = min(pushLower, key.lower - line.lower);
      pushUpper = max(pushUpper, key.upper - line.upper);
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
