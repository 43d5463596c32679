// Temporal splits (STBVH paper §3.2-3.3): split a node's time range in two
// at a step boundary, each half getting its own references with linear
// bounds recomputed for the half (Fig. 4). Knows references, not trees.
//
// The split time is the centre of the range snapped to the nearest step
// boundary, strictly inside the range, of the reference with the most active
// segments. The cost is the MBSAH of the two halves relative to the node's
// range: (A_L N_L T_L + A_R N_R T_R) / T, in the units of ObjectSplit::cost.
#pragma once

#include <span>
#include <vector>

#include "bvh/heuristics/binned_sah.h"
#include "bvh/build/build_ref.h"

namespace mbrt::detail {

// The paper's constants: temporal splits are tried only when the best object
// split costs at least kTemporalTry times the leaf cost, and chosen only when
// kTemporalPenalty times their cost still beats the object split.
inline constexpr float kTemporalTry = 0.5f;      // θ
inline constexpr float kTemporalPenalty = 1.25f;  // λ

// What temporal splits need to know of the primitives (the kind provides it).
class TemporalSource {
 public:
  virtual ~TemporalSource() = default;
  // The primitive's geometry time range and its motion segments (0: static),
  // the same for every primitive of a geometry.
  // Step k sits at range.lo + range.size() * k / segments (Geometry::stepTime).
  virtual TimeRange stepRange(PrimRef prim, uint32_t& segments) const = 0;
  // The reference for `range` (tree parameter): bounds recomputed over it
  // (local to it, as BuildRef::bounds), active segments in it. False when the primitive is not alive
  // anywhere in the half-open range.
  virtual bool remake(const BuildRef& ref, TimeRange range, BuildRef& out) const = 0;
};

struct TemporalSplit {
  float time = 0.0f;
  float cost = kInf;  // unnormalised, as ObjectSplit::cost
  RefSetInfo sides[2];    // summaries of the halves' references (for their nodes)
  bool valid() const { return cost < kInf; }
};

// The split time for `refs` over `range`, or false when temporal splits do
// not apply (the range is not longer than the shortest segment of the
// references, or the chosen reference has no step strictly inside it).
bool temporalSplitTime(std::span<const BuildRef> refs, TimeRange range, const TemporalSource& source, float& time);

// Cost (MBSAH, §3.2) of the split at `time` whose halves' references are
// `left` and `right` (splitTemporal), each half charged in leaf blocks of
// `leafBlock` as an object split's sides are (leafBlocks, binned_sah.h;
// charged per reference, the halves lose to every per-block object split).
// The builder makes the halves once and keeps them when the split is taken
// (each half's bounds are recomputed only once, Fig. 4).
TemporalSplit temporalSplitCost(std::span<const BuildRef> left, std::span<const BuildRef> right, TimeRange range,
                                float time, int leafBlock = 1);

// splitTemporal, then temporalSplitCost.
TemporalSplit evaluateTemporalSplit(std::span<const BuildRef> refs, TimeRange range, float time,
                                    const TemporalSource& source);

// The references of both halves [range.lo, time) and [time, range.hi), in
// the order of `refs`; references not alive in a half are left out of it.
void splitTemporal(std::span<const BuildRef> refs, TimeRange range, float time, const TemporalSource& source,
                   std::vector<BuildRef>& left, std::vector<BuildRef>& right);

}  // namespace mbrt::detail
