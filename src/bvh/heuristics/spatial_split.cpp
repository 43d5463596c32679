#include "bvh/heuristics/spatial_split.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_reduce.h>

#include "core/simd.h"
#include "scene/primitive_bounds.h"

namespace mbrt::detail {

namespace {

// The half-space side of a box.
Box3f cutBelow(Box3f b, int axis, float pos) {
  b.upper[axis] = std::min(b.upper[axis], pos);
  return b;
}
Box3f cutAbove(Box3f b, int axis, float pos) {
  b.lower[axis] = std::max(b.lower[axis], pos);
  return b;
}

// The clipped piece's bounds, widened against clipping round-off but never
// beyond the box it was clipped to.
Box3f piece(const RefClipper& clipper, PrimRef prim, const Box3f& within) {
  const Box3f c = clipper.clip(prim, within);
  if (c.empty()) return c;
  return intersect(widen(c), within);
}

}  // namespace

bool splitReference(const SplitRef& ref, int axis, float pos, const RefClipper& clipper, SplitRef& left,
                    SplitRef& right) {
  const Box3f l = piece(clipper, ref.prim, cutBelow(ref.box, axis, pos));
  if (l.empty()) return false;
  const Box3f r = piece(clipper, ref.prim, cutAbove(ref.box, axis, pos));
  if (r.empty()) return false;
  left = {l, cutBelow(ref.region, axis, pos), ref.prim};
  right = {r, cutAbove(ref.region, axis, pos), ref.prim};
  return true;
}

void RefClipper::chop(PrimRef prim, const Box3f& box, int axis, std::span<const float> planes, Box3f* pieces) const {
  for (size_t k = 0; k <= planes.size(); ++k) {
    Box3f slab = box;
    if (k > 0) slab.lower[axis] = std::max(slab.lower[axis], planes[k - 1]);
    if (k < planes.size()) slab.upper[axis] = std::min(slab.upper[axis], planes[k]);
    pieces[k] = clip(prim, slab);
  }
}

namespace {

using P4 = Pack<4>;

// A box in three lanes. Each operation picks as the Box3f operation it
// stands for (std::min / std::max: the operands in that order), so the
// bins hold the same bits as Box3f arithmetic would.
struct LaneBox {
  P4 lo = P4::set1(kInf), hi = P4::set1(-kInf);

  static LaneBox of(const Box3f& b) { return {P4::loadu(&b.lower.x), P4::load3(&b.upper.x)}; }
  bool empty() const { return (lessMask(hi, lo) & 0x7) != 0; }  // Box3f::empty
  void extend(const LaneBox& b) {  // Box3f::extend
    lo = vmin(b.lo, lo);
    hi = vmax(b.hi, hi);
  }
  LaneBox intersect(const LaneBox& b) const { return {vmax(b.lo, lo), vmin(b.hi, hi)}; }  // intersect(*this, b)
  LaneBox widen() const {  // widen() of a box that is not empty
    const P4 s = vmax(abs(hi), abs(lo)) * P4::set1(kRelativeSlack) + P4::set1(1e-30f);
    return {lo - s, hi + s};
  }
  Box3f get() const {
    alignas(16) float l[4], h[4];
    lo.store(l);
    hi.store(h);
    return {{l[0], l[1], l[2]}, {h[0], h[1], h[2]}};
  }
};

struct SpatialBin {
  LaneBox bounds;
  uint32_t enter = 0, exit = 0;
};

constexpr int kMaxSpatialBins = 256;
constexpr size_t kParallelSpatialRefs = 4096;
constexpr size_t kSpatialGrain = 1024;

// The binning planes of one axis over the node box.
struct SpatialAxis {
  float lo = 0.0f, extent = 0.0f, scale = 0.0f;
  int numBins = 0;
  bool valid() const { return extent > 0.0f; }
  float plane(int i) const { return lo + extent * float(i) / float(numBins); }
  int binOf(float x) const { return std::clamp(int((x - lo) * scale), 0, numBins - 1); }
};

// x with lane `axis` replaced by v.
struct LaneOfAxis {
  P4 on, off;
  explicit LaneOfAxis(int axis) {
    const P4 index = P4::of(0.0f, 1.0f, 2.0f, 3.0f), a = P4::set1(float(axis));
    on = equalLanes(index, a);
    off = lessLanes(index, a) | lessLanes(a, index);
  }
  P4 set(P4 x, float v) const { return (x & off) | (P4::set1(v) & on); }
};

// Bins `refs` on every valid axis into bins[axis * numBins + bin]: each
// reference enters its first bin, exits its last, and its piece in each bin
// it spans (chopped at the bin planes, SBVH §4.2) grows that bin.
void fillSpatialBins(std::span<const SplitRef> refs, const SpatialAxis (&axes)[3], const RefClipper& clipper,
                     SpatialBin* bins) {
  float planes[3][kMaxSpatialBins + 1];  // ax.plane(i), evaluated once
  for (int axis = 0; axis < 3; ++axis)
    for (int i = 0; i <= axes[axis].numBins; ++i) planes[axis][i] = axes[axis].plane(i);
  const LaneOfAxis lanes[3] = {LaneOfAxis(0), LaneOfAxis(1), LaneOfAxis(2)};
  Box3f pieces[kMaxSpatialBins];
  for (const SplitRef& r : refs) {
    const LaneBox box = LaneBox::of(r.box);
    for (int axis = 0; axis < 3; ++axis) {
      const SpatialAxis& ax = axes[axis];
      if (!ax.valid()) continue;
      SpatialBin* ab = bins + size_t(axis) * size_t(ax.numBins);
      const int first = ax.binOf(r.box.lower[axis]), last = ax.binOf(r.box.upper[axis]);
      ++ab[first].enter;
      ++ab[last].exit;
      if (first == last) {
        ab[first].bounds.extend(box);
        continue;
      }
      const int cuts = last - first;
      const float* cut = planes[axis] + first + 1;  // the planes inside the reference
      clipper.chop(r.prim, r.box, axis, std::span<const float>(cut, size_t(cuts)), pieces);
      for (int k = 0; k <= cuts; ++k) {
        const LaneBox piece = LaneBox::of(pieces[k]);
        if (piece.empty()) continue;
        // The reference's box between the planes around the bin.
        LaneBox slab = box;
        if (k > 0) slab.lo = lanes[axis].set(slab.lo, std::max(r.box.lower[axis], cut[k - 1]));
        if (k < cuts) slab.hi = lanes[axis].set(slab.hi, std::min(r.box.upper[axis], cut[k]));
        // Widened against clipping round-off, never beyond the slab.
        ab[first + k].bounds.extend(piece.widen().intersect(slab));
      }
    }
  }
}

void mergeBins(std::vector<SpatialBin>& a, const std::vector<SpatialBin>& b) {
  for (size_t i = 0; i < a.size(); ++i) {
    a[i].bounds.extend(b[i].bounds);
    a[i].enter += b[i].enter;
    a[i].exit += b[i].exit;
  }
}

// The best plane of one axis's bins, if it beats `best`.
void sweepSpatialAxis(const SpatialBin* ab, const SpatialAxis& ax, int axis, size_t count, SpatialSplit& best) {
  Box3f rightBox[kMaxSpatialBins];
  Box3f acc;
  for (int i = ax.numBins - 1; i > 0; --i) {
    acc.extend(ab[i].bounds.get());
    rightBox[i] = acc;
  }
  acc = Box3f();
  size_t nl = 0, nr = count;
  for (int i = 1; i < ax.numBins; ++i) {
    acc.extend(ab[i - 1].bounds.get());
    nl += ab[i - 1].enter;
    nr -= ab[i - 1].exit;
    if (nl == 0 || nr == 0) continue;
    const float cost = acc.halfArea() * float(nl) + rightBox[i].halfArea() * float(nr);
    if (cost < best.cost) {
      best.axis = axis;
      best.pos = ax.plane(i);
      best.cost = cost;
      best.leftCount = nl;
      best.rightCount = nr;
    }
  }
}

}  // namespace

SpatialSplit findSpatialSplit(std::span<const SplitRef> refs, const Box3f& nodeBox, int numBins,
                              const RefClipper& clipper, int onlyAxis) {
  numBins = std::clamp(numBins, 1, kMaxSpatialBins);
  SpatialAxis axes[3];
  for (int axis = 0; axis < 3; ++axis) {
    SpatialAxis& ax = axes[axis];
    ax.lo = nodeBox.lower[axis];
    ax.extent = nodeBox.upper[axis] - ax.lo;
    if (!(ax.extent > 0.0f)) ax.extent = 0.0f;
    if (onlyAxis >= 0 && axis != onlyAxis) ax.extent = 0.0f;
    ax.scale = ax.valid() ? float(numBins) / ax.extent : 0.0f;
    ax.numBins = numBins;
  }
  using Bins = std::vector<SpatialBin>;
  const size_t nb = 3 * size_t(numBins);
  Bins bins;
  if (refs.size() < kParallelSpatialRefs) {
    bins.resize(nb);
    fillSpatialBins(refs, axes, clipper, bins.data());
  } else {
    bins = tbb::parallel_deterministic_reduce(
        tbb::blocked_range<size_t>(0, refs.size(), kSpatialGrain), Bins(nb),
        [&](const tbb::blocked_range<size_t>& r, Bins acc) {
          fillSpatialBins(refs.subspan(r.begin(), r.size()), axes, clipper, acc.data());
          return acc;
        },
        [](Bins a, const Bins& b) {
          mergeBins(a, b);
          return a;
        });
  }
  SpatialSplit best;
  for (int axis = 0; axis < 3; ++axis)
    if (axes[axis].valid())
      sweepSpatialAxis(bins.data() + size_t(axis) * size_t(numBins), axes[axis], axis, refs.size(), best);
  return best;
}

size_t applySpatialSplit(std::span<const SplitRef> refs, const SpatialSplit& split, const RefClipper& clipper,
                         SpatialSplitScratch& out) {
  const int axis = split.axis;
  const float pos = split.pos;
  using Straddler = SpatialSplitScratch::Straddler;
  std::vector<SplitRef>& left = out.left;
  std::vector<SplitRef>& right = out.right;
  std::vector<Straddler>& straddlers = out.straddlers;
  left.clear();
  right.clear();
  straddlers.clear();
  Box3f lbox, rbox;
  size_t nl = 0, nr = 0;
  for (const SplitRef& r : refs) {
    if (r.box.upper[axis] <= pos) {
      left.push_back(r);
      lbox.extend(r.box);
      ++nl;
    } else if (r.box.lower[axis] >= pos) {
      right.push_back(r);
      rbox.extend(r.box);
      ++nr;
    } else {
      Straddler s{&r, {}, {}, false};
      s.split = splitReference(r, axis, pos, clipper, s.l, s.r);
      if (s.split) {
        lbox.extend(s.l.box);
        rbox.extend(s.r.box);
        ++nl;
        ++nr;
      }
      straddlers.push_back(s);
    }
  }
  size_t added = 0;
  for (Straddler& s : straddlers) {
    const SplitRef& r = *s.ref;
    if (!s.split) {
      // One side has nothing of it: whole to the side of its centre.
      const bool toLeft = r.box.center()[axis] < pos;
      (toLeft ? left : right).push_back(r);
      (toLeft ? lbox : rbox).extend(r.box);
      ++(toLeft ? nl : nr);
      continue;
    }
    // Unsplitting (SBVH §4.3): keep whole on one side where that is cheaper.
    const float csplit = lbox.halfArea() * float(nl) + rbox.halfArea() * float(nr);
    const float c1 = merge(lbox, r.box).halfArea() * float(nl) + rbox.halfArea() * float(nr - 1);
    const float c2 = lbox.halfArea() * float(nl - 1) + merge(rbox, r.box).halfArea() * float(nr);
    if (c1 < csplit && c1 <= c2 && nr > 1) {
      left.push_back(r);
      lbox.extend(r.box);
      --nr;
    } else if (c2 < csplit && nl > 1) {
      right.push_back(r);
      rbox.extend(r.box);
      --nl;
    } else {
      left.push_back(s.l);
      right.push_back(s.r);
      ++added;
    }
  }
  return added;
}

}  // namespace mbrt::detail
