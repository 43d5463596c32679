#include "msbvh/sbvh_builder.h"

#include <algorithm>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_invoke.h>

#include "bvh/heuristics/binned_sah.h"

namespace mbrt::detail {
namespace {

// A child's references: the first `count` of `slot`, the rest its room.
struct Side {
  std::span<SplitRef> slot;
  size_t count = 0;
};

class Builder {
 public:
  Builder(const SbvhSettings& s, const RefClipper& c, float rootArea, SbvhTree& tree)
      : s_(s), clipper_(c), rootArea_(rootArea), tree_(tree) {}

  uint32_t newNodes(size_t count) { return uint32_t(tree_.nodes.grow_by(count) - tree_.nodes.begin()); }

  // Node `index` over `node.count` references; the rest of its slot is the
  // subtree's growth room (the budget of references it may add).
  void build(uint32_t index, Side in, int depth) {
    SbvhNode& node = tree_.nodes[index];
    const std::span<SplitRef> refs = in.slot.first(in.count);
    const size_t n = in.count, budget = in.slot.size() - n;
    const BoxSetInfo info = summarize(refs);
    node.box = info.bounds;
    if (n <= 1) {
      node.refs = refs;
      return;
    }
    const float area = node.box.halfArea();
    ObjectSplit obj;
    Box3f objSides[2];
    // Object bins as the BVH family's, 8 + 10% of the references (at most
    // objectBins): a small node swept 32 bins per axis.
    if (depth < s_.maxBinnedDepth) obj = findObjectSplit(refs, info, adaptiveObjectBins(s_.objectBins, n), objSides);
    SpatialSplit sp;
    if (depth < s_.maxBinnedDepth && budget > 0 && s_.alpha < 1.0f) {
      const float overlap = obj.valid() ? intersect(objSides[0], objSides[1]).halfArea() : area;
      if (overlap > s_.alpha * rootArea_ && overlap > s_.nodeOverlap * area) {
        sp = findSpatialSplit(refs, node.box, adaptiveObjectBins(s_.spatialBins, n), clipper_,
                              s_.spatialLongestAxisOnly ? node.box.largestAxis() : -1);
        if (sp.valid() && (sp.leftCount >= n || sp.rightCount >= n || sp.leftCount + sp.rightCount - n > budget))
          sp = SpatialSplit();
      }
    }
    const float best = std::min(obj.cost, sp.cost);
    const float leafCost = area * float(n);
    const float splitCost = s_.traversalCost * area + best;
    if (n <= size_t(s_.maxLeafSize) && !(splitCost < leafCost)) return fillLeaf(index, refs);
    Side sides[2];
    if (!(sp.valid() && sp.cost < obj.cost && splitSpatial(in, sp, sides))) {
      const size_t mid = splitObject(refs, obj, info);
      place(in.slot, mid, n - mid, budget, sides);
    }
    const uint32_t first = newNodes(2);
    node.child[0] = first;
    node.child[1] = first + 1;
    if (n > s_.parallelThreshold) {
      tbb::parallel_invoke([&] { build(first, sides[0], depth + 1); }, [&] { build(first + 1, sides[1], depth + 1); });
    } else {
      build(first, sides[0], depth + 1);
      build(first + 1, sides[1], depth + 1);
    }
  }

 private:
  // The children's slots in `slot`, whose first nl references go left and
  // the next nr right: the room left, `rest`, is handed to them in
  // proportion to their sizes, the right references moving up past the
  // left child's share.
  static void place(std::span<SplitRef> slot, size_t nl, size_t nr, size_t rest, Side (&sides)[2]) {
    const size_t lb = size_t(double(rest) * double(nl) / double(nl + nr));
    const size_t rb = rest - lb;
    if (lb > 0) std::copy_backward(slot.begin() + nl, slot.begin() + nl + nr, slot.begin() + nl + lb + nr);
    sides[0] = {slot.first(nl + lb), nl};
    sides[1] = {slot.subspan(nl + lb, nr + rb), nr};
  }

  // The spatial split `sp` of the node's references, written back into its
  // slot (or, where it added more references than the room, into storage of
  // its own); false where one side would get everything or nothing.
  bool splitSpatial(Side in, const SpatialSplit& sp, Side (&sides)[2]) {
    const size_t n = in.count, budget = in.slot.size() - n;
    SpatialSplitScratch& scratch = scratch_.local();
    const size_t added = applySpatialSplit(in.slot.first(n), sp, clipper_, scratch);
    const size_t nl = scratch.left.size(), nr = scratch.right.size();
    if (nl == 0 || nr == 0 || nl >= n || nr >= n) return false;
    const size_t rest = budget - std::min(budget, added);
    std::span<SplitRef> slot = in.slot;
    if (nl + nr + rest > slot.size()) slot = *tree_.overflow.emplace_back(nl + nr + rest);
    std::copy(scratch.left.begin(), scratch.left.end(), slot.begin());
    std::copy(scratch.right.begin(), scratch.right.end(), slot.begin() + nl);
    place(slot, nl, nr, rest, sides);
    return true;
  }

  // The object split `obj` in place, or the median of the largest centroid
  // axis where it is invalid or puts everything on one side; returns the
  // size of the left side.
  static size_t splitObject(std::span<SplitRef> refs, const ObjectSplit& obj, const BoxSetInfo& info) {
    const size_t n = refs.size();
    BoxSetInfo sides[2];
    size_t mid = obj.valid() ? partitionObject(refs, obj, sides) : 0;
    if (mid == 0 || mid == n) mid = partitionMedian(refs, info.centroids.largestAxis(), sides);
    return mid;
  }

  // An SAH leaf, split by object splits down to single references for the
  // collapse's node filling (sbvh_builder.h).
  void fillLeaf(uint32_t index, std::span<SplitRef> refs) {
    SbvhNode& node = tree_.nodes[index];
    node.fill = true;
    if (refs.size() <= 1) {
      node.refs = refs;
      return;
    }
    const BoxSetInfo info = summarize(refs);
    const size_t mid = splitObject(refs, findObjectSplit(refs, info, s_.objectBins), info);
    const uint32_t first = newNodes(2);
    node.child[0] = first;
    node.child[1] = first + 1;
    const std::span<SplitRef> halves[2] = {refs.first(mid), refs.subspan(mid)};
    for (int i = 0; i < 2; ++i) {
      SbvhNode& child = tree_.nodes[first + uint32_t(i)];
      for (const SplitRef& r : halves[i]) child.box.extend(r.box);
      fillLeaf(first + uint32_t(i), halves[i]);
    }
  }

  const SbvhSettings& s_;
  const RefClipper& clipper_;
  float rootArea_;
  SbvhTree& tree_;
  // Per thread: a spatial split's sides are made there, then copied into
  // the node's slot (no recursion runs in between).
  tbb::enumerable_thread_specific<SpatialSplitScratch> scratch_;
};

}  // namespace

SbvhTree buildSbvh(std::vector<SplitRef> refs, const SbvhSettings& settings, const RefClipper& clipper) {
  SbvhTree tree;
  if (refs.empty()) return tree;
  Box3f root;
  for (const SplitRef& r : refs) root.extend(r.box);
  const size_t count = refs.size();
  const size_t budget = size_t(double(settings.maxGrowth) * double(count));
  tree.refs = std::move(refs);
  tree.refs.resize(count + budget);
  Builder b(settings, clipper, root.halfArea(), tree);
  b.build(b.newNodes(1), {tree.refs, count}, 0);
  return tree;
}

}  // namespace mbrt::detail
