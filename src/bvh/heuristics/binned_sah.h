// Object splits by binned SAH (Wald 2007, as used by STBVH §3.3), with the
// MBSAH cost of STBVH §3.2: the half-area of the box at the centre time times
// the number of active primitive segments. Knows references, not trees.
#pragma once

#include <algorithm>
#include <span>

#include "bvh/build/build_ref.h"

namespace mbrt::detail {

// MBSAH area of bounds local to a range: half-area of the box at its centre time.
inline float mbsahArea(const LBounds& b) { return b.at(0.5f).halfArea(); }

// What a node knows of its references before splitting.
struct RefSetInfo {
  LBounds bounds;     // merged linear bounds
  Box3f centroids;    // bounds of the binning keys
  uint64_t active = 0;  // sum of active segment counts
};
RefSetInfo summarize(std::span<const BuildRef> refs);

struct ObjectSplit {
  int axis = -1;          // -1: no valid split (all keys coincide)
  int bin = 0;            // references in bins [0, bin) go left
  float cost = kInf;      // areaL*countL + areaR*countR (unnormalised), active segments
  float origin = 0.0f;    // binning transform of the axis
  float scale = 0.0f;
  int numBins = 0;

  bool valid() const { return axis >= 0; }
  int binAt(float key) const { return std::clamp(int((key - origin) * scale), 0, numBins - 1); }
  int binOf(const BuildRef& r) const { return binAt(r.centroid()[axis]); }
};

// Best split over all three axes; ties go to the lower axis, then lower bin.
// Bins per axis: 8 + 10% of the references, at most `maxBins` (Embree
// scales them likewise, from 4 + 5%).
ObjectSplit findObjectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int maxBins,
                            TimeRange range);

// Moves the left side to the front; returns its size. `sides` gets the
// summaries of the left and right references (as summarize gives them).
// `along0` and `along1` (empty, or as long as `refs`) get the same moves.
size_t partitionObject(std::span<BuildRef> refs, const ObjectSplit& split, RefSetInfo sides[2],
                       std::span<BuildRef> along0 = {}, std::span<BuildRef> along1 = {});

// Splits at the median binning key along `axis` (ties by ids), for when
// binning cannot separate the references; returns count / 2, and `sides`
// as partitionObject does.
size_t partitionMedian(std::span<BuildRef> refs, int axis, RefSetInfo sides[2]);

}  // namespace mbrt::detail
