#include "bvh/heuristics/binned_sah.h"

#include "core/simd.h"

#include <algorithm>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

namespace mbrt::detail {

namespace {

using P4 = Pack<4>;

// A bin's linear bounds. Binning extends a bin per axis for every
// reference, the hottest loop of the build: the four corners are one 4-lane
// min/max each (the fourth lane is ignored). min/max are exact, so the
// corners are those of LBounds::extend.
struct BinBounds {
  P4 lo0 = P4::set1(kInf), hi0 = P4::set1(-kInf), lo1 = P4::set1(kInf), hi1 = P4::set1(-kInf);

  void extend(const LBounds& b) {
    static_assert(sizeof(LBounds) == 12 * sizeof(float));
    const float* f = &b.b0.lower.x;  // b0.lower, b0.upper, b1.lower, b1.upper
    lo0 = vmin(lo0, P4::loadu(f));
    hi0 = vmax(hi0, P4::loadu(f + 3));
    lo1 = vmin(lo1, P4::loadu(f + 6));
    hi1 = vmax(hi1, P4::load3(f + 9));  // the last corner: no read past the bounds
  }
  void extend(const BinBounds& o) {
    lo0 = vmin(lo0, o.lo0);
    hi0 = vmax(hi0, o.hi0);
    lo1 = vmin(lo1, o.lo1);
    hi1 = vmax(hi1, o.hi1);
  }
  LBounds get() const { return {box(lo0, hi0), box(lo1, hi1)}; }
  // mbsahArea(get()), by the same operations.
  float mbsahArea() const {
    const P4 half = P4::set1(0.5f);
    const P4 lo = lo0 * half + lo1 * half;
    const P4 hi = hi0 * half + hi1 * half;
    if (lessMask(hi, lo) & 0x7) return 0.0f;  // Box3f::empty
    alignas(16) float d[4];
    (hi - lo).store(d);
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
  }

  static Box3f box(P4 lo, P4 hi) {
    alignas(16) float l[4], h[4];
    lo.store(l);
    hi.store(h);
    return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
  }
};

// BuildRef::centroid() in three lanes, by the same operations: the box at
// the centre time (lerp with t = 0.5, whose 1 - t is 0.5 too), then its
// centre. Bit-identical to the scalar key.
using Centroid = P4;
inline Centroid centroidOf(const BuildRef& r) {
  const float* f = &r.bounds.b0.lower.x;
  const P4 half = P4::set1(0.5f);
  const P4 lo = P4::loadu(f) * half + P4::loadu(f + 6) * half;
  const P4 hi = P4::loadu(f + 3) * half + P4::load3(f + 9) * half;
  return (lo + hi) * half;
}
inline float axisOf(Centroid c, int axis) { return c.lane(axis); }
struct CentroidBounds {
  P4 lo = P4::set1(kInf), hi = P4::set1(-kInf);
  void extend(Centroid c) {
    lo = vmin(lo, c);
    hi = vmax(hi, c);
  }
  Box3f get() const { return BinBounds::box(lo, hi); }
};

struct Bin {
  BinBounds bounds;
  uint64_t active = 0;
  uint32_t count = 0;
};

// Large nodes reduce in parallel over fixed blocks. The merges (min/max and
// integer sums) are exact, so the result never depends on the thread count.
constexpr size_t kParallelRefs = 32768;
constexpr size_t kGrain = 8192;

// A RefSetInfo as it is accumulated, one reference at a time.
struct InfoAcc {
  BinBounds bounds;
  CentroidBounds centroids;
  uint64_t active = 0;

  void add(const BuildRef& r, Centroid centroid) {
    bounds.extend(r.bounds);
    centroids.extend(centroid);
    active += r.active;
  }
  RefSetInfo get() const { return {bounds.get(), centroids.get(), active}; }
};

RefSetInfo summarizeSerial(std::span<const BuildRef> refs) {
  InfoAcc acc;
  for (const BuildRef& r : refs) acc.add(r, centroidOf(r));
  return acc.get();
}

void merge(RefSetInfo& a, const RefSetInfo& b) {
  a.bounds.extend(b.bounds);
  a.centroids.extend(b.centroids);
  a.active += b.active;
}

}  // namespace

RefSetInfo summarize(std::span<const BuildRef> refs) {
  if (refs.size() < kParallelRefs) return summarizeSerial(refs);
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, refs.size(), kGrain), RefSetInfo(),
      [&](const tbb::blocked_range<size_t>& r, RefSetInfo acc) {
        merge(acc, summarizeSerial(refs.subspan(r.begin(), r.size())));
        return acc;
      },
      [](RefSetInfo a, const RefSetInfo& b) {
        merge(a, b);
        return a;
      });
}

namespace {

// Bins per axis grow with the node, as in Embree's object binner, at most
// `maxBins`: small nodes fill and sweep few bins. Embree's 4 + 5% of the
// references cost `hair` 5% SAH and 8% more intersections per ray; 8 + 10%
// costs 2% and 3% and saves nearly as much binning (docs/stbvh.md).
constexpr int kMaxBins = 256;  // BuildOptions::sahBins at most (accel.cpp)
int adaptiveBins(int maxBins, size_t count) {
  return std::min({maxBins, kMaxBins, int(8.0f + 0.1f * float(std::min<size_t>(count, 1 << 20)))});
}

// Bins of the three axes, on the stack for the many small nodes.
class BinArray {
 public:
  explicit BinArray(size_t n) {
    if (n <= kInline) {
      data_ = std::uninitialized_value_construct_n(reinterpret_cast<Bin*>(inline_), n) - n;
    } else {
      heap_.resize(n);
      data_ = heap_.data();
    }
  }
  BinArray(const BinArray&) = delete;
  BinArray& operator=(const BinArray&) = delete;
  Bin* data() { return data_; }

 private:
  static constexpr size_t kInline = 3 * 32;
  alignas(Bin) unsigned char inline_[kInline * sizeof(Bin)];
  std::vector<Bin> heap_;
  Bin* data_;
};

// The bins of a reference on the three axes (ObjectSplit::binAt of each,
// by the same operations: truncation, then the clamp).
class BinMap {
 public:
  explicit BinMap(const ObjectSplit (&axes)[3])
      : axes_(axes),
        origin_(P4::of(axes[0].origin, axes[1].origin, axes[2].origin, 0.0f)),
        scale_(P4::of(axes[0].scale, axes[1].scale, axes[2].scale, 0.0f)) {}
  void binsOf(Centroid c, int (&bin)[3]) const {
    alignas(16) int32_t unclamped[4];
    ((c - origin_) * scale_).storeTruncated(unclamped);
    for (int a = 0; a < 3; ++a) bin[a] = std::clamp(unclamped[a], 0, std::max(axes_[a].numBins - 1, 0));
  }

 private:
  const ObjectSplit (&axes_)[3];
  P4 origin_, scale_;
};

// Fills the bins of the axes that have a transform (axes[a].axis >= 0).
void fillBins(std::span<const BuildRef> refs, const ObjectSplit (&axes)[3], size_t nb, Bin* bins) {
  const BinMap map(axes);
  for (const BuildRef& r : refs) {
    int bin[3];
    map.binsOf(centroidOf(r), bin);
    BinBounds bounds;  // loaded once for the three axes
    bounds.extend(r.bounds);
    for (int axis = 0; axis < 3; ++axis) {
      if (axes[axis].axis < 0) continue;
      Bin& b = bins[size_t(axis) * nb + size_t(bin[axis])];
      b.bounds.extend(bounds);
      b.active += r.active;
      ++b.count;
    }
  }
}

// Bins of a large node, reduced in parallel over fixed blocks (exact merges).
std::vector<Bin> fillBinsParallel(std::span<const BuildRef> refs, const ObjectSplit (&axes)[3], size_t nb) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, refs.size(), kGrain), std::vector<Bin>(3 * nb),
      [&](const tbb::blocked_range<size_t>& r, std::vector<Bin> acc) {
        fillBins(refs.subspan(r.begin(), r.size()), axes, nb, acc.data());
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

// Two references (a third of the nodes the SAH sees): on the first axis
// where their bins differ, each goes to its own side. The sweep would find
// exactly this split, with the same cost and tie-breaks, after filling and
// sweeping the bins.
ObjectSplit splitPair(std::span<const BuildRef> refs, const ObjectSplit (&axes)[3]) {
  const BinMap map(axes);
  int bins[2][3];
  map.binsOf(centroidOf(refs[0]), bins[0]);
  map.binsOf(centroidOf(refs[1]), bins[1]);
  for (int axis = 0; axis < 3; ++axis) {
    if (axes[axis].axis < 0 || bins[0][axis] == bins[1][axis]) continue;
    const int left = bins[0][axis] < bins[1][axis] ? 0 : 1;
    BinBounds lb, rb;
    lb.extend(refs[left].bounds);
    rb.extend(refs[1 - left].bounds);
    const float rightCost = rb.mbsahArea() * float(uint64_t(refs[1 - left].active));
    const float cost = lb.mbsahArea() * float(uint64_t(refs[left].active)) + rightCost;
    if (!(cost < kInf)) break;  // every axis has this cost: no split beats kInf
    ObjectSplit split = axes[axis];
    split.bin = bins[left][axis] + 1;
    split.cost = cost;
    return split;
  }
  return ObjectSplit();
}

// The best split of one axis's bins, if it beats `best`.
void sweepAxis(const Bin* ab, const ObjectSplit& axis, size_t total, float* rightCost, ObjectSplit& best) {
  const int numBins = axis.numBins;
  // Sweep from the right: cost of bins [i, numBins).
  BinBounds acc;
  uint64_t active = 0;
  // Empty bins change nothing: they repeat the costs of their neighbour
  // (small nodes leave most of the bins empty).
  float cost = 0.0f;
  for (int i = numBins - 1; i > 0; --i) {
    if (ab[i].count != 0 || i + 1 == numBins) {
      acc.extend(ab[i].bounds);
      active += ab[i].active;
      cost = acc.mbsahArea() * float(active);
    }
    rightCost[i] = cost;
  }
  // Sweep from the left: split between bin i-1 and bin i.
  acc = BinBounds();
  active = 0;
  size_t leftCount = 0;
  // A split after an empty bin repeats the split before it (same sides,
  // same cost; the first one is kept), so it is not evaluated again.
  for (int i = 1; i < numBins; ++i) {
    if (ab[i - 1].count == 0) continue;
    acc.extend(ab[i - 1].bounds);
    active += ab[i - 1].active;
    leftCount += ab[i - 1].count;
    if (leftCount == 0 || leftCount == total) continue;
    const float area = acc.mbsahArea();
    const float c = area * float(active) + rightCost[i];
    if (c < best.cost) {
      best = axis;
      best.bin = i;
      best.cost = c;
    }
  }
}

}  // namespace

ObjectSplit findObjectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int maxBins,
                            TimeRange /*range: bounds are local to it*/) {
  const int numBins = adaptiveBins(maxBins, refs.size());
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
  if (refs.size() == 2) return splitPair(refs, axes);
  // One pass over the references fills the bins of all three axes.
  const size_t nb = static_cast<size_t>(numBins);
  const bool serial = refs.size() < kParallelRefs;
  BinArray small(serial ? 3 * nb : 0);
  std::vector<Bin> large;
  if (serial) fillBins(refs, axes, nb, small.data());
  else large = fillBinsParallel(refs, axes, nb);
  const Bin* bins = serial ? small.data() : large.data();
  float rightCost[kMaxBins];
  for (int axis = 0; axis < 3; ++axis)
    if (axes[axis].axis >= 0) sweepAxis(bins + size_t(axis) * nb, axes[axis], refs.size(), rightCost, best);
  return best;
}

size_t partitionObject(std::span<BuildRef> refs, const ObjectSplit& split, RefSetInfo sides[2],
                       std::span<BuildRef> along0, std::span<BuildRef> along1) {
  // Hoare partition that summarizes each reference as it is placed, so the
  // children need no pass of their own over their references.
  InfoAcc acc[2];
  auto goesLeft = [&](Centroid c) { return split.binAt(axisOf(c, split.axis)) < split.bin; };
  size_t i = 0, j = refs.size();
  Centroid right{}, left{};  // keys of the pair that stopped the scans
  while (true) {
    for (; i < j; ++i) {
      right = centroidOf(refs[i]);
      if (!goesLeft(right)) break;
      acc[0].add(refs[i], right);
    }
    for (; i < j; --j) {
      left = centroidOf(refs[j - 1]);
      if (goesLeft(left)) break;
      acc[1].add(refs[j - 1], left);
    }
    if (i == j) break;
    // refs[i] goes right and refs[j - 1] left: swapped into place.
    std::swap(refs[i], refs[j - 1]);
    if (!along0.empty()) std::swap(along0[i], along0[j - 1]);
    if (!along1.empty()) std::swap(along1[i], along1[j - 1]);
    acc[0].add(refs[i], left);
    acc[1].add(refs[j - 1], right);
    ++i;
    --j;
  }
  sides[0] = acc[0].get();
  sides[1] = acc[1].get();
  return i;
}

size_t partitionMedian(std::span<BuildRef> refs, int axis, RefSetInfo sides[2]) {
  const size_t half = refs.size() / 2;
  std::nth_element(refs.begin(), refs.begin() + std::ptrdiff_t(half), refs.end(),
                   [axis](const BuildRef& a, const BuildRef& b) {
                     const float ca = a.centroid()[axis], cb = b.centroid()[axis];
                     if (ca != cb) return ca < cb;
                     if (a.prim.geomID != b.prim.geomID) return a.prim.geomID < b.prim.geomID;
                     return a.prim.primID < b.prim.primID;
                   });
  sides[0] = summarize(refs.first(half));
  sides[1] = summarize(refs.subspan(half));
  return half;
}

}  // namespace mbrt::detail
