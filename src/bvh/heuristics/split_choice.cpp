#include "bvh/heuristics/split_choice.h"

#include <algorithm>

#include "bvh/heuristics/temporal_split.h"

namespace mbrt::detail {

// Leaf cost C_I*A*|X|_s against C_T*A + split cost (MBSAH, STBVH §3.2);
// with leaf blocks, |X|_s counts blocks (leafBlocks, binned_sah.h).
Decision SplitChooser::choose(std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth,
                              const TemporalHalves& tried) {
  Decision d;
  const float area = mbsahArea(info.bounds);
  const size_t count = refs.size();
  if (count <= 1 && !s_.temporal) return d;
  const ObjectSplit split = objectSplit(refs, info, depth);
  const float leafCost = area * leafBlocks(info.active, count, s_.leafBlock);
  float best = split.cost;  // unnormalised, kInf when invalid
  // Temporal split: tried when the object split is poor (θ), chosen when
  // it wins even with the penalty λ for the references it duplicates.
  TemporalSplit temporal;
  float time = 0.0f;
  if (s_.temporal && depth < s_.maxBinnedDepth && !(split.cost < kTemporalTry * leafCost) &&
      temporalSplitTime(refs, range, *s_.temporal, time)) {
    temporalHalves(refs, range, time, tried, d);
    temporal = temporalSplitCost(d.halves.refs[0], d.halves.refs[1], range, time, s_.leafBlock);
    if (kTemporalPenalty * temporal.cost < best) best = temporal.cost;
    else temporal = TemporalSplit();
  }
  // Leaf or split (MBSAH); a temporal split also pays its penalty λ_leaf
  // for the references it duplicates.
  const float splitCost =
      s_.traversalCost * area + (temporal.valid() ? s_.temporalLeafPenalty * temporal.cost : best);
  if (count <= size_t(s_.maxLeafSize) && !(splitCost < leafCost)) {
    Decision leaf;
    leaf.split = split;
    return leaf;
  }
  if (temporal.valid()) {
    d.kind = Decision::Temporal;
    std::copy_n(temporal.sides, 2, d.sides);
    return d;
  }
  if (count <= 1) return Decision();
  // The rejected temporal split goes to the children in their order: they
  // have the same range, and most try the same split again.
  // Halves that cannot follow the references' moves are freed now.
  d.kind = Decision::Object;
  if (!d.halves.alignedWith(refs)) dropHalves(d);
  d.mid = partition(refs, info, split, d.sides, d.halves.refs);
  if (!d.halves.alignedWith(refs)) dropHalves(d);  // the median moved them
  return d;
}

void SplitChooser::dropHalves(Decision& d) {
  d.halves = TemporalHalves();
  for (OwnedRefs& made : d.made) made = OwnedRefs();
}

ObjectSplit SplitChooser::objectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int depth) const {
  if (depth >= s_.maxBinnedDepth || refs.size() <= 1) return ObjectSplit();
  return findObjectSplit(refs, info, adaptiveObjectBins(s_.numBins, refs.size()), s_.leafBlock);
}

size_t SplitChooser::partition(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split,
                               RefSetInfo sides[2]) {
  std::span<BuildRef> none[2];
  return partition(refs, info, split, sides, none);
}

// `along` (empty, or as long as `refs`) gets the same moves; it is emptied
// where the median's moves cannot be followed.
size_t SplitChooser::partition(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split,
                               RefSetInfo sides[2], std::span<BuildRef> (&along)[2]) {
  size_t mid = split.valid() ? partitionObject(refs, split, sides, along[0], along[1]) : 0;
  if (mid == 0 || mid == refs.size()) {  // partitionObject moved nothing
    mid = partitionMedian(refs, info.centroids.largestAxis(), sides);
    along[0] = along[1] = {};
  }
  return mid;
}

// The halves of the temporal split at `time`: those an ancestor made for the
// same references when it has them, else made here (Fig. 4 bounds).
void SplitChooser::temporalHalves(std::span<BuildRef> refs, TimeRange range, float time,
                                  const TemporalHalves& tried, Decision& d) {
  if (s_.reuseTriedTemporalSplits && tried.time == time && tried.alignedWith(refs)) {
    d.halves = tried;
    return;
  }
  std::vector<BuildRef> halves[2];
  {
    ScopedCharge scratch(budget_, 2 * refs.size() * sizeof(BuildRef), "the temporal split references");
    splitTemporal(refs, range, time, *s_.temporal, halves[0], halves[1]);
  }
  d.halves.time = time;
  for (int h = 0; h < 2; ++h) {
    d.made[h] = OwnedRefs(budget_, std::move(halves[h]));
    d.halves.refs[h] = d.made[h].span();
  }
}

}  // namespace mbrt::detail
