#include "bvh/builder.h"

#include <algorithm>

#include <tbb/parallel_invoke.h>

#include "bvh/binned_sah.h"
#include "bvh/temporal_split.h"

namespace mbrt::detail {
namespace {

// Tree storage is charged to the budget in blocks of this many elements.
constexpr size_t kChargeBlock = 4096;

// Charges the blocks that [first, first + count) starts.
template <class T>
void chargeBlocks(GrowingCharge& charge, size_t first, size_t count, const char* what) {
  const size_t before = (first + kChargeBlock - 1) / kChargeBlock;
  const size_t after = (first + count + kChargeBlock - 1) / kChargeBlock;
  if (after > before) charge.charge((after - before) * kChargeBlock * sizeof(T), what);
}

struct Decision {
  enum Kind { Leaf, Object, Temporal } kind = Leaf;
  size_t mid = 0;     // Object: size of the left side (references reordered)
  float time = 0.0f;  // Temporal: split time
  ObjectSplit split;  // Leaf: the best object split, the soft subtree's first
  std::vector<BuildRef> left, right;  // Temporal: the halves' references
  RefSetInfo sides[2];                // Object, Temporal: the children's summaries
};

class Driver {
 public:
  Driver(const BuildSettings& s, BinaryTree& tree, BuildBudget& budget) : s_(s), tree_(tree), budget_(budget) {}

  // Builds the subtree of `refs` (all made for `range`, summarized by
  // `known` when the parent's split did it); returns its node id.
  uint32_t build(std::span<BuildRef> refs, TimeRange range, int depth, const RefSetInfo* known = nullptr) {
    const RefSetInfo info = known ? *known : summarize(refs);
    BinaryNode node = makeNode(info, range);
    Decision d = chooseSplit(refs, info, range, depth, mbsahArea(info.bounds));
    if (d.kind == Decision::Leaf) {
      const auto it = tree_.prims.grow_by(refs.size());
      const size_t first = size_t(it - tree_.prims.begin());
      chargeBlocks<PrimRef>(*tree_.charge, first, refs.size(), "the temporary binary BVH");
      return buildSoft(refs, info, d.split, range, depth, first);
    }
    if (d.kind == Decision::Object) {
      const std::span<BuildRef> l = refs.first(d.mid), r = refs.subspan(d.mid);
      children(node, refs.size(), [&] { return build(l, range, depth + 1, &d.sides[0]); },
               [&] { return build(r, range, depth + 1, &d.sides[1]); });
      return store(node);
    }
    // Temporal: both halves are new reference sets, alive while the children build.
    std::vector<BuildRef>& left = d.left;
    std::vector<BuildRef>& right = d.right;
    ScopedCharge scratch(budget_, (left.size() + right.size()) * sizeof(BuildRef), "the temporal split references");
    const TimeRange lr{range.lo, d.time}, rr{d.time, range.hi};
    // A half where nothing is alive gets no child: the node narrows to the other.
    if (left.empty()) return build(right, rr, depth + 1, &d.sides[1]);
    if (right.empty()) return build(left, lr, depth + 1, &d.sides[0]);
    children(node, refs.size(), [&] { return build(left, lr, depth + 1, &d.sides[0]); },
             [&] { return build(right, rr, depth + 1, &d.sides[1]); });
    return store(node);
  }

 private:
  static BinaryNode makeNode(const RefSetInfo& info, TimeRange range) {
    BinaryNode node;
    node.bounds = info.bounds;
    node.range = range;
    node.area = mbsahArea(info.bounds) * range.size();
    return node;
  }

  // The subtree of a leaf decision, its references at prims [first, first +
  // size): object splits only (no temporal splits, no new references), down
  // to single references; inner nodes are soft (builder.h). Small: built by
  // the calling task.
  uint32_t buildSoft(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split, TimeRange range,
                     int depth, size_t first) {
    BinaryNode node = makeNode(info, range);
    node.begin = uint32_t(first);
    node.count = uint32_t(refs.size());
    if (refs.size() == 1) {
      tree_.prims[first] = refs[0].prim;
      return store(node);
    }
    RefSetInfo sides[2];
    const size_t mid = partition(refs, info, split, sides);
    node.soft = true;
    node.child[0] = softChild(refs.first(mid), sides[0], range, depth + 1, first);
    node.child[1] = softChild(refs.subspan(mid), sides[1], range, depth + 1, first + mid);
    return store(node);
  }

  uint32_t softChild(std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth, size_t first) {
    return buildSoft(refs, info, objectSplit(refs, info, range, depth), range, depth, first);
  }

  ObjectSplit objectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth) const {
    if (depth >= s_.maxBinnedDepth || refs.size() <= 1) return ObjectSplit();
    return findObjectSplit(refs, info, s_.numBins, range, s_.leafBlock);
  }

  // The object split, or the median where binning cannot separate the
  // references; `sides` gets both children's summaries.
  static size_t partition(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split,
                          RefSetInfo sides[2]) {
    size_t mid = split.valid() ? partitionObject(refs, split, sides) : 0;
    if (mid == 0 || mid == refs.size()) mid = partitionMedian(refs, info.centroids.largestAxis(), sides);
    return mid;
  }

  template <class L, class R>
  void children(BinaryNode& node, size_t count, const L& left, const R& right) {
    if (count > s_.parallelThreshold) {
      tbb::parallel_invoke([&] { node.child[0] = left(); }, [&] { node.child[1] = right(); });
    } else {
      node.child[0] = left();
      node.child[1] = right();
    }
  }

  uint32_t store(const BinaryNode& node) {
    auto it = tree_.nodes.push_back(node);
    const size_t id = size_t(it - tree_.nodes.begin());
    chargeBlocks<BinaryNode>(*tree_.charge, id, 1, "the temporary binary BVH");
    return uint32_t(id);
  }

  // Leaf cost C_I*A*|X|_s against C_T*A + split cost (MBSAH, STBVH §3.2).
  Decision chooseSplit(std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth, float area) {
    Decision d;
    const size_t count = refs.size();
    if (count <= 1 && !s_.temporal) return d;
    const ObjectSplit split = objectSplit(refs, info, range, depth);
    const float leafCost = area * float(info.active);
    float best = split.cost;  // unnormalised, kInf when invalid
    // Temporal split: tried when the object split is poor (θ), chosen when
    // it wins even with the penalty λ for the references it duplicates.
    TemporalSplit temporal;
    float time = 0.0f;
    if (s_.temporal && depth < s_.maxBinnedDepth && !(split.cost < kTemporalTry * leafCost) &&
        temporalSplitTime(refs, range, *s_.temporal, time)) {
      ScopedCharge scratch(budget_, 2 * refs.size() * sizeof(BuildRef), "the temporal split references");
      splitTemporal(refs, range, time, *s_.temporal, d.left, d.right);
      temporal = temporalSplitCost(d.left, d.right, range, time, s_.leafBlock);
      if (kTemporalPenalty * temporal.cost < best) best = temporal.cost;
      else temporal = TemporalSplit();
    }
    if (!temporal.valid()) {
      d.left = {};
      d.right = {};
    }
    // Leaf or split: MBSAH with segment counts, or (primitiveLeafCost) the
    // cost of our leaves, which test a primitive once whatever its segments.
    float splitCost = s_.traversalCost * area + best, leafTest = leafCost;
    if (s_.primitiveLeafCost) {
      splitCost = s_.traversalCost * area + (temporal.valid() ? temporal.primCost : split.primCost);
      leafTest = area * leafBlocks(count, s_.leafBlock);
    }
    if (count <= size_t(s_.maxLeafSize) && !(splitCost < leafTest)) {
      Decision leaf;
      leaf.split = split;
      return leaf;
    }
    if (temporal.valid()) {
      d.kind = Decision::Temporal;
      d.time = temporal.time;
      std::copy_n(temporal.sides, 2, d.sides);
      return d;
    }
    if (count <= 1) return d;
    d.kind = Decision::Object;
    d.mid = partition(refs, info, split, d.sides);
    return d;
  }

  const BuildSettings& s_;
  BinaryTree& tree_;
  BuildBudget& budget_;
};

}  // namespace

void buildBinaryTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget, BinaryTree& tree) {
  if (refs.empty()) return;
  tree.charge = std::make_unique<GrowingCharge>(budget);
  tree.range = settings.range;
  Driver driver(settings, tree, budget);
  tree.root = driver.build(refs, settings.range, 0);
}

}  // namespace mbrt::detail
