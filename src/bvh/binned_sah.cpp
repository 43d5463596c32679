#include "bvh/binned_sah.h"

#include "bvh/simd.h"

#include <algorithm>
#include <cstring>
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

// A bin's linear bounds. Binning extends a bin per axis for every
// reference, the hottest loop of the build: with SSE the four corners are
// one min/max each (the fourth lane is ignored). min/max are exact, so the
// result equals LBounds::extend.
#ifdef MBRT_BVH_SSE
struct BinBounds {
  __m128 lo0 = _mm_set1_ps(kInf), hi0 = _mm_set1_ps(-kInf), lo1 = _mm_set1_ps(kInf), hi1 = _mm_set1_ps(-kInf);

  void extend(const LBounds& b) {
    static_assert(sizeof(LBounds) == 12 * sizeof(float));
    const float* f = &b.b0.lower.x;  // b0.lower, b0.upper, b1.lower, b1.upper
    lo0 = _mm_min_ps(lo0, _mm_loadu_ps(f));
    hi0 = _mm_max_ps(hi0, _mm_loadu_ps(f + 3));
    lo1 = _mm_min_ps(lo1, _mm_loadu_ps(f + 6));
    hi1 = _mm_max_ps(hi1, load3(f + 9));  // the last corner: no read past the bounds
  }
  void extend(const BinBounds& o) {
    lo0 = _mm_min_ps(lo0, o.lo0);
    hi0 = _mm_max_ps(hi0, o.hi0);
    lo1 = _mm_min_ps(lo1, o.lo1);
    hi1 = _mm_max_ps(hi1, o.hi1);
  }
  LBounds get() const {
    alignas(16) float v[4][4];
    _mm_store_ps(v[0], lo0);
    _mm_store_ps(v[1], hi0);
    _mm_store_ps(v[2], lo1);
    _mm_store_ps(v[3], hi1);
    LBounds b;
    b.b0.lower = {v[0][0], v[0][1], v[0][2]};
    b.b0.upper = {v[1][0], v[1][1], v[1][2]};
    b.b1.lower = {v[2][0], v[2][1], v[2][2]};
    b.b1.upper = {v[3][0], v[3][1], v[3][2]};
    return b;
  }

 private:
  static __m128 load3(const float* f) {
    double x_y;  // the two floats x, y as one 8-byte load (f need not be 8-byte aligned)
    std::memcpy(&x_y, f, sizeof x_y);
    const __m128 xy = _mm_castpd_ps(_mm_set_sd(x_y));
    return _mm_movelh_ps(xy, _mm_load_ss(f + 2));
  }
};
#else
struct BinBounds {
  LBounds b;
  void extend(const LBounds& o) { b.extend(o); }
  void extend(const BinBounds& o) { b.extend(o.b); }
  LBounds get() const { return b; }
};
#endif

struct Bin {
  BinBounds bounds;
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
    // Empty bins change nothing: they repeat the costs of their neighbour
    // (small nodes leave most of the bins empty).
    float cost = 0.0f, prim = 0.0f;
    for (int i = numBins - 1; i > 0; --i) {
      if (ab[i].count != 0 || i + 1 == numBins) {
        acc.extend(ab[i].bounds.get());
        active += ab[i].active;
        rightCount += ab[i].count;
        cost = mbsahArea(acc) * float(active);
        prim = mbsahArea(acc) * leafBlocks(rightCount, leafBlock);
      }
      rightCost[size_t(i)] = cost;
      rightPrim[size_t(i)] = prim;
    }
    // Sweep from the left: split between bin i-1 and bin i.
    acc = LBounds();
    active = 0;
    size_t leftCount = 0;
    // A split after an empty bin repeats the split before it (same sides,
    // same cost; the first one is kept), so it is not evaluated again.
    for (int i = 1; i < numBins; ++i) {
      if (ab[i - 1].count == 0) continue;
      acc.extend(ab[i - 1].bounds.get());
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
