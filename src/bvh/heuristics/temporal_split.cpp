#include "bvh/heuristics/temporal_split.h"

#include <algorithm>
#include <cmath>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "bvh/heuristics/binned_sah.h"
#include "core/huge_pages.h"

namespace mbrt::detail {
namespace {

constexpr size_t kParallelRefs = 16384;
constexpr size_t kGrain = 4096;

float stepAt(TimeRange r, uint32_t segments, uint32_t k) { return r.lo + r.size() * float(k) / float(segments); }

// The half's reference; when the recomputed bounds are unusable, the
// parent's hull (conservative over the half too) stands in.
bool remakeRef(const BuildRef& ref, TimeRange half, const TemporalSource& source, BuildRef& out) {
  if (!source.remake(ref, half, out)) return false;
  if (!isUsable(out.bounds)) {
    const Box3f hull = ref.bounds.hull();
    out.bounds = LBounds(hull, hull);
  }
  return true;
}

}  // namespace

bool temporalSplitTime(std::span<const BuildRef> refs, TimeRange range, const TemporalSource& source, float& time) {
  // The steps are those of the reference with the most active segments,
  // ties to the least (geomID, primID). Steps are per geometry, so only the
  // geometry of that reference matters: each run of one geometry's
  // references gives its most active segments, and the runs are compared by
  // (active, geomID), so a geometry that comes back in a later run counts
  // there too. The source is asked once per run, not per reference.
  float shortest = kInf;
  bool found = false;
  uint32_t mostActive = 0, mostGeom = 0, mostSegments = 0;
  TimeRange mostRange;
  for (size_t i = 0; i < refs.size();) {
    const uint32_t geom = refs[i].prim.geomID;
    uint32_t segments = 0;
    const TimeRange steps = source.stepRange(refs[i].prim, segments);
    uint32_t active = 0;
    for (; i < refs.size() && refs[i].prim.geomID == geom; ++i) active = std::max(active, refs[i].active);
    if (segments == 0) continue;  // static: no steps to split at
    shortest = std::min(shortest, steps.size() / float(segments));
    if (!found || active > mostActive || (active == mostActive && geom < mostGeom)) {
      found = true;
      mostActive = active;
      mostGeom = geom;
      mostSegments = segments;
      mostRange = steps;
    }
  }
  if (!found || !(range.size() > shortest)) return false;
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
                                float time, int leafBlock) {
  const TimeRange halves[2] = {{range.lo, time}, {time, range.hi}};
  const std::span<const BuildRef> refs[2] = {left, right};
  TemporalSplit split;
  split.time = time;
  float cost = 0.0f;
  for (int i = 0; i < 2; ++i) {
    const RefSetInfo& info = split.sides[i] = summarize(refs[i]);
    if (info.active == 0) continue;
    const float p = mbsahArea(info.bounds) * (halves[i].size() / range.size());
    cost += p * leafBlocks(info.active, refs[i].size(), leafBlock);
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
      reserveOnHugePages(out, refs.size());
      for (const BuildRef& r : refs) {
        BuildRef made;
        if (remakeRef(r, halves[i], source, made)) out.push_back(made);
      }
    } else {
      out.clear();
      resizeOnHugePages(out, refs.size());
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
