#include "bvh/builder.h"

#include <tbb/parallel_invoke.h>

#include "bvh/binned_sah.h"

namespace mbrt::detail {
namespace {

class Driver {
 public:
  Driver(std::span<BuildRef> refs, const BuildSettings& s, BinaryTree& tree) : refs_(refs), s_(s), tree_(tree) {}

  uint32_t build(uint32_t begin, uint32_t end, int depth) {
    const std::span<BuildRef> refs = refs_.subspan(begin, end - begin);
    const RefSetInfo info = summarize(refs);
    const uint32_t id = next_.fetch_add(1, std::memory_order_relaxed);
    BinaryNode node;
    node.bounds = info.bounds;
    node.area = mbsahArea(info.bounds, s_.range);
    node.begin = begin;
    node.count = end - begin;

    const size_t mid = chooseSplit(refs, info, depth, node.area);
    if (mid == 0) {
      tree_.nodes[id] = node;
      return id;
    }
    const uint32_t m = begin + uint32_t(mid);
    if (node.count > s_.parallelThreshold) {
      tbb::parallel_invoke([&] { node.child[0] = build(begin, m, depth + 1); },
                           [&] { node.child[1] = build(m, end, depth + 1); });
    } else {
      node.child[0] = build(begin, m, depth + 1);
      node.child[1] = build(m, end, depth + 1);
    }
    tree_.nodes[id] = node;
    return id;
  }

 private:
  // Partitions the references and returns the left size, or 0 for a leaf.
  // Leaf cost C_I*A*|X|_s against C_T*A + split cost (MBSAH, STBVH §3.2).
  size_t chooseSplit(std::span<BuildRef> refs, const RefSetInfo& info, int depth, float area) {
    const size_t count = refs.size();
    if (count <= 1) return 0;
    ObjectSplit split;
    if (depth < s_.maxBinnedDepth) split = findObjectSplit(refs, info, s_.numBins, s_.range);
    const float leafCost = area * float(info.active);
    const float splitCost = s_.traversalCost * area + split.cost;
    if (count <= size_t(s_.maxLeafSize) && !(splitCost < leafCost)) return 0;
    size_t mid = split.valid() ? partitionObject(refs, split) : 0;
    if (mid == 0 || mid == count) mid = partitionMedian(refs, info.centroids.largestAxis());
    return mid;
  }

  std::span<BuildRef> refs_;
  const BuildSettings& s_;
  BinaryTree& tree_;
  std::atomic<uint32_t> next_{0};
};

}  // namespace

BinaryTree buildBinaryTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget) {
  BinaryTree tree;
  if (refs.empty()) return tree;
  const size_t maxNodes = 2 * refs.size() - 1;  // every leaf holds >= 1 reference
  tree.charge = std::make_unique<ScopedCharge>(budget, maxNodes * sizeof(BinaryNode), "the temporary binary BVH");
  tree.nodes.resize(maxNodes);
  Driver driver(refs, settings, tree);
  tree.root = driver.build(0, uint32_t(refs.size()), 0);
  return tree;
}

}  // namespace mbrt::detail
