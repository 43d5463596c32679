#include "msbvh/sbvh_builder.h"

#include <algorithm>

#include <tbb/parallel_invoke.h>

#include "bvh/heuristics/binned_sah.h"

namespace mbrt::detail {
namespace {

class Builder {
 public:
  Builder(const SbvhSettings& s, const RefClipper& c, float rootArea) : s_(s), clipper_(c), rootArea_(rootArea) {}

  std::unique_ptr<SbvhNode> build(std::vector<SplitRef> refs, int depth, size_t budget) {
    auto node = std::make_unique<SbvhNode>();
    const BoxSetInfo info = summarize(refs);
    node->box = info.bounds;
    const size_t n = refs.size();
    if (n <= 1) {
      node->refs = std::move(refs);
      return node;
    }
    const float area = node->box.halfArea();
    ObjectSplit obj;
    Box3f objSides[2];
    if (depth < s_.maxBinnedDepth) obj = findObjectSplit(refs, info, s_.objectBins, objSides);
    SpatialSplit sp;
    if (depth < s_.maxBinnedDepth && budget > 0 && s_.alpha < 1.0f) {
      const float overlap = obj.valid() ? intersect(objSides[0], objSides[1]).halfArea() : area;
      if (overlap > s_.alpha * rootArea_) {
        sp = findSpatialSplit(refs, node->box, adaptiveObjectBins(s_.spatialBins, n), clipper_);
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
    if (left.empty() && right.empty()) splitObject(refs, obj, info, left, right);
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
  static void splitObject(std::vector<SplitRef>& refs, const ObjectSplit& obj, const BoxSetInfo& info,
                          std::vector<SplitRef>& left, std::vector<SplitRef>& right) {
    const size_t n = refs.size();
    BoxSetInfo sides[2];
    size_t mid = obj.valid() ? partitionObject(refs, obj, sides) : 0;
    if (mid == 0 || mid == n) mid = partitionMedian(refs, info.centroids.largestAxis(), sides);
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
    const BoxSetInfo info = summarize(refs);
    std::vector<SplitRef> left, right;
    splitObject(refs, findObjectSplit(refs, info, s_.objectBins), info, left, right);
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
