// N-wide BVH nodes, structure of arrays (STBVH §4: nodes store linear bounds
// per child). Motion nodes store the box at t=0 (b0) and d = b1 - b0 per
// plane, so the box at ray time t is one FMA per plane: lo = fma(t, dlo, lo0).
// Static nodes (the `frozen` kind) store one box. Empty lanes have
// lower = +inf, upper = -inf, d = 0: every slab test misses them.
//
// Spatial-temporal nodes (STBVH §3.3) also give each lane a time range
// [t0, t1): `times` indexes the tree's LaneTimes table (kNoTimes: every lane
// serves the whole range of the node). The index lives in the node's
// alignment padding, so plain nodes cost no byte more.
#pragma once

#include <cstdint>
#include <cstring>

#include "bvh/simd.h"
#include "mbrt/math.h"

namespace mbrt::detail {

template <int N, bool Motion>
struct alignas(32) WideNode {
  static constexpr int kPlanes = Motion ? 4 : 2;  // lo, hi[, dlo, dhi]
  // plane[axis][k][lane]: k = 0 lower, 1 upper, 2 lower delta, 3 upper delta.
  float plane[3][kPlanes][N];
  uint32_t child[N];  // inner: node index; leaf: first reference
  uint8_t count[N];   // 0: inner node (or empty lane); > 0: leaf size
  uint32_t times;     // LaneTimes index, or kNoTimes
  static constexpr uint32_t kNoTimes = 0xFFFFFFFFu;

  void clear() {
    std::memset(static_cast<void*>(this), 0, sizeof(*this));
    for (int a = 0; a < 3; ++a)
      for (int l = 0; l < N; ++l) {
        plane[a][0][l] = kInf;
        plane[a][1][l] = -kInf;
      }
    times = kNoTimes;
  }
  bool hasTimes() const { return times != kNoTimes; }
  bool isLeaf(int lane) const { return count[lane] != 0; }
  // Only clear() makes +inf planes (stored bounds are finite; extrapolated
  // ones may be inverted at t = 0, so lower > upper does not mean empty).
  bool isEmpty(int lane) const { return count[lane] == 0 && plane[0][0][lane] == kInf; }

  // Global linear bounds (box at t=0 and t=1); static nodes keep b0.
  void setBounds(int lane, const LBounds& b) {
    for (int a = 0; a < 3; ++a) {
      plane[a][0][lane] = b.b0.lower[a];
      plane[a][1][lane] = b.b0.upper[a];
      if constexpr (Motion) {
        plane[a][2][lane] = b.b1.lower[a] - b.b0.lower[a];
        plane[a][3][lane] = b.b1.upper[a] - b.b0.upper[a];
      }
    }
  }
  // The linear bounds as stored (b1 = b0 + d).
  LBounds bounds(int lane) const {
    LBounds b;
    for (int a = 0; a < 3; ++a) {
      b.b0.lower[a] = plane[a][0][lane];
      b.b0.upper[a] = plane[a][1][lane];
      b.b1.lower[a] = Motion ? plane[a][0][lane] + plane[a][2][lane] : plane[a][0][lane];
      b.b1.upper[a] = Motion ? plane[a][1][lane] + plane[a][3][lane] : plane[a][1][lane];
    }
    return b;
  }
  // The box the node test sees at tree time t (same arithmetic).
  Box3f boxAt(int lane, float t) const {
    Box3f b;
    for (int a = 0; a < 3; ++a) {
      if constexpr (Motion) {
        b.lower[a] = madd(t, plane[a][2][lane], plane[a][0][lane]);
        b.upper[a] = madd(t, plane[a][3][lane], plane[a][1][lane]);
      } else {
        b.lower[a] = plane[a][0][lane];
        b.upper[a] = plane[a][1][lane];
      }
    }
    return b;
  }
};

// Per-lane time ranges of a spatial-temporal node, in the tree's time
// parameter: lane i serves t0[i] <= t < t1[i]. A range ending at the end of
// the tree's range stores the next float above it, so that end is included;
// an inner boundary belongs to the lane on its right only. Empty lanes have
// t0 = +inf, t1 = -inf.
template <int N>
struct alignas(32) LaneTimes {
  float t0[N];
  float t1[N];
};

}  // namespace mbrt::detail
