#include "msbvh/sbvh_builder.h"

#include <algorithm>

#include <tbb/parallel_invoke.h>

namespace mbrt::detail {
namespace {

struct ObjectSplitResult {
  int axis = -1;
  int bin = 0;
  float cost = kInf;
  float origin = 0.0f, scale = 0.0f;
  int numBins = 0;
  Box3f left, right;
  bool valid() const { return axis >= 0; }
  int binOf(const SplitRef& r) const {
    return std::clamp(int((r.box.center()[axis] - origin) * scale), 0, numBins - 1);
  }
};

ObjectSplitResult findObject(const std::vector<SplitRef>& refs, const Box3f& centroids, int numBins) {
  ObjectSplitResult best;
  struct Bin {
    Box3f box;
    uint32_t count = 0;
  };
  std::vector<Bin> bins(static_cast<size_t>(numBins));
  std::vector<Box3f> rightBox(static_cast<size_t>(numBins));
  std::vector<uint32_t> rightCount(static_cast<size_t>(numBins));
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = centroids.lower[axis], extent = centroids.upper[axis] - lo;
    if (!(extent > 0.0f)) continue;
    ObjectSplitResult cand;
    cand.axis = axis;
    cand.origin = lo;
    cand.scale = float(numBins) * (1.0f - 1e-6f) / extent;
    cand.numBins = numBins;
    std::fill(bins.begin(), bins.end(), Bin());
    for (const SplitRef& r : refs) {
      Bin& b = bins[size_t(cand.binOf(r))];
      b.box.extend(r.box);
      ++b.count;
    }
    Box3f acc;
    uint32_t cnt = 0;
    for (int i = numBins - 1; i > 0; --i) {
      acc.extend(bins[size_t(i)].box);
      cnt += bins[size_t(i)].count;
      rightBox[size_t(i)] = acc;
      rightCount[size_t(i)] = cnt;
    }
    acc = Box3f();
    cnt = 0;
    for (int i = 1; i < numBins; ++i) {
      acc.extend(bins[size_t(i - 1)].box);
      cnt += bins[size_t(i - 1)].count;
      if (cnt == 0 || rightCount[size_t(i)] == 0) continue;
      const float cost = acc.halfArea() * float(cnt) + rightBox[size_t(i)].halfArea() * float(rightCount[size_t(i)]);
      if (cost < best.cost) {
        best = cand;
        best.bin = i;
        best.cost = cost;
        best.left = acc;
        best.right = rightBox[size_t(i)];
      }
    }
  }
  return best;
}

bool refLess(const SplitRef& a, const SplitRef& b, int axis) {
  const float ca = a.box.center()[axis], cb = b.box.center()[axis];
  if (ca != cb) return ca < cb;
  if (a.prim.geomID != b.prim.geomID) return a.prim.geomID < b.prim.geomID;
  if (a.prim.primID != b.prim.primID) return a.prim.primID < b.prim.primID;
  for (int k = 0; k < 3; ++k)
    if (a.region.lower[k] != b.region.lower[k]) return a.region.lower[k] < b.region.lower[k];
  return false;
}

class Builder {
 public:
  Builder(const SbvhSettings& s, const RefClipper& c, float rootArea) : s_(s), clipper_(c), rootArea_(rootArea) {}

  std::unique_ptr<SbvhNode> build(std::vector<SplitRef> refs, int depth, size_t budget) {
    auto node = std::make_unique<SbvhNode>();
    Box3f centroids;
    for (const SplitRef& r : refs) {
      node->box.extend(r.box);
      centroids.extend(r.box.center());
    }
    const size_t n = refs.size();
    if (n <= 1) {
      node->refs = std::move(refs);
      return node;
    }
    const float area = node->box.halfArea();
    ObjectSplitResult obj;
    if (depth < s_.maxBinnedDepth) obj = findObject(refs, centroids, s_.objectBins);
    SpatialSplit sp;
    if (depth < s_.maxBinnedDepth && budget > 0 && s_.alpha < 1.0f) {
      const float overlap = obj.valid() ? intersect(obj.left, obj.right).halfArea() : area;
      if (overlap > s_.alpha * rootArea_) {
        sp = findSpatialSplit(refs, node->box, s_.spatialBins, clipper_);
        if (sp.valid() && (sp.leftCount >= n || sp.rightCount >= n || sp.leftCount + sp.rightCount - n > budget))
          sp = SpatialSplit();
      }
    }
    const float best = std::min(obj.cost, sp.cost);
    const float leafCost = area * float(n);
    const float splitCost = s_.traversalCost * area + best;
    if (n <= size_t(s_.maxLeafSize) && !(splitCost < leafCost)) return fillLeaf(std::move(node), std::move(refs));
    std::vector<SplitRef> left, right;
    size_t added = 0;
    if (sp.valid() && sp.cost < obj.cost) {
      added = applySpatialSplit(refs, sp, clipper_, left, right);
      if (left.empty() || right.empty() || left.size() >= n || right.size() >= n) {
        left.clear();
        right.clear();
        added = 0;
      }
    }
    if (left.empty() && right.empty()) splitObject(refs, obj, centroids, left, right);
    refs.clear();
    refs.shrink_to_fit();
    const size_t rest = budget - std::min(budget, added);
    const size_t lb = size_t(double(rest) * double(left.size()) / double(left.size() + right.size()));
    const size_t rb = rest - lb;
    if (n > s_.parallelThreshold) {
      tbb::parallel_invoke([&] { node->child[0] = build(std::move(left), depth + 1, lb); },
                           [&] { node->child[1] = build(std::move(right), depth + 1, rb); });
    } else {
      node->child[0] = build(std::move(left), depth + 1, lb);
      node->child[1] = build(std::move(right), depth + 1, rb);
    }
    return node;
  }

 private:
  // The object split `obj`, or the median of the largest centroid axis
  // where it is invalid or puts everything on one side.
  static void splitObject(std::vector<SplitRef>& refs, const ObjectSplitResult& obj, const Box3f& centroids,
                          std::vector<SplitRef>& left, std::vector<SplitRef>& right) {
    const size_t n = refs.size();
    size_t mid = 0;
    if (obj.valid()) {
      auto it = std::partition(refs.begin(), refs.end(), [&](const SplitRef& r) { return obj.binOf(r) < obj.bin; });
      mid = size_t(it - refs.begin());
    }
    if (mid == 0 || mid == n) {
      const int axis = centroids.largestAxis();
      mid = n / 2;
      std::nth_element(refs.begin(), refs.begin() + std::ptrdiff_t(mid), refs.end(),
                       [axis](const SplitRef& a, const SplitRef& b) { return refLess(a, b, axis); });
    }
    left.assign(refs.begin(), refs.begin() + std::ptrdiff_t(mid));
    right.assign(refs.begin() + std::ptrdiff_t(mid), refs.end());
  }

  // An SAH leaf, split by object splits down to single references for the
  // collapse's node filling (sbvh_builder.h).
  std::unique_ptr<SbvhNode> fillLeaf(std::unique_ptr<SbvhNode> node, std::vector<SplitRef> refs) {
    node->fill = true;
    if (refs.size() <= 1) {
      node->refs = std::move(refs);
      return node;
    }
    Box3f centroids;
    for (const SplitRef& r : refs) centroids.extend(r.box.center());
    std::vector<SplitRef> left, right;
    splitObject(refs, findObject(refs, centroids, s_.objectBins), centroids, left, right);
    for (int i = 0; i < 2; ++i) {
      std::vector<SplitRef>& side = i == 0 ? left : right;
      auto child = std::make_unique<SbvhNode>();
      for (const SplitRef& r : side) child->box.extend(r.box);
      node->child[i] = fillLeaf(std::move(child), std::move(side));
    }
    return node;
  }

  const SbvhSettings& s_;
  const RefClipper& clipper_;
  float rootArea_;
};

}  // namespace

std::unique_ptr<SbvhNode> buildSbvh(std::vector<SplitRef> refs, const SbvhSettings& settings,
                                    const RefClipper& clipper) {
  if (refs.empty()) return nullptr;
  Box3f root;
  for (const SplitRef& r : refs) root.extend(r.box);
  const size_t budget = size_t(double(settings.maxGrowth) * double(refs.size()));
  Builder b(settings, clipper, root.halfArea());
  return b.build(std::move(refs), 0, budget);
}

}  // namespace mbrt::detail
