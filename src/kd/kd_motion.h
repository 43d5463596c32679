// Primitive boxes as piecewise-linear paths over time, for kd-tree builds:
// per primitive its key boxes at evenly spaced key times over its time range
// (one key for a static primitive), clamped outside that range. The exact
// times at which a box side crosses a plane follow from each linear piece.
#pragma once

#include <algorithm>
#include <span>
#include <vector>

#include "scene/scene_context.h"

namespace mbrt::detail {

inline constexpr int kKdMaxWindows = 4;
inline constexpr float kKdWindowGap = 1.0f / 32;

// A primitive (index into the paths) during a closed time interval.
struct KdBuildRef {
  uint32_t prim;
  float t0, t1;
};

class KdPaths {
 public:
  // Widened key boxes of the context's primitives (geometry step times).
  static KdPaths fromContext(const SceneContext& ctx, std::span<const PrimRef> prims);
  // Static boxes, one key each (the static kd-tree).
  static KdPaths fromBoxes(std::span<const Box3f> boxes);

  size_t size() const { return range_.size(); }
  size_t bytes() const {
    return keys_.size() * sizeof(Box3f) + offset_.size() * sizeof(uint32_t) + range_.size() * sizeof(TimeRange);
  }
  uint32_t numKeys(uint32_t i) const { return offset_[i + 1] - offset_[i]; }
  TimeRange range(uint32_t i) const { return range_[i]; }
  const Box3f& key(uint32_t i, uint32_t k) const { return keys_[offset_[i] + k]; }
  float keyTime(uint32_t i, uint32_t k) const {
    const uint32_t n = numKeys(i);
    return n == 1 ? range_[i].lo : range_[i].lo + range_[i].size() * float(k) / float(n - 1);
  }
  // The box at time t (clamped to the primitive's range).
  Box3f boxAt(uint32_t i, float t) const;
  // The union of the keys: the box over the whole shutter.
  Box3f hull(uint32_t i) const;
  // The time at which the primitive is placed: 0.5, or the nearest time it
  // is alive.
  float placementTime(uint32_t i) const { return std::clamp(0.5f, range_[i].lo, range_[i].hi); }

  // Calls fn(sa, sb, boxA, boxB) for the linear pieces of the path over
  // [t0, t1] (t0 <= t1); a point interval gives one piece with sa == sb.
  template <class Fn>
  void forEachPiece(uint32_t i, float t0, float t1, const Fn& fn) const {
    const uint32_t n = numKeys(i);
    if (n == 1 || !(t1 > t0)) {
      const Box3f b = boxAt(i, t0);
      fn(t0, t1 > t0 ? t1 : t0, b, n == 1 ? b : boxAt(i, t1 > t0 ? t1 : t0));
      return;
    }
    const TimeRange r = range_[i];
    if (t0 < r.lo) fn(t0, std::min(t1, r.lo), key(i, 0), key(i, 0));
    for (uint32_t k = 0; k + 1 < n; ++k) {
      const float ka = keyTime(i, k), kb = keyTime(i, k + 1);
      const float a = std::max(t0, ka), b = std::min(t1, kb);
      if (!(a < b)) continue;
      const float inv = 1.0f / (kb - ka);
      const Box3f& A = key(i, k);
      const Box3f& B = key(i, k + 1);
      fn(a, b, a == ka ? A : lerp(A, B, (a - ka) * inv), b == kb ? B : lerp(A, B, (b - ka) * inv));
    }
    if (t1 > r.hi) fn(std::max(t0, r.hi), t1, key(i, n - 1), key(i, n - 1));
  }

  // Conservative hull of the times in [t0, t1] at which the box reaches the
  // side of the plane `pos` on `axis`: lower <= pos (left) or upper >= pos
  // (right). Empty (lo > hi) when it never does.
  TimeRange sideInterval(uint32_t i, int axis, float pos, bool left, float t0, float t1) const;

  // The same times as up to kKdMaxWindows disjoint, increasing intervals
  // (a primitive that leaves the side and comes back); windows closer than
  // kKdWindowGap are merged, and the last one absorbs any beyond the limit.
  // Returns the count.
  int sideWindows(uint32_t i, int axis, float pos, bool left, float t0, float t1, TimeRange* out) const;

 private:
  std::vector<Box3f> keys_;
  std::vector<uint32_t> offset_{0};
  std::vector<TimeRange> range_;
};

}  // namespace mbrt::detail
