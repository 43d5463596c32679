// N-wide BVH nodes, structure of arrays (STBVH §4: nodes store linear bounds
// per child). Motion nodes (motion_node.h) store them quantised on a grid
// that moves with the node; static nodes (the `frozen` kind) store one float
// box per lane, empty lanes with lower = +inf, upper = -inf, which every slab
// test misses.
//
// Spatial-temporal nodes (STBVH §3.3) also give each lane a time range
// [t0, t1): `times` indexes the tree's LaneTimes table (kNoTimes: every lane
// serves the whole range of the node).
//
// A lane's count says what it holds: an inner node (kInnerLane, child = node
// index), a leaf of count references (child = first reference in the tree's
// table), nothing (kEmptyLane), or one reference kept in the node itself
// (kInlineLeaf: child = its primID, its geometry the node's leafGeom), which
// saves the leaf test a dependent load from the reference table.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "core/simd.h"
#include "mbrt/math.h"

namespace mbrt::detail {

// Nodes of 4 or more lanes (whole cache lines: 128, 192 or 256 bytes) start
// on a cache line, so that a visit reads no line more than its size needs (an
// allocation aligned to 32 bytes only puts every other node across one more
// line). Narrower nodes keep 32 bytes: a 96-byte node would grow to 128.
inline constexpr size_t nodeAlignment(int N) { return N >= 4 ? 64 : 32; }

// What a lane's count byte holds besides a leaf size (1 to 64, accel.cpp).
inline constexpr uint8_t kInnerLane = 0, kInlineLeaf = 0xFE, kEmptyLane = 0xFF;

// Static nodes (Motion = false, the `frozen` kind): one float box per lane.
// Motion nodes are the specialisation in motion_node.h.
template <int N, bool Motion>
struct alignas(nodeAlignment(N)) WideNode {
  static_assert(!Motion, "motion nodes: motion_node.h");
  // plane[axis][k][lane]: k = 0 lower, 1 upper.
  float plane[3][2][N];
  uint32_t child[N];  // by count: node index, first reference, or primID
  uint8_t count[N];   // kInnerLane, leaf size, kInlineLeaf or kEmptyLane
  uint32_t times;     // LaneTimes index, or kNoTimes
  uint32_t leafGeom;  // geometry of the kInlineLeaf lanes
  static constexpr uint32_t kNoTimes = 0xFFFFFFFFu;

  void clear() {
    std::memset(static_cast<void*>(this), 0, sizeof(*this));
    for (int a = 0; a < 3; ++a)
      for (int l = 0; l < N; ++l) {
        plane[a][0][l] = kInf;
        plane[a][1][l] = -kInf;
      }
    std::memset(count, kEmptyLane, sizeof(count));
    times = kNoTimes;
  }
  bool hasTimes() const { return times != kNoTimes; }
  bool isLeaf(int lane) const { return count[lane] != kInnerLane && count[lane] != kEmptyLane; }
  bool isEmpty(int lane) const { return count[lane] == kEmptyLane; }

  // Sets the lanes with a bit in `present` to their boxes (b0; a static
  // node has no motion); a lane that gets a box stops being empty (its
  // caller says what it holds).
  void encode(const LBounds (&lanes)[N], uint32_t present) {
    for (int lane = 0; lane < N; ++lane)
      if (present >> lane & 1u) {
        if (count[lane] == kEmptyLane) count[lane] = kInnerLane;
        for (int a = 0; a < 3; ++a) {
          plane[a][0][lane] = lanes[lane].b0.lower[a];
          plane[a][1][lane] = lanes[lane].b0.upper[a];
        }
      }
  }
  LBounds bounds(int lane) const { return LBounds(boxAt(lane, 0.0f), boxAt(lane, 0.0f)); }
  Box3f boxAt(int lane, float) const {
    Box3f b;
    for (int a = 0; a < 3; ++a) {
      b.lower[a] = plane[a][0][lane];
      b.upper[a] = plane[a][1][lane];
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

#include "bvh/nodes/motion_node.h"
