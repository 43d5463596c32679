#include "kd/kd_motion.h"

#include <cmath>

#include "scene/primitive_bounds.h"

namespace mbrt::detail {
namespace {

// Slack of the crossing times (the key boxes are already widened in space).
constexpr float kTimeSlack = 1.0f / (1 << 18);

}  // namespace

KdPaths KdPaths::fromContext(const SceneContext& ctx, std::span<const PrimRef> prims) {
  KdPaths p;
  p.range_.reserve(prims.size());
  p.offset_.reserve(prims.size() + 1);
  for (const PrimRef& ref : prims) {
    const Geometry& g = ctx.geometry(ref.geomID);
    const uint32_t n = g.numSteps();
    for (uint32_t k = 0; k < n; ++k) p.keys_.push_back(widen(ctx.keyBox(ref, k)));
    p.offset_.push_back(uint32_t(p.keys_.size()));
    p.range_.push_back(g.timeRange());
  }
  return p;
}

KdPaths KdPaths::fromBoxes(std::span<const Box3f> boxes) {
  KdPaths p;
  p.keys_.assign(boxes.begin(), boxes.end());
  p.offset_.resize(boxes.size() + 1);
  for (size_t i = 0; i <= boxes.size(); ++i) p.offset_[i] = uint32_t(i);
  p.range_.assign(boxes.size(), TimeRange{0.0f, 1.0f});
  return p;
}

Box3f KdPaths::boxAt(uint32_t i, float t) const {
  const uint32_t n = numKeys(i);
  if (n == 1) return key(i, 0);
  const TimeRange r = range_[i];
  const float local = (std::clamp(t, r.lo, r.hi) - r.lo) * float(n - 1) / r.size();
  const uint32_t k = uint32_t(std::clamp(std::floor(local), 0.0f, float(n - 2)));
  return lerp(key(i, k), key(i, k + 1), local - float(k));
}

Box3f KdPaths::hull(uint32_t i) const {
  Box3f b;
  for (uint32_t k = 0; k < numKeys(i); ++k) b.extend(key(i, k));
  return b;
}

int KdPaths::sideWindows(uint32_t i, int axis, float pos, bool left, float t0, float t1, TimeRange* out) const {
  int n = 0;
  // Strictly on the side; a box flat in the plane counts as left. A box
  // only touching the plane is found from the other side, whose cell the
  // traversal enters around the same ray distance.
  auto inside = [&](const Box3f& b) {
    return left ? (b.lower[axis] < pos || (b.lower[axis] == pos && b.upper[axis] == pos)) : b.upper[axis] > pos;
  };
  forEachPiece(i, t0, t1, [&](float sa, float sb, const Box3f& A, const Box3f& B) {
    const bool inA = inside(A), inB = inside(B);
    float lo, hi;
    if (inA && inB) {
      lo = sa, hi = sb;
    } else if (!inA && !inB) {
      return;
    } else {
      // f(t) < 0 on the wanted side, linear over the piece.
      const float fa = left ? A.lower[axis] - pos : pos - A.upper[axis];
      const float fb = left ? B.lower[axis] - pos : pos - B.upper[axis];
      const float f = fa - fb;
      const float tc = f != 0.0f ? sa + (sb - sa) * std::clamp(fa / f, 0.0f, 1.0f) : (inA ? sb : sa);
      if (inA) {
        lo = sa, hi = std::min(sb, tc + kTimeSlack);
      } else {
        lo = std::max(sa, tc - kTimeSlack), hi = sb;
      }
    }
    // Pieces come in time order: extend the last window or open a new one.
    if (n > 0 && (lo <= out[n - 1].hi + kKdWindowGap || n == kKdMaxWindows)) {
      out[n - 1].hi = std::max(out[n - 1].hi, hi);
    } else {
      out[n++] = {lo, hi};
    }
  });
  return n;
}

TimeRange KdPaths::sideInterval(uint32_t i, int axis, float pos, bool left, float t0, float t1) const {
  TimeRange w[kKdMaxWindows];
  const int n = sideWindows(i, axis, pos, left, t0, t1, w);
  return n == 0 ? TimeRange{kInf, -kInf} : TimeRange{w[0].lo, w[n - 1].hi};
}

}  // namespace mbrt::detail
