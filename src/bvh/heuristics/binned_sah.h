// Object splits by binned SAH (Wald 2007, as used by STBVH §3.3), the one
// object binner of the SAH builders. Written once over the reference type:
// - BuildRef (the BVH family): linear bounds, with the MBSAH cost of STBVH
//   §3.2, the half-area of the box at the centre time times the number of
//   active primitive segments;
// - SplitRef (the MSBVH's SBVH topology, MSBVH §3): static boxes at the
//   build time, the plain SAH (half-area times references).
// Knows references, not trees.
#pragma once

#include <algorithm>
#include <span>

#include "bvh/build/build_ref.h"
#include "bvh/heuristics/spatial_split.h"

namespace mbrt::detail {

// MBSAH area of bounds local to a range: half-area of the box at its centre time.
inline float mbsahArea(const LBounds& b) { return b.at(0.5f).halfArea(); }

// What a node knows of its references before splitting: merged bounds
// (LBounds for BuildRefs, Box3f for SplitRefs), the bounds of the binning
// keys and the summed weights (active segments; 1 per SplitRef).
template <class Bounds>
struct RefSummary {
  Bounds bounds;
  Box3f centroids;
  uint64_t active = 0;
};
using RefSetInfo = RefSummary<LBounds>;  // BuildRefs
using BoxSetInfo = RefSummary<Box3f>;    // SplitRefs

// Parallel over fixed blocks above 32768 references; exact merges, so the
// result never depends on the thread count.
RefSetInfo summarize(std::span<const BuildRef> refs);
BoxSetInfo summarize(std::span<const SplitRef> refs);

struct ObjectSplit {
  int axis = -1;          // -1: no valid split (all keys coincide)
  int bin = 0;            // references in bins [0, bin) go left
  float cost = kInf;      // areaL*weightL + areaR*weightR (unnormalised)
  float origin = 0.0f;    // binning transform of the axis
  float scale = 0.0f;
  int numBins = 0;

  bool valid() const { return axis >= 0; }
  int binAt(float key) const { return std::clamp(int((key - origin) * scale), 0, numBins - 1); }
};

// Bins per axis for a node of `count` references in the BVH family: 8 +
// 10% of the references, at most `maxBins` (Embree scales them likewise,
// from 4 + 5%: docs/stbvh.md).
int adaptiveObjectBins(int maxBins, size_t count);

// The SAH's intersection cost of `count` references of summed weight
// `weight` (their active segments, MBSAH) in leaf blocks of `leafBlock`: a
// block is tested at once, so it costs as one reference of the mean weight
// (Embree's BVH builders charge ceil(n / 4) for Triangle4 leaves,
// GeneralBVHBuilder's logBlockSize). leafBlock 1: the weight itself. With
// weight == count (a static tree) this is exactly ceil(count / leafBlock).
inline float leafBlocks(uint64_t weight, uint64_t count, int leafBlock) {
  if (leafBlock <= 1 || count == 0) return float(weight);
  const float blocks = float((count + uint64_t(leafBlock) - 1) / uint64_t(leafBlock));
  return blocks * (float(weight) / float(count));
}

// Best split over all three axes with `numBins` bins each (at most 256);
// ties go to the lower axis, then lower bin; each side costs its area times
// leafBlocks(its weight, leafBlock). `sides`, when given, gets the bounds of
// both sides of the split found.
ObjectSplit findObjectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int numBins,
                            int leafBlock = 1);
ObjectSplit findObjectSplit(std::span<const SplitRef> refs, const BoxSetInfo& info, int numBins,
                            Box3f* sides = nullptr);

// Moves the left side to the front (Hoare partition); returns its size.
// `sides` gets the summaries of the left and right references (as summarize
// gives them). `along0` and `along1` (empty, or as long as `refs`) get the
// same moves. From 32768 references on, in parallel over fixed blocks with
// the same moves (the result never depends on the node size or threads).
size_t partitionObject(std::span<BuildRef> refs, const ObjectSplit& split, RefSetInfo sides[2],
                       std::span<BuildRef> along0 = {}, std::span<BuildRef> along1 = {});
size_t partitionObject(std::span<SplitRef> refs, const ObjectSplit& split, BoxSetInfo sides[2]);

// Splits at the median binning key along `axis` (ties by ids, then by
// region), for when binning cannot separate the references; returns
// count / 2, and `sides` as partitionObject does.
size_t partitionMedian(std::span<BuildRef> refs, int axis, RefSetInfo sides[2]);
size_t partitionMedian(std::span<SplitRef> refs, int axis, BoxSetInfo sides[2]);

}  // namespace mbrt::detail
