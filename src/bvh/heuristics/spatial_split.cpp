#include "bvh/heuristics/spatial_split.h"

#include <algorithm>

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

SpatialSplit findSpatialSplit(std::span<const SplitRef> refs, const Box3f& nodeBox, int numBins,
                              const RefClipper& clipper) {
  SpatialSplit best;
  const size_t nb = size_t(numBins);
  std::vector<Box3f> bounds(nb);
  std::vector<uint32_t> enter(nb), exit(nb);
  std::vector<Box3f> rightBox(nb);
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = nodeBox.lower[axis], extent = nodeBox.upper[axis] - lo;
    if (!(extent > 0.0f)) continue;
    const float scale = float(numBins) / extent;
    auto plane = [&](int i) { return lo + extent * float(i) / float(numBins); };
    auto binOf = [&](float x) { return std::clamp(int((x - lo) * scale), 0, numBins - 1); };
    std::fill(bounds.begin(), bounds.end(), Box3f());
    std::fill(enter.begin(), enter.end(), 0u);
    std::fill(exit.begin(), exit.end(), 0u);
    for (const SplitRef& r : refs) {
      const int first = binOf(r.box.lower[axis]), last = binOf(r.box.upper[axis]);
      ++enter[size_t(first)];
      ++exit[size_t(last)];
      if (first == last) {
        bounds[size_t(first)].extend(r.box);
        continue;
      }
      for (int b = first; b <= last; ++b) {
        Box3f slab = r.box;
        if (b > first) slab.lower[axis] = std::max(slab.lower[axis], plane(b));
        if (b < last) slab.upper[axis] = std::min(slab.upper[axis], plane(b + 1));
        bounds[size_t(b)].extend(piece(clipper, r.prim, slab));
      }
    }
    Box3f acc;
    for (int i = numBins - 1; i > 0; --i) {
      acc.extend(bounds[size_t(i)]);
      rightBox[size_t(i)] = acc;
    }
    acc = Box3f();
    size_t nl = 0, nr = refs.size();
    for (int i = 1; i < numBins; ++i) {
      acc.extend(bounds[size_t(i - 1)]);
      nl += enter[size_t(i - 1)];
      nr -= exit[size_t(i - 1)];
      if (nl == 0 || nr == 0) continue;
      const float cost = acc.halfArea() * float(nl) + rightBox[size_t(i)].halfArea() * float(nr);
      if (cost < best.cost) {
        best.axis = axis;
        best.pos = plane(i);
        best.cost = cost;
        best.leftCount = nl;
        best.rightCount = nr;
      }
    }
  }
  return best;
}

size_t applySpatialSplit(std::span<const SplitRef> refs, const SpatialSplit& split, const RefClipper& clipper,
                         std::vector<SplitRef>& left, std::vector<SplitRef>& right) {
  const int axis = split.axis;
  const float pos = split.pos;
  struct Straddler {
    const SplitRef* ref;
    SplitRef l, r;
    bool split;
  };
  std::vector<Straddler> straddlers;
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
