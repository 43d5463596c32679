// Spatial splits (SBVH, Stich et al. 2009; MSBVH §2): binning along each
// axis of a node box where every reference is *clipped* to each bin it
// overlaps, and the split itself with reference unsplitting. Knows
// references and boxes, never trees.
//
// References carry a `region`: the box cut out of space by the spatial split
// planes above them (infinite at first). A spatial split divides a
// reference's region into two halves, so the regions of the references of
// one primitive always tile space, whatever the primitive looks like: this
// is what lets a structure bound each reference's *piece* (the primitive
// clipped to its region) at another time and still cover the whole
// primitive (see src/msbvh/key_bounds.h).
#pragma once

#include <span>
#include <vector>

#include "core/prim_ref.h"
#include "mbrt/math.h"

namespace mbrt::detail {

struct SplitRef {
  Box3f box;     // bounds of the primitive's piece in `region` at the build time
  Box3f region;  // the part of space this reference stands for
  PrimRef prim{0, 0};
};

// Tight bounds of a primitive's part inside `box` at the build time; empty
// when none of it is there.
struct RefClipper {
  virtual ~RefClipper() = default;
  virtual Box3f clip(PrimRef prim, const Box3f& box) const = 0;
  // The bounds of the primitive's parts inside `box` between consecutive
  // planes x[axis] = planes[k] (increasing): planes.size() + 1 pieces, each
  // containing what clip() of its slab gives (binning bounds: they may be
  // looser). By default one clip() per slab; clippers that can split a
  // primitive plane by plane do so.
  virtual void chop(PrimRef prim, const Box3f& box, int axis, std::span<const float> planes, Box3f* pieces) const;
};

// Splits one reference at the plane x[axis] = pos into two pieces; false
// (outputs untouched) when one side would be empty.
bool splitReference(const SplitRef& ref, int axis, float pos, const RefClipper& clipper, SplitRef& left,
                    SplitRef& right);

struct SpatialSplit {
  int axis = -1;
  float pos = 0.0f;
  float cost = kInf;  // areaL*countL + areaR*countR (half-areas, unnormalised)
  size_t leftCount = 0, rightCount = 0;
  bool valid() const { return axis >= 0; }
};

// Best spatial split of the references over `nodeBox` with `numBins` bins
// per axis (at most 256), on every axis or only on `onlyAxis` (>= 0);
// invalid when no plane separates anything. Large nodes bin in parallel
// over fixed blocks (exact merges: the result does not depend on the thread
// count).
SpatialSplit findSpatialSplit(std::span<const SplitRef> refs, const Box3f& nodeBox, int numBins,
                              const RefClipper& clipper, int onlyAxis = -1);

// What applySpatialSplit makes: the sides, and its working list. Kept by
// the caller from one split to the next, so that no split allocates once
// the vectors have grown.
struct SpatialSplitScratch {
  struct Straddler {
    const SplitRef* ref;
    SplitRef l, r;
    bool split;
  };
  std::vector<SplitRef> left, right;
  std::vector<Straddler> straddlers;
};

// Performs the split: references wholly on one side go there; straddling
// ones are split, or kept whole on one side where that costs less
// (unsplitting). `out.left` and `out.right` get the sides (emptied first).
// Returns the number of references added.
size_t applySpatialSplit(std::span<const SplitRef> refs, const SpatialSplit& split, const RefClipper& clipper,
                         SpatialSplitScratch& out);

}  // namespace mbrt::detail
