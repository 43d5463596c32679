// N-wide motion-blur BVH nodes with quantised child bounds (included by
// wide_node.h). Each lane keeps linear bounds (STBVH §4: the box at t = 0
// and t = 1, "global", extrapolated beyond the lane's own time range) as 8-bit
// steps of a per-node grid, as compressed static BVH nodes do (Ylitie et al.
// 2017; Embree's QBVH): 192 bytes for 8 lanes instead of 448 with floats.
//
// Per axis, the grid's origin moves linearly with time like the children:
// at time t it is origin + t * drift, with steps step0 at t = 0 and step1 at
// t = 1. Lane plane k at time t is
//   origin + t * drift + q[k@0] * step0 * (1 - t) + q[k@1] * step1 * t,
// a linear function of t, so the node test stays a few FMAs per plane and no
// per-node time rescaling. Because the grid moves with the node, the steps
// measure the children's spread inside the node, not the node's travel.
//
// Encoding rounds every plane outwards and keeps a margin for the float
// evaluation above (motion_node.cpp), so the decoded box contains the lane's
// linear bounds at every t in [0, 1].
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace mbrt::detail {

template <int N>
struct alignas(nodeAlignment(N)) WideNode<N, true> {
  static_assert(N <= 8, "one byte of lane bits");
  // Per axis: the grid's origin at t = 0, its drift to t = 1, its steps.
  float origin[3], drift[3], step0[3], step1[3];
  // q[axis][k][lane]: k = 0 lower at t = 0, 1 upper at t = 0, 2 lower at t = 1, 3 upper at t = 1.
  uint8_t q[3][4][N];
  uint32_t child[N];  // by count: node index, first reference, or primID (wide_node.h)
  uint8_t count[N];   // kInnerLane, leaf size, kInlineLeaf or kEmptyLane
  uint32_t times;     // LaneTimes index, or kNoTimes
  uint32_t leafGeom;  // geometry of the kInlineLeaf lanes
  static constexpr uint32_t kNoTimes = 0xFFFFFFFFu;

  void clear() {
    std::memset(static_cast<void*>(this), 0, sizeof(*this));
    std::memset(count, kEmptyLane, sizeof(count));
    times = kNoTimes;
  }
  bool hasTimes() const { return times != kNoTimes; }
  bool isLeaf(int lane) const { return count[lane] != kInnerLane && count[lane] != kEmptyLane; }
  bool isEmpty(int lane) const { return count[lane] == kEmptyLane; }
  // Bit per lane that is not empty: the node test ignores the levels of empty
  // lanes, which stand in for a present lane's (motion_node.cpp).
  uint32_t occupiedLanes() const {
    static_assert(offsetof(WideNode, count) + 8 <= sizeof(WideNode));
    return bytesDifferMask<N>(count, kEmptyLane);
  }

  // Sets the bounds of every lane at once (the grid depends on all of them);
  // lanes without a bit in `lanesPresent` become empty (motion_node.cpp).
  void encode(const LBounds (&lanes)[N], uint32_t lanesPresent);

  // Per axis, the grid at time t (omt = 1 - t): its origin and the weights
  // of the t = 0 and t = 1 steps.
  void gridAt(float t, float omt, float (&at)[3], float (&w0)[3], float (&w1)[3]) const {
    for (int a = 0; a < 3; ++a) {
      at[a] = madd(t, drift[a], origin[a]);
      w0[a] = step0[a] * omt;
      w1[a] = step1[a] * t;
    }
  }
  // Per axis, the terms of a slab distance (plane - org) * rdir at time t:
  // A = (origin at t - org) * rdir, B0 = w0 * rdir, B1 = w1 * rdir, so
  // that lane plane k is at distance A + q[k@0] * B0 + q[k@1] * B1
  // (traverse.h). Entries [3] are scratch. Unless the ray is `tame`, a term
  // that overflowed with a finite rdir becomes NaN, which the slab test
  // ignores (the axis then culls nothing): A alone may overflow where the
  // distance it sums to is finite. Tame rays cannot overflow: with
  // coordinates within 2^60 (scene coordinates within 1e18, extrapolated
  // ends within some 2^67) and |rdir| < 2^56, every term is below 2^125.
  void distanceTerms(float t, float omt, const float (&org)[4], const float (&rdir)[4], bool tame, float (&A)[4],
                     float (&B0)[4], float (&B1)[4]) const {
    using P = Pack<4>;
    static_assert(offsetof(WideNode, step1) + 4 * sizeof(float) <= sizeof(WideNode));
    const P o = P::loadu(origin), d = P::loadu(drift), s0 = P::loadu(step0);
    // Lane 3 of each load is the next field's first float; step1's would be
    // level bytes (perhaps a denormal, slow to multiply), so it is cleared.
    const P s1 = clearLastLane(P::loadu(step1));
    const P tt = P::set1(t), r = P::load(rdir);
    P a = (fmadd(tt, d, o) - P::load(org)) * r;  // gridAt's origin at t, then the distance
    P b0 = (s0 * P::set1(omt)) * r;
    P b1 = (s1 * tt) * r;
    if (!tame) {
      const P inf = P::set1(kInf);
      const P finiteR = lessLanes(abs(r), inf);
      const auto nanIfOverflowed = [&](P x) { return x | (finiteR & equalLanes(abs(x), inf)); };  // all ones: NaN
      a = nanIfOverflowed(a);
      b0 = nanIfOverflowed(b0);
      b1 = nanIfOverflowed(b1);
    }
    a.store(A);
    b0.store(B0);
    b1.store(B1);
  }
  // The decoded box at tree time t, in float: the planes the node test's
  // distances (distanceTerms) measure, evaluated as positions.
  Box3f boxAt(int lane, float t) const {
    float at[3], w0[3], w1[3];
    gridAt(t, 1.0f - t, at, w0, w1);
    Box3f b;
    for (int a = 0; a < 3; ++a) {
      b.lower[a] = madd(float(q[a][2][lane]), w1[a], madd(float(q[a][0][lane]), w0[a], at[a]));
      b.upper[a] = madd(float(q[a][3][lane]), w1[a], madd(float(q[a][1][lane]), w0[a], at[a]));
    }
    return b;
  }
  // The linear bounds as decoded at t = 0 and t = 1 (for statistics).
  LBounds bounds(int lane) const { return LBounds(boxAt(lane, 0.0f), boxAt(lane, 1.0f)); }
};

}  // namespace mbrt::detail
