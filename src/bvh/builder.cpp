#include "bvh/builder.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "bvh/binned_sah.h"
#include "bvh/temporal_split.h"
#include "bvh/wide_layout.h"
#include "geometry/primitive_bounds.h"

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

// References made by a temporal split, charged to the budget while they
// live. Moving keeps the buffer, so spans into it stay valid.
class OwnedRefs {
 public:
  OwnedRefs() = default;
  OwnedRefs(BuildBudget& budget, std::vector<BuildRef>&& refs) : refs_(std::move(refs)) {
    budget.charge(bytes(), "the temporal split references");
    budget_ = &budget;
  }
  OwnedRefs(OwnedRefs&& o) noexcept : budget_(std::exchange(o.budget_, nullptr)), refs_(std::move(o.refs_)) {}
  OwnedRefs& operator=(OwnedRefs&& o) noexcept {
    release();
    budget_ = std::exchange(o.budget_, nullptr);
    refs_ = std::move(o.refs_);
    return *this;
  }
  ~OwnedRefs() { release(); }
  std::span<BuildRef> span() { return refs_; }

 private:
  size_t bytes() const { return refs_.size() * sizeof(BuildRef); }
  void release() {
    if (budget_) budget_->release(bytes());
    budget_ = nullptr;
  }
  BuildBudget* budget_ = nullptr;
  std::vector<BuildRef> refs_;
};

struct Decision {
  enum Kind { Leaf, Object, Temporal } kind = Leaf;
  size_t mid = 0;     // Object: size of the left side (references reordered)
  float time = 0.0f;  // Temporal: split time
  ObjectSplit split;  // Leaf: the best object split, to fill lanes with
  std::vector<BuildRef> left, right;  // Temporal: the halves' references
  RefSetInfo sides[2];                // Object, Temporal: the children's summaries
};

// A node of the binary split hierarchy, as a candidate lane of a wide node.
// Hard nodes carry the SAH's decision; soft nodes lie below a leaf decision
// and are split by objects only to fill lanes.
struct Candidate {
  std::span<BuildRef> refs;
  RefSetInfo info;
  TimeRange range;
  int depth = 0;
  float area = 0.0f;  // MBSAH area x range length: the largest is split first
  bool soft = false;
  Decision decision;  // hard nodes only
  OwnedRefs storage;  // the references, when a temporal split made them

  bool inner() const { return !soft && decision.kind != Decision::Leaf; }
  bool fillable() const { return !inner() && refs.size() > 1; }
};

// The node's bounds extrapolated to t = 0 and 1 (one FMA per plane in
// traversal, STBVH §3.1); outside the node's range they may invert, which is
// fine: no ray outside the range reaches the node. Should the extrapolation
// overflow (a tiny range far from the origin), the constant hull of the
// local bounds stands in.
LBounds globalBounds(const Candidate& c) {
  const LBounds g = toGlobal(c.info.bounds, c.range);
  if (isFinite(g.b0.lower) && isFinite(g.b0.upper) && isFinite(g.b1.lower) && isFinite(g.b1.upper)) return g;
  const Box3f hull = c.info.bounds.hull();
  return LBounds(hull, hull);
}

template <int N, bool Motion>
class Driver {
 public:
  Driver(const BuildSettings& s, UnorderedWideBvh<N, Motion>& tree, BuildBudget& budget)
      : s_(s), tree_(tree), budget_(budget) {}

  uint32_t buildRoot(std::span<BuildRef> refs) {
    Candidate root = candidate(refs, summarize(refs), s_.range, 0, false);
    decide(root);
    return build(root);
  }

 private:
  // The wide node of `node` (an inner node, or a root leaf); returns its id.
  uint32_t build(Candidate& node) {
    const TimeRange range = node.range;
    Candidate lanes[N];
    std::vector<OwnedRefs> kept;  // references of the nodes split into lanes
    int n = 1;
    lanes[0] = std::move(node);
    if (lanes[0].inner() || lanes[0].fillable()) n = splitLane(lanes, n, 0, kept);
    n = fill(lanes, n, kept, [](const Candidate& c) { return c.inner(); });
    n = fill(lanes, n, kept, [](const Candidate& c) { return c.fillable(); });
    uint32_t child[N];
    auto buildLane = [&](int i) { child[i] = lanes[i].inner() ? build(lanes[i]) : storeLeaf(lanes[i]); };
    if (totalRefs(lanes, n) > s_.parallelThreshold) {
      tbb::parallel_for(0, n, 1, buildLane);
    } else {
      for (int i = 0; i < n; ++i) buildLane(i);
    }
    return storeNode(lanes, n, range, child);
  }

  // Splits the largest lane that `splittable` accepts until the node has N
  // lanes or none is left (STBVH §3.3: "repeatedly splitting the child with
  // the largest area"); the halves keep the split lane's place.
  template <class Splittable>
  int fill(Candidate (&lanes)[N], int n, std::vector<OwnedRefs>& kept, const Splittable& splittable) {
    while (n < N) {
      int best = -1;
      for (int i = 0; i < n; ++i)
        if (splittable(lanes[i]) && (best < 0 || lanes[i].area > lanes[best].area)) best = i;
      if (best < 0) break;
      n = splitLane(lanes, n, best, kept);
    }
    return n;
  }

  // Replaces lane i by its two children (n < N); returns the lane count.
  int splitLane(Candidate (&lanes)[N], int n, int i, std::vector<OwnedRefs>& kept) {
    Candidate& node = lanes[i];
    Candidate halves[2];
    if (node.inner() && node.decision.kind == Decision::Temporal) {
      Decision& d = node.decision;
      halves[0] = candidate({}, d.sides[0], {node.range.lo, d.time}, node.depth + 1, false);
      halves[1] = candidate({}, d.sides[1], {d.time, node.range.hi}, node.depth + 1, false);
      adopt(halves[0], std::move(d.left));
      adopt(halves[1], std::move(d.right));
    } else {
      RefSetInfo sides[2];
      size_t mid = node.decision.mid;
      if (node.inner()) {
        std::copy_n(node.decision.sides, 2, sides);
      } else {  // fill: split by objects, whatever the SAH says
        const ObjectSplit split = node.soft ? objectSplit(node.refs, node.info, node.depth) : node.decision.split;
        mid = partition(node.refs, node.info, split, sides);
      }
      const bool soft = !node.inner();
      halves[0] = candidate(node.refs.first(mid), sides[0], node.range, node.depth + 1, soft);
      halves[1] = candidate(node.refs.subspan(mid), sides[1], node.range, node.depth + 1, soft);
    }
    kept.push_back(std::move(node.storage));
    auto decideHalf = [&](int h) {
      if (!halves[h].soft) decide(halves[h]);
    };
    if (node.refs.size() > s_.parallelThreshold) {
      tbb::parallel_invoke([&] { decideHalf(0); }, [&] { decideHalf(1); });
    } else {
      decideHalf(0);
      decideHalf(1);
    }
    for (int k = n; k > i + 1; --k) lanes[k] = std::move(lanes[k - 1]);
    lanes[i] = std::move(halves[0]);
    lanes[i + 1] = std::move(halves[1]);
    return n + 1;
  }

  Candidate candidate(std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth, bool soft) {
    Candidate c;
    c.refs = refs;
    c.info = info;
    c.range = range;
    c.depth = depth;
    c.area = mbsahArea(info.bounds) * range.size();
    c.soft = soft;
    return c;
  }

  void adopt(Candidate& c, std::vector<BuildRef>&& refs) {
    c.storage = OwnedRefs(budget_, std::move(refs));
    c.refs = c.storage.span();
  }

  // The SAH's decision for a hard node. A temporal split with a half where
  // nothing is alive makes no node: the candidate narrows to the other half.
  void decide(Candidate& c) {
    while (true) {
      c.decision = chooseSplit(c.refs, c.info, c.range, c.depth, mbsahArea(c.info.bounds));
      Decision& d = c.decision;
      if (d.kind != Decision::Temporal || (!d.left.empty() && !d.right.empty())) return;
      const int half = d.left.empty() ? 1 : 0;
      const TimeRange range = half == 0 ? TimeRange{c.range.lo, d.time} : TimeRange{d.time, c.range.hi};
      Candidate narrowed = candidate({}, d.sides[half], range, c.depth + 1, false);
      adopt(narrowed, std::move(half == 0 ? d.left : d.right));
      c = std::move(narrowed);
    }
  }

  static size_t totalRefs(const Candidate (&lanes)[N], int n) {
    size_t total = 0;
    for (int i = 0; i < n; ++i) total += lanes[i].refs.size();
    return total;
  }

  uint32_t storeLeaf(const Candidate& c) {
    const auto it = tree_.prims.grow_by(c.refs.size());
    const size_t first = size_t(it - tree_.prims.begin());
    chargeBlocks<PrimRef>(tree_.charge, first, c.refs.size(), "the BVH build's leaves");
    for (size_t k = 0; k < c.refs.size(); ++k) tree_.prims[first + k] = c.refs[k].prim;
    return uint32_t(first);
  }

  uint32_t storeNode(const Candidate (&lanes)[N], int n, TimeRange range, const uint32_t (&child)[N]) {
    WideNode<N, Motion> node;
    node.clear();
    // Lanes serving less than the node's range get time ranges (§3.3).
    bool timed = false;
    for (int i = 0; i < n; ++i) timed |= !(lanes[i].range == range);
    if (Motion && timed) node.times = storeTimes(lanes, n);
    for (int i = 0; i < n; ++i) {
      node.setBounds(i, globalBounds(lanes[i]));
      node.child[i] = child[i];
      node.count[i] = lanes[i].inner() ? 0 : uint8_t(lanes[i].refs.size());
    }
    const auto it = tree_.nodes.push_back(node);
    const size_t id = size_t(it - tree_.nodes.begin());
    chargeBlocks<WideNode<N, Motion>>(tree_.charge, id, 1, "the BVH build's nodes");
    return uint32_t(id);
  }

  uint32_t storeTimes(const Candidate (&lanes)[N], int n) {
    LaneTimes<N> lt;
    std::memset(static_cast<void*>(&lt), 0, sizeof(lt));  // padding too: bytes are compared
    for (int i = 0; i < N; ++i) {
      lt.t0[i] = kInf;
      lt.t1[i] = -kInf;
    }
    const float end = s_.range.hi;
    for (int i = 0; i < n; ++i) {
      const TimeRange r = lanes[i].range;
      lt.t0[i] = r.lo;
      // The end of the tree's range is inclusive: store the next float up.
      lt.t1[i] = r.hi >= end ? std::nextafter(r.hi, kInf) : r.hi;
    }
    const auto it = tree_.times.push_back(lt);
    const size_t id = size_t(it - tree_.times.begin());
    chargeBlocks<LaneTimes<N>>(tree_.charge, id, 1, "the BVH build's nodes");
    return uint32_t(id);
  }

  ObjectSplit objectSplit(std::span<const BuildRef> refs, const RefSetInfo& info, int depth) const {
    if (depth >= s_.maxBinnedDepth || refs.size() <= 1) return ObjectSplit();
    return findObjectSplit(refs, info, s_.numBins, {}, s_.leafBlock);
  }

  // The object split, or the median where binning cannot separate the
  // references; `sides` gets both children's summaries.
  static size_t partition(std::span<BuildRef> refs, const RefSetInfo& info, const ObjectSplit& split,
                          RefSetInfo sides[2]) {
    size_t mid = split.valid() ? partitionObject(refs, split, sides) : 0;
    if (mid == 0 || mid == refs.size()) mid = partitionMedian(refs, info.centroids.largestAxis(), sides);
    return mid;
  }

  // Leaf cost C_I*A*|X|_s against C_T*A + split cost (MBSAH, STBVH §3.2).
  Decision chooseSplit(std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth, float area) {
    Decision d;
    const size_t count = refs.size();
    if (count <= 1 && !s_.temporal) return d;
    const ObjectSplit split = objectSplit(refs, info, depth);
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
  UnorderedWideBvh<N, Motion>& tree_;
  BuildBudget& budget_;
};

}  // namespace

template <int N, bool Motion>
void buildWideTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget,
                   WideBvh<N, Motion>& out) {
  out = WideBvh<N, Motion>();
  if (refs.empty()) return;
  UnorderedWideBvh<N, Motion> tree(budget);
  tree.root = Driver<N, Motion>(settings, tree, budget).buildRoot(refs);
  layOut(tree, out, budget);
}

#define MBRT_BUILD_WIDE_TREE(N, Motion) \
  template void buildWideTree<N, Motion>(std::span<BuildRef>, const BuildSettings&, BuildBudget&, WideBvh<N, Motion>&);
MBRT_BUILD_WIDE_TREE(2, true)
MBRT_BUILD_WIDE_TREE(4, true)
MBRT_BUILD_WIDE_TREE(8, true)
MBRT_BUILD_WIDE_TREE(2, false)
MBRT_BUILD_WIDE_TREE(4, false)
MBRT_BUILD_WIDE_TREE(8, false)
#undef MBRT_BUILD_WIDE_TREE

}  // namespace mbrt::detail
