#include "bvh/heuristics/binned_sah.h"

#include <algorithm>
#include <memory>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "bvh/heuristics/bin_accumulators.h"

namespace mbrt::detail {

namespace {

using namespace binning;

// Large nodes reduce in parallel over fixed blocks. The merges (min/max and
// integer sums) are exact, so the result never depends on the thread count.
constexpr size_t kParallelRefs = 32768;
constexpr size_t kGrain = 8192;

template <class Ref>
Summary<Ref> summarizeSerial(std::span<const Ref> refs) {
  InfoAcc<Ref> acc;
  for (const Ref& r : refs) acc.add(r, RefTraits<Ref>::key(r));
  return acc.get();
}

template <class Bounds>
void merge(RefSummary<Bounds>& a, const RefSummary<Bounds>& b) {
  a.bounds.extend(b.bounds);
  a.centroids.extend(b.centroids);
  a.active += b.active;
}

template <class Ref>
Summary<Ref> summarizeAny(std::span<const Ref> refs) {
  if (refs.size() < kParallelRefs) return summarizeSerial(refs);
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, refs.size(), kGrain), Summary<Ref>(),
      [&](const tbb::blocked_range<size_t>& r, Summary<Ref> acc) {
        merge(acc, summarizeSerial(refs.subspan(r.begin(), r.size())));
        return acc;
      },
      [](Summary<Ref> a, const Summary<Ref>& b) {
        merge(a, b);
        return a;
      });
}

constexpr int kMaxBins = 256;  // BuildOptions::sahBins at most (accel.cpp)

// Bins of the three axes, on the stack for the many small nodes.
template <class Ref>
class BinArray {
 public:
  explicit BinArray(size_t n) {
    if (n <= kInline) {
      data_ = std::uninitialized_value_construct_n(reinterpret_cast<Bin<Ref>*>(inline_), n) - n;
    } else {
      heap_.resize(n);
      data_ = heap_.data();
    }
  }
  BinArray(const BinArray&) = delete;
  BinArray& operator=(const BinArray&) = delete;
  Bin<Ref>* data() { return data_; }

 private:
  static constexpr size_t kInline = 3 * 32;
  alignas(Bin<Ref>) unsigned char inline_[kInline * sizeof(Bin<Ref>)];
  std::vector<Bin<Ref>> heap_;
  Bin<Ref>* data_;
};

// The bins of a key on the three axes (ObjectSplit::binAt of each, by the
// same operations: truncation, then the clamp).
class BinMap {
 public:
  explicit BinMap(const ObjectSplit (&axes)[3])
      : axes_(axes),
        origin_(P4::of(axes[0].origin, axes[1].origin, axes[2].origin, 0.0f)),
        scale_(P4::of(axes[0].scale, axes[1].scale, axes[2].scale, 0.0f)) {}
  void binsOf(P4 c, int (&bin)[3]) const {
    alignas(16) int32_t unclamped[4];
    ((c - origin_) * scale_).storeTruncated(unclamped);
    for (int a = 0; a < 3; ++a) bin[a] = std::clamp(unclamped[a], 0, std::max(axes_[a].numBins - 1, 0));
  }

 private:
  const ObjectSplit (&axes_)[3];
  P4 origin_, scale_;
};

// Fills the bins of the axes that have a transform (axes[a].axis >= 0).
template <class Ref>
void fillBins(std::span<const Ref> refs, const ObjectSplit (&axes)[3], size_t nb, Bin<Ref>* bins) {
  const BinMap map(axes);
  for (const Ref& r : refs) {
    int bin[3];
    map.binsOf(RefTraits<Ref>::key(r), bin);
    typename RefTraits<Ref>::Acc bounds;  // loaded once for the three axes
    bounds.extend(RefTraits<Ref>::bounds(r));
    const uint64_t weight = RefTraits<Ref>::weight(r);
    for (int axis = 0; axis < 3; ++axis) {
      if (axes[axis].axis < 0) continue;
      Bin<Ref>& b = bins[size_t(axis) * nb + size_t(bin[axis])];
      b.bounds.extend(bounds);
      b.active += weight;
      ++b.count;
    }
  }
}

// Bins of a large node, reduced in parallel over fixed blocks (exact merges).
template <class Ref>
std::vector<Bin<Ref>> fillBinsParallel(std::span<const Ref> refs, const ObjectSplit (&axes)[3], size_t nb) {
  using Bins = std::vector<Bin<Ref>>;
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, refs.size(), kGrain), Bins(3 * nb),
      [&](const tbb::blocked_range<size_t>& r, Bins acc) {
        fillBins(refs.subspan(r.begin(), r.size()), axes, nb, acc.data());
        return acc;
      },
      [](Bins a, const Bins& b) {
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
template <class Ref>
ObjectSplit splitPair(std::span<const Ref> refs, const ObjectSplit (&axes)[3], int leafBlock) {
  using T = RefTraits<Ref>;
  const BinMap map(axes);
  int bins[2][3];
  map.binsOf(T::key(refs[0]), bins[0]);
  map.binsOf(T::key(refs[1]), bins[1]);
  for (int axis = 0; axis < 3; ++axis) {
    if (axes[axis].axis < 0 || bins[0][axis] == bins[1][axis]) continue;
    const int left = bins[0][axis] < bins[1][axis] ? 0 : 1;
    typename T::Acc lb, rb;
    lb.extend(T::bounds(refs[left]));
    rb.extend(T::bounds(refs[1 - left]));
    const float rightCost = rb.area() * leafBlocks(T::weight(refs[1 - left]), 1, leafBlock);
    const float cost = lb.area() * leafBlocks(T::weight(refs[left]), 1, leafBlock) + rightCost;
    if (!(cost < kInf)) break;  // every axis has this cost: no split beats kInf
    ObjectSplit split = axes[axis];
    split.bin = bins[left][axis] + 1;
    split.cost = cost;
    return split;
  }
  return ObjectSplit();
}

// The best split of one axis's bins, if it beats `best`.
template <class Ref>
void sweepAxis(const Bin<Ref>* ab, const ObjectSplit& axis, size_t total, int leafBlock, float* rightCost,
               ObjectSplit& best) {
  const int numBins = axis.numBins;
  // Sweep from the right: cost of bins [i, numBins).
  typename RefTraits<Ref>::Acc acc;
  uint64_t active = 0, count = 0;
  // Empty bins change nothing: they repeat the costs of their neighbour
  // (small nodes leave most of the bins empty).
  float cost = 0.0f;
  for (int i = numBins - 1; i > 0; --i) {
    if (ab[i].count != 0 || i + 1 == numBins) {
      acc.extend(ab[i].bounds);
      active += ab[i].active;
      count += ab[i].count;
      cost = acc.area() * leafBlocks(active, count, leafBlock);
    }
    rightCost[i] = cost;
  }
  // Sweep from the left: split between bin i-1 and bin i.
  acc = {};
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
    const float c = acc.area() * leafBlocks(active, leftCount, leafBlock) + rightCost[i];
    if (c < best.cost) {
      best = axis;
      best.bin = i;
      best.cost = c;
    }
  }
}

// The bounds of both sides of `split` from its axis's bins.
template <class Ref>
void sideBounds(const Bin<Ref>* ab, const ObjectSplit& split, typename RefTraits<Ref>::Bounds (&sides)[2]) {
  typename RefTraits<Ref>::Acc acc[2];
  for (int i = 0; i < split.numBins; ++i) acc[i < split.bin ? 0 : 1].extend(ab[i].bounds);
  sides[0] = acc[0].get();
  sides[1] = acc[1].get();
}

template <class Ref>
ObjectSplit findSplit(std::span<const Ref> refs, const Summary<Ref>& info, int numBins,
                      typename RefTraits<Ref>::Bounds* sides, int leafBlock) {
  using Bounds = typename RefTraits<Ref>::Bounds;
  numBins = std::clamp(numBins, 1, kMaxBins);
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
  if (refs.size() == 2 && !sides) return splitPair(refs, axes, leafBlock);
  // One pass over the references fills the bins of all three axes.
  const size_t nb = static_cast<size_t>(numBins);
  const bool serial = refs.size() < kParallelRefs;
  BinArray<Ref> small(serial ? 3 * nb : 0);
  std::vector<Bin<Ref>> large;
  if (serial) fillBins(refs, axes, nb, small.data());
  else large = fillBinsParallel(refs, axes, nb);
  const Bin<Ref>* bins = serial ? small.data() : large.data();
  float rightCost[kMaxBins];
  for (int axis = 0; axis < 3; ++axis)
    if (axes[axis].axis >= 0) sweepAxis(bins + size_t(axis) * nb, axes[axis], refs.size(), leafBlock, rightCost, best);
  if (sides && best.valid()) {
    Bounds both[2];
    sideBounds(bins + size_t(best.axis) * nb, best, both);
    std::copy_n(both, 2, sides);
  }
  return best;
}

// Hoare partition that summarizes each reference as it is placed, so the
// children need no pass of their own over their references.
template <class Ref>
size_t partitionBins(std::span<Ref> refs, const ObjectSplit& split, Summary<Ref> sides[2],
                     std::span<Ref> along0, std::span<Ref> along1) {
  using T = RefTraits<Ref>;
  InfoAcc<Ref> acc[2];
  auto goesLeft = [&](P4 c) { return split.binAt(c.lane(split.axis)) < split.bin; };
  size_t i = 0, j = refs.size();
  P4 right{}, left{};  // keys of the pair that stopped the scans
  while (true) {
    for (; i < j; ++i) {
      right = T::key(refs[i]);
      if (!goesLeft(right)) break;
      acc[0].add(refs[i], right);
    }
    for (; i < j; --j) {
      left = T::key(refs[j - 1]);
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

// partitionBins in parallel over fixed blocks, with the same result: the
// serial scans swap the k-th reference that goes right among the first
// `mid` (counted from the front) with the k-th that goes left among the
// rest (counted from the back), and the sides' summaries depend only on
// which references they hold. So this pass finds every reference's side and
// the blocks' summaries, then makes the same swaps, in chunks of k.
template <class Ref>
size_t partitionBinsParallel(std::span<Ref> refs, const ObjectSplit& split, Summary<Ref> sides[2],
                             std::span<Ref> along0, std::span<Ref> along1) {
  using T = RefTraits<Ref>;
  const size_t n = refs.size(), blocks = (n + kGrain - 1) / kGrain;
  // One byte per reference: within the charge of the build references.
  std::vector<uint8_t> left(n);
  std::vector<InfoAcc<Ref>> acc(2 * blocks);
  std::vector<size_t> leftCount(blocks);
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t count = 0;
    for (size_t i = b * kGrain, end = std::min(n, i + kGrain); i < end; ++i) {
      const P4 key = T::key(refs[i]);
      const bool goesLeft = split.binAt(key.lane(split.axis)) < split.bin;
      left[i] = goesLeft;
      count += goesLeft;
      acc[2 * b + (goesLeft ? 0 : 1)].add(refs[i], key);
    }
    leftCount[b] = count;
  });
  InfoAcc<Ref> total[2];
  size_t mid = 0;
  for (size_t b = 0; b < blocks; ++b) {
    for (int side = 0; side < 2; ++side) total[side].add(acc[2 * b + side]);
    mid += leftCount[b];
  }
  sides[0] = total[0].get();
  sides[1] = total[1].get();
  // Misplaced references: those going right in [0, mid), ascending, and
  // those going left in [mid, n), descending; the k-th of each are swapped.
  auto misplacedFront = [&](size_t i) { return i < mid && !left[i]; };
  auto misplacedBack = [&](size_t i) { return i >= mid && left[i]; };
  std::vector<size_t> frontStart(blocks + 1, 0), backStart(blocks + 1, 0);  // ordinals of each block's first
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t f = 0, k = 0;
    for (size_t i = b * kGrain, end = std::min(n, i + kGrain); i < end; ++i) {
      f += misplacedFront(i);
      k += misplacedBack(i);
    }
    frontStart[b + 1] = f;
    backStart[b] = k;
  });
  for (size_t b = 0; b < blocks; ++b) frontStart[b + 1] += frontStart[b];
  for (size_t b = blocks; b-- > 0;) backStart[b] += backStart[b + 1];  // now: misplaced at the back in blocks >= b
  tbb::parallel_for(size_t(0), blocks, [&](size_t b) {
    size_t k = frontStart[b];
    if (frontStart[b + 1] == k) return;
    // The k-th misplaced reference at the back, counted from the end: in
    // the last block c with backStart[c] > k.
    size_t c = blocks - 1;
    while (backStart[c] <= k) --c;
    size_t skip = k - backStart[c + 1], q = std::min(n, (c + 1) * kGrain);
    while (true) {
      --q;
      if (misplacedBack(q) && skip-- == 0) break;
    }
    for (size_t i = b * kGrain, end = std::min(n, i + kGrain); i < end; ++i) {
      if (!misplacedFront(i)) continue;
      while (!misplacedBack(q)) --q;
      std::swap(refs[i], refs[q]);
      if (!along0.empty()) std::swap(along0[i], along0[q]);
      if (!along1.empty()) std::swap(along1[i], along1[q]);
      --q;
    }
  });
  return mid;
}

template <class Ref>
size_t partitionAtMedian(std::span<Ref> refs, int axis, Summary<Ref> sides[2]) {
  using T = RefTraits<Ref>;
  const size_t half = refs.size() / 2;
  std::nth_element(refs.begin(), refs.begin() + std::ptrdiff_t(half), refs.end(), [axis](const Ref& a, const Ref& b) {
    const float ca = T::scalarKey(a, axis), cb = T::scalarKey(b, axis);
    if (ca != cb) return ca < cb;
    return T::tieLess(a, b);
  });
  sides[0] = summarizeAny<Ref>(refs.first(half));
  sides[1] = summarizeAny<Ref>(refs.subspan(half));
  return half;
}

}  // namespace

RefSetInfo summarize(std::span<const BuildRef> refs) { return summarizeAny(refs); }
BoxSetInfo summarize(std::span<const SplitRef> refs) { return summarizeAny(refs); }

// Bins grow with the references (8 + 10% of them, at most maxBins): fewer
// than Embree's 4 + 5% lose SAH quality on thin geometry, and nearly all of
// the binning time is saved all the same (the measurements: docs/stbvh.md).
int adaptiveObjectBins(int maxBins, size_t count) {
  return std::min({maxBins, kMaxBins, int(8.0f + 0.1f * float(std::min<size_t>(count, 1 << 20)))});
}

ObjectSplit findObjectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int numBins, int leafBlock) {
  return findSplit<BuildRef>(refs, info, numBins, nullptr, leafBlock);
}
ObjectSplit findObjectSplit(std::span<const SplitRef> refs, const BoxSetInfo& info, int numBins, Box3f* sides) {
  return findSplit<SplitRef>(refs, info, numBins, sides, 1);
}

size_t partitionObject(std::span<BuildRef> refs, const ObjectSplit& split, RefSetInfo sides[2],
                       std::span<BuildRef> along0, std::span<BuildRef> along1) {
  if (refs.size() >= kParallelRefs) return partitionBinsParallel(refs, split, sides, along0, along1);
  return partitionBins(refs, split, sides, along0, along1);
}
size_t partitionObject(std::span<SplitRef> refs, const ObjectSplit& split, BoxSetInfo sides[2]) {
  if (refs.size() >= kParallelRefs) return partitionBinsParallel<SplitRef>(refs, split, sides, {}, {});
  return partitionBins<SplitRef>(refs, split, sides, {}, {});
}

size_t partitionMedian(std::span<BuildRef> refs, int axis, RefSetInfo sides[2]) {
  return partitionAtMedian(refs, axis, sides);
}
size_t partitionMedian(std::span<SplitRef> refs, int axis, BoxSetInfo sides[2]) {
  return partitionAtMedian(refs, axis, sides);
}

}  // namespace mbrt::detail
