// The accumulators of the object binner (binned_sah.cpp), per reference
// type: the bounds a bin grows by (linear bounds of a BuildRef, the box of
// a SplitRef), the binning key and the SAH weight of a reference. Binning
// extends a bin per axis for every reference, the hottest loop of a build:
// each corner is one 4-lane min/max (the fourth lane is ignored). min/max
// are exact, so the corners are those of LBounds::extend / Box3f::extend,
// and merges in any order give the same bits.
#pragma once

#include "bvh/heuristics/binned_sah.h"
#include "core/simd.h"

namespace mbrt::detail::binning {

using P4 = Pack<4>;

inline Box3f toBox(P4 lo, P4 hi) {
  alignas(16) float l[4], h[4];
  lo.store(l);
  hi.store(h);
  return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
}

// Half-area of the box [lo, hi] (Box3f::halfArea by the same operations).
inline float halfArea(P4 lo, P4 hi) {
  if (lessMask(hi, lo) & 0x7) return 0.0f;  // Box3f::empty
  alignas(16) float d[4];
  (hi - lo).store(d);
  return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

// Linear bounds (BuildRef).
struct LinearAcc {
  P4 lo0 = P4::set1(kInf), hi0 = P4::set1(-kInf), lo1 = P4::set1(kInf), hi1 = P4::set1(-kInf);

  void extend(const LBounds& b) {
    static_assert(sizeof(LBounds) == 12 * sizeof(float));
    const float* f = &b.b0.lower.x;  // b0.lower, b0.upper, b1.lower, b1.upper
    lo0 = vmin(lo0, P4::loadu(f));
    hi0 = vmax(hi0, P4::loadu(f + 3));
    lo1 = vmin(lo1, P4::loadu(f + 6));
    hi1 = vmax(hi1, P4::load3(f + 9));  // the last corner: no read past the bounds
  }
  void extend(const LinearAcc& o) {
    lo0 = vmin(lo0, o.lo0);
    hi0 = vmax(hi0, o.hi0);
    lo1 = vmin(lo1, o.lo1);
    hi1 = vmax(hi1, o.hi1);
  }
  LBounds get() const { return {toBox(lo0, hi0), toBox(lo1, hi1)}; }
  // mbsahArea(get()), by the same operations.
  float area() const {
    const P4 half = P4::set1(0.5f);
    return halfArea(lo0 * half + lo1 * half, hi0 * half + hi1 * half);
  }
};

// A static box (SplitRef).
struct BoxAcc {
  P4 lo = P4::set1(kInf), hi = P4::set1(-kInf);

  void extend(const Box3f& b) {
    static_assert(sizeof(Box3f) == 6 * sizeof(float));
    lo = vmin(lo, P4::loadu(&b.lower.x));
    hi = vmax(hi, P4::load3(&b.upper.x));
  }
  void extend(const BoxAcc& o) {
    lo = vmin(lo, o.lo);
    hi = vmax(hi, o.hi);
  }
  Box3f get() const { return toBox(lo, hi); }
  float area() const { return halfArea(lo, hi); }  // Box3f::halfArea
};

template <class Ref>
struct RefTraits;

template <>
struct RefTraits<BuildRef> {
  using Bounds = LBounds;
  using Acc = LinearAcc;
  static const LBounds& bounds(const BuildRef& r) { return r.bounds; }
  static uint64_t weight(const BuildRef& r) { return r.active; }  // MBSAH |X|_s
  // BuildRef::centroid() in three lanes, by the same operations: the box
  // at the centre time (lerp with t = 0.5, whose 1 - t is 0.5 too), then
  // its centre. Bit-identical to the scalar key.
  static P4 key(const BuildRef& r) {
    const float* f = &r.bounds.b0.lower.x;
    const P4 half = P4::set1(0.5f);
    const P4 lo = P4::loadu(f) * half + P4::loadu(f + 6) * half;
    const P4 hi = P4::loadu(f + 3) * half + P4::load3(f + 9) * half;
    return (lo + hi) * half;
  }
  static float scalarKey(const BuildRef& r, int axis) { return r.centroid()[axis]; }
  static bool tieLess(const BuildRef& a, const BuildRef& b) {
    if (a.prim.geomID != b.prim.geomID) return a.prim.geomID < b.prim.geomID;
    return a.prim.primID < b.prim.primID;
  }
};

template <>
struct RefTraits<SplitRef> {
  using Bounds = Box3f;
  using Acc = BoxAcc;
  static const Box3f& bounds(const SplitRef& r) { return r.box; }
  static uint64_t weight(const SplitRef&) { return 1; }
  // Box3f::center() in three lanes, by the same operations.
  static P4 key(const SplitRef& r) {
    return (P4::loadu(&r.box.lower.x) + P4::load3(&r.box.upper.x)) * P4::set1(0.5f);
  }
  static float scalarKey(const SplitRef& r, int axis) { return r.box.center()[axis]; }
  // Pieces of one primitive differ in their regions, which tile space.
  static bool tieLess(const SplitRef& a, const SplitRef& b) {
    if (a.prim.geomID != b.prim.geomID) return a.prim.geomID < b.prim.geomID;
    if (a.prim.primID != b.prim.primID) return a.prim.primID < b.prim.primID;
    for (int k = 0; k < 3; ++k)
      if (a.region.lower[k] != b.region.lower[k]) return a.region.lower[k] < b.region.lower[k];
    return false;
  }
};

template <class Ref>
using Summary = RefSummary<typename RefTraits<Ref>::Bounds>;

struct CentroidBounds {
  P4 lo = P4::set1(kInf), hi = P4::set1(-kInf);
  void extend(P4 c) {
    lo = vmin(lo, c);
    hi = vmax(hi, c);
  }
  void extend(const CentroidBounds& o) {
    lo = vmin(lo, o.lo);
    hi = vmax(hi, o.hi);
  }
  Box3f get() const { return toBox(lo, hi); }
};

template <class Ref>
struct Bin {
  typename RefTraits<Ref>::Acc bounds;
  uint64_t active = 0;
  uint32_t count = 0;
};

// A summary as it is accumulated, one reference at a time.
template <class Ref>
struct InfoAcc {
  typename RefTraits<Ref>::Acc bounds;
  CentroidBounds centroids;
  uint64_t active = 0;

  void add(const Ref& r, P4 key) {
    bounds.extend(RefTraits<Ref>::bounds(r));
    centroids.extend(key);
    active += RefTraits<Ref>::weight(r);
  }
  void add(const InfoAcc& o) {
    bounds.extend(o.bounds);
    centroids.extend(o.centroids);
    active += o.active;
  }
  Summary<Ref> get() const { return {bounds.get(), centroids.get(), active}; }
};

}  // namespace mbrt::detail::binning
