// The SAH cost of docs/design.md, one formula for every kind (C_T = C_I = 1):
//   ( sum_inner A(n) T(n) + sum_leaves A(l) T(l) seg(l) ) / A(scene)
// A: surface area averaged over 8 times spread over the node's time range;
// T: length of that range; seg: active primitive segments (MBSAH, STBVH §3.2).
// This header holds the sums and the time-averaged area that every kind
// (BVHs, kd-trees) adds its nodes with; A(scene) is scene/scene_area.h.
#pragma once

#include <cstddef>

#include "mbrt/accel_stats.h"
#include "mbrt/math.h"

namespace mbrt::detail {

// Surface area of lerp(b0, b1, t) averaged over t = lo + (hi - lo) * k / 7,
// k = 0..7 (t in the bounds' own parameter).
inline double meanSurfaceArea(const LBounds& b, float lo = 0.0f, float hi = 1.0f) {
  double sum = 0.0;
  for (int k = 0; k < 8; ++k) sum += double(b.at(lo + (hi - lo) * float(k) / 7.0f).area());
  return sum / 8.0;
}

// Sums of one or more trees, turned into AccelStats by `fill`.
struct SahSums {
  double inner = 0.0, leaves = 0.0;
  size_t innerNodes = 0, leafNodes = 0, references = 0, maxDepth = 0, bytes = 0;

  void fill(AccelStats& s, double sceneArea) const {
    s.innerNodes = innerNodes;
    s.leafNodes = leafNodes;
    s.references = references;
    s.maxDepth = maxDepth;
    s.bytes = bytes;
    s.sahCost = sceneArea > 0.0 ? (inner + leaves) / sceneArea : 0.0;
  }
};

}  // namespace mbrt::detail
