#include "bvh/binned_sah.h"

#include <algorithm>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace mbrt::detail {

namespace {

// Large nodes reduce in parallel over fixed blocks. The merges (min/max and
// integer sums) are exact, so the result never depends on the thread count.
constexpr size_t kParallelRefs = 32768;
constexpr size_t kGrain = 8192;

RefSetInfo summarizeSerial(std::span<const BuildRef> refs) {
  RefSetInfo info;
  for (const BuildRef& r : refs) {
    info.bounds.extend(r.bounds);
    info.centroids.extend(r.centroid());
    info.active += r.active;
  }
  return info;
}

}  // namespace

RefSetInfo summarize(std::span<const BuildRef> refs) {
  if (refs.size() < kParallelRefs) return summarizeSerial(refs);
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, refs.size(), kGrain), RefSetInfo(),
      [&](const tbb::blocked_range<size_t>& r, RefSetInfo acc) {
        const RefSetInfo part = summarizeSerial(refs.subspan(r.begin(), r.size()));
        acc.bounds.extend(part.bounds);
        acc.centroids.extend(part.centroids);
        acc.active += part.active;
        return acc;
      },
      [](RefSetInfo a, const RefSetInfo& b) {
        a.bounds.extend(b.bounds);
        a.centroids.extend(b.centroids);
        a.active += b.active;
        return a;
      });
}

namespace {

struct Bin {
  LBounds bounds;
  uint64_t active = 0;
  uint32_t count = 0;
};

}  // namespace

ObjectSplit findObjectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int numBins,
                            TimeRange /*range: bounds are local to it*/, int leafBlock) {
  // Binning transform per axis; axes where all keys coincide are skipped.
  ObjectSplit axes[3];
  bool any = false;
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = info.centroids.lower[axis], extent = info.centroids.upper[axis] - lo;
    if (!(extent > 0.0f)) continue;
    axes[axis].axis = axis;
    axes[axis].origin = lo;
    axes[axis].scale = float(numBins) * (1.0f - 1e-6f) / extent;
    axes[axis].numBins = numBins;
    any = true;
  }
  ObjectSplit best;
  if (!any) return best;
  // One pass over the references fills the bins of all three axes.
  const size_t nb = static_cast<size_t>(numBins);
  auto fill = [&](std::span<const BuildRef> part, std::vector<Bin>& bins) {
    for (const BuildRef& r : part) {
      const Vec3f c = r.centroid();
      for (int axis = 0; axis < 3; ++axis) {
        if (axes[axis].axis < 0) continue;
        Bin& b = bins[size_t(axis) * nb + size_t(axes[axis].binAt(c[axis]))];
        b.bounds.extend(r.bounds);
        b.active += r.active;
        ++b.count;
      }
    }
  };
  std::vector<Bin> bins(3 * nb);
  if (refs.size() < kParallelRefs) {
    fill(refs, bins);
  } else {
    bins = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<size_t>(0, refs.size(), kGrain), bins,
        [&](const tbb::blocked_range<size_t>& r, std::vector<Bin> acc) {
          fill(refs.subspan(r.begin(), r.size()), acc);
          return acc;
        },
        [](std::vector<Bin> a, const std::vector<Bin>& b) {
          for (size_t i = 0; i < a.size(); ++i) {
            a[i].bounds.extend(b[i].bounds);
            a[i].active += b[i].active;
            a[i].count += b[i].count;
          }
          return a;
        });
  }
  std::vector<float> rightCost(nb), rightPrim(nb);
  for (int axis = 0; axis < 3; ++axis) {
    if (axes[axis].axis < 0) continue;
    const Bin* ab = &bins[size_t(axis) * nb];
    // Sweep from the right: cost of bins [i, numBins).
    LBounds acc;
    uint64_t active = 0;
    size_t rightCount = 0;
    for (int i = numBins - 1; i > 0; --i) {
      acc.extend(ab[i].bounds);
      active += ab[i].active;
      rightCount += ab[i].count;
      rightCost[size_t(i)] = mbsahArea(acc) * float(active);
      rightPrim[size_t(i)] = mbsahArea(acc) * leafBlocks(rightCount, leafBlock);
    }
    // Sweep from the left: split between bin i-1 and bin i.
    acc = LBounds();
    active = 0;
    size_t leftCount = 0;
    for (int i = 1; i < numBins; ++i) {
      acc.extend(ab[i - 1].bounds);
      active += ab[i - 1].active;
      leftCount += ab[i - 1].count;
      if (leftCount == 0 || leftCount == refs.size()) continue;
      const float cost = mbsahArea(acc) * float(active) + rightCost[size_t(i)];
      if (cost < best.cost) {
        best = axes[axis];
        best.bin = i;
        best.cost = cost;
        best.primCost = mbsahArea(acc) * leafBlocks(leftCount, leafBlock) + rightPrim[size_t(i)];
      }
    }
  }
  return best;
}

size_t partitionObject(std::span<BuildRef> refs, const ObjectSplit& split) {
  auto mid = std::partition(refs.begin(), refs.end(), [&](const BuildRef& r) { return split.binOf(r) < split.bin; });
  return size_t(mid - refs.begin());
}

size_t partitionMedian(std::span<BuildRef> refs, int axis) {
  const size_t half = refs.size() / 2;
  std::nth_element(refs.begin(), refs.begin() + std::ptrdiff_t(half), refs.end(),
                   [axis](const BuildRef& a, const BuildRef& b) {
                     const float ca = a.centroid()[axis], cb = b.centroid()[axis];
                     if (ca != cb) return ca < cb;
                     if (a.prim.geomID != b.prim.geomID) return a.prim.geomID < b.prim.geomID;
                     return a.prim.primID < b.prim.primID;
                   });
  return half;
}

}  // namespace mbrt::detail
