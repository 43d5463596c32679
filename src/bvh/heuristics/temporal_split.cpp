#include "bvh/heuristics/temporal_split.h"

#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bvh/heuristics/binned_sah.h"

namespace mbrt::detail {
namespace {

constexpr size_t kParallelRefs = 16384;
constexpr size_t kGrain = 4096;

float stepAt(TimeRange r, uint32_t segments, uint32_t k) { return r.lo + r.size() * float(k) / float(segments); }

// The half's reference; when the recomputed bounds are unusable, the
// parent's hull (conservative over the half too) stands in.
bool remakeRef(const BuildRef& ref, TimeRange half, const TemporalSource& source, BuildRef& out) {
  if (!source.remake(ref, half, out)) return false;
  if (!usableBounds(out.bounds)) {
    const Box3f hull = ref.bounds.hull();
    out.bounds = LBounds(hull, hull);
  }
  return true;
}

}  // namespace

bool temporalSplitTime(std::span<const BuildRef> refs, TimeRange range, const TemporalSource& source, float& time) {
  float shortest = kInf;
  const BuildRef* most = nullptr;
  uint32_t mostSegments = 0;
  TimeRange mostRange;
  // Steps are per geometry and references come in runs of one geometry:
  // ask the source once per run.
  const BuildRef* run = nullptr;
  uint32_t segments = 0;
  TimeRange steps;
  for (const BuildRef& r : refs) {
    if (!run || r.prim.geomID != run->prim.geomID) {
      run = &r;
      steps = source.stepRange(r.prim, segments);
      if (segments > 0) shortest = std::min(shortest, steps.size() / float(segments));
    }
    if (segments == 0) continue;  // static: no steps to split at
    const bool better = !most || r.active > most->active ||
                        (r.active == most->active &&
                         (r.prim.geomID < most->prim.geomID ||
                          (r.prim.geomID == most->prim.geomID && r.prim.primID < most->prim.primID)));
    if (better) {
      most = &r;
      mostSegments = segments;
      mostRange = steps;
    }
  }
  if (!most || !(range.size() > shortest)) return false;
  // Nearest step to the centre, then moved strictly inside the range.
  const float c = range.center();
  int k = int(std::lround((c - mostRange.lo) / mostRange.size() * float(mostSegments)));
  k = std::clamp(k, 0, int(mostSegments));
  while (k < int(mostSegments) && stepAt(mostRange, mostSegments, uint32_t(k)) <= range.lo) ++k;
  while (k > 0 && stepAt(mostRange, mostSegments, uint32_t(k)) >= range.hi) --k;
  const float t = stepAt(mostRange, mostSegments, uint32_t(k));
  if (!(t > range.lo && t < range.hi)) return false;
  time = t;
  return true;
}

TemporalSplit temporalSplitCost(std::span<const BuildRef> left, std::span<const BuildRef> right, TimeRange range,
                                float time) {
  const TimeRange halves[2] = {{range.lo, time}, {time, range.hi}};
  const std::span<const BuildRef> refs[2] = {left, right};
  TemporalSplit split;
  split.time = time;
  float cost = 0.0f;
  for (int i = 0; i < 2; ++i) {
    const RefSetInfo& info = split.sides[i] = summarize(refs[i]);
    if (info.active == 0) continue;
    const float p = mbsahArea(info.bounds) * (halves[i].size() / range.size());
    cost += p * float(info.active);
  }
  split.cost = cost;
  return split;
}

TemporalSplit evaluateTemporalSplit(std::span<const BuildRef> refs, TimeRange range, float time,
                                    const TemporalSource& source) {
  std::vector<BuildRef> left, right;
  splitTemporal(refs, range, time, source, left, right);
  return temporalSplitCost(left, right, range, time);
}

void splitTemporal(std::span<const BuildRef> refs, TimeRange range, float time, const TemporalSource& source,
                   std::vector<BuildRef>& left, std::vector<BuildRef>& right) {
  const TimeRange halves[2] = {{range.lo, time}, {time, range.hi}};
  std::vector<BuildRef>* outs[2] = {&left, &right};
  for (int i = 0; i < 2; ++i) {
    std::vector<BuildRef>& out = *outs[i];
    if (refs.size() < kParallelRefs) {  // appended: no constructed-then-overwritten references
      out.clear();
      out.reserve(refs.size());
      for (const BuildRef& r : refs) {
        BuildRef made;
        if (remakeRef(r, halves[i], source, made)) out.push_back(made);
      }
    } else {
      out.resize(refs.size());
      size_t n = 0;
      std::vector<uint8_t> keep(refs.size(), 0);
      tbb::parallel_for(tbb::blocked_range<size_t>(0, refs.size(), kGrain), [&](const tbb::blocked_range<size_t>& r) {
        for (size_t k = r.begin(); k != r.end(); ++k) keep[k] = remakeRef(refs[k], halves[i], source, out[k]);
      });
      for (size_t k = 0; k < refs.size(); ++k)  // serial compaction keeps the order
        if (keep[k]) out[n++] = out[k];
      out.resize(n);
    }
  }
}

}  // namespace mbrt::detail
