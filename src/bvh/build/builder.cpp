#include "bvh/build/builder.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>
#include <vector>

#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "bvh/heuristics/split_choice.h"
#include "bvh/build/wide_layout.h"
#include "scene/primitive_bounds.h"

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
  OwnedRefs storage;  // the references, when a temporal split narrowed to them
  // A temporal split of these references (same range) that an ancestor
  // tried and rejected: its object-split children try it again.
  TemporalHalves tried;

  bool inner() const { return !soft && decision.kind != Decision::Leaf; }
  // A leaf that filling may split: more references than one leaf block.
  bool fillable(int leafBlock) const { return !inner() && refs.size() > size_t(std::max(leafBlock, 1)); }
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
      : s_(s), tree_(tree), chooser_(s, budget) {}

  uint32_t buildRoot(std::span<BuildRef> refs) {
    Candidate root;
    place(root, refs, summarize(refs), s_.range, 0, false);
    decide(root);
    return build(root);
  }

 private:
  // The wide node of `node` (an inner node, or a root leaf); returns its id.
  // Split candidates stay where they are made, in `pool`, while their lanes
  // are built: their references (and a temporal split's) live there.
  uint32_t build(Candidate& node) {
    Candidate* lanes[N] = {&node};
    Candidate pool[2 * (N - 1)];
    Candidate* next = pool;
    int n = 1;
    const int block = s_.leafBlock;
    if (node.inner() || node.fillable(block)) n = splitLane(lanes, n, 0, next);
    n = fill(lanes, n, next, [](const Candidate& c) { return c.inner(); });
    n = fill(lanes, n, next, [block](const Candidate& c) { return c.fillable(block); });
    uint32_t child[N];
    auto buildLane = [&](int i) { child[i] = lanes[i]->inner() ? build(*lanes[i]) : storeLeaf(*lanes[i]); };
    if (totalRefs(lanes, n) > s_.parallelThreshold) {
      tbb::parallel_for(0, n, 1, buildLane);
    } else {
      for (int i = 0; i < n; ++i) buildLane(i);
    }
    return storeNode(lanes, n, node.range, child);
  }

  // Splits the largest lane that `splittable` accepts until the node has N
  // lanes or none is left (STBVH §3.3: "repeatedly splitting the child with
  // the largest area"); the halves keep the split lane's place.
  template <class Splittable>
  int fill(Candidate* (&lanes)[N], int n, Candidate*& next, const Splittable& splittable) {
    while (n < N) {
      int best = -1;
      for (int i = 0; i < n; ++i)
        if (splittable(*lanes[i]) && (best < 0 || lanes[i]->area > lanes[best]->area)) best = i;
      if (best < 0) break;
      n = splitLane(lanes, n, best, next);
    }
    return n;
  }

  // Replaces lane i by its two children, made at `next` (n < N); returns
  // the lane count.
  int splitLane(Candidate* (&lanes)[N], int n, int i, Candidate*& next) {
    Candidate& node = *lanes[i];
    Candidate* halves = next;
    next += 2;
    Decision& d = node.decision;
    if (node.inner() && d.kind == Decision::Temporal) {
      const float time = d.halves.time;
      place(halves[0], d.halves.refs[0], d.sides[0], {node.range.lo, time}, node.depth + 1, false);
      place(halves[1], d.halves.refs[1], d.sides[1], {time, node.range.hi}, node.depth + 1, false);
    } else {
      RefSetInfo sides[2];
      size_t mid = node.decision.mid;
      if (node.inner()) {
        std::copy_n(node.decision.sides, 2, sides);
      } else {  // fill: split by objects, whatever the SAH says
        const ObjectSplit split =
            node.soft ? chooser_.objectSplit(node.refs, node.info, node.depth) : node.decision.split;
        mid = SplitChooser::partition(node.refs, node.info, split, sides);
      }
      const bool soft = !node.inner();
      place(halves[0], node.refs.first(mid), sides[0], node.range, node.depth + 1, soft);
      place(halves[1], node.refs.subspan(mid), sides[1], node.range, node.depth + 1, soft);
      if (!soft && d.halves.alignedWith(node.refs)) {
        halves[0].tried = {d.halves.time, {d.halves.refs[0].first(mid), d.halves.refs[1].first(mid)}};
        halves[1].tried = {d.halves.time, {d.halves.refs[0].subspan(mid), d.halves.refs[1].subspan(mid)}};
      }
    }
    auto decideHalf = [&](int h) {
      if (!halves[h].soft) decide(halves[h]);
    };
    if (node.refs.size() > s_.parallelThreshold) {
      tbb::parallel_invoke([&] { decideHalf(0); }, [&] { decideHalf(1); });
    } else {
      decideHalf(0);
      decideHalf(1);
    }
    for (int k = n; k > i + 1; --k) lanes[k] = lanes[k - 1];
    lanes[i] = &halves[0];
    lanes[i + 1] = &halves[1];
    return n + 1;
  }

  // Sets what every candidate has (`c` is fresh: no decision, nothing tried).
  static void place(Candidate& c, std::span<BuildRef> refs, const RefSetInfo& info, TimeRange range, int depth,
                    bool soft) {
    c.refs = refs;
    c.info = info;
    c.range = range;
    c.depth = depth;
    c.area = mbsahArea(info.bounds) * range.size();
    c.soft = soft;
  }

  // The SAH's decision for a hard node. A temporal split with a half where
  // nothing is alive makes no node: the candidate narrows to the other half.
  void decide(Candidate& c) {
    while (true) {
      c.decision = chooser_.choose(c.refs, c.info, c.range, c.depth, c.tried);
      Decision& d = c.decision;
      const std::span<BuildRef>(&halves)[2] = d.halves.refs;
      if (d.kind != Decision::Temporal || (!halves[0].empty() && !halves[1].empty())) return;
      const int half = halves[0].empty() ? 1 : 0;
      const float time = d.halves.time;
      const TimeRange range = half == 0 ? TimeRange{c.range.lo, time} : TimeRange{time, c.range.hi};
      Candidate narrowed;
      place(narrowed, halves[half], d.sides[half], range, c.depth + 1, false);
      narrowed.storage = std::move(d.made[half]);
      c = std::move(narrowed);
    }
  }

  static size_t totalRefs(Candidate* const (&lanes)[N], int n) {
    size_t total = 0;
    for (int i = 0; i < n; ++i) total += lanes[i]->refs.size();
    return total;
  }

  uint32_t storeLeaf(const Candidate& c) {
    const auto it = tree_.prims.grow_by(c.refs.size());
    const size_t first = size_t(it - tree_.prims.begin());
    chargeBlocks<PrimRef>(tree_.charge, first, c.refs.size(), "the BVH build's leaves");
    // Sorted by geometry: the leaf test takes one geometry's run at a time
    // (leaves/leaf_runs.h). A leaf is small (its lane count is 8 bits).
    PrimRef leaf[UINT8_MAX];
    const size_t n = c.refs.size();
    for (size_t k = 0; k < n; ++k) leaf[k] = c.refs[k].prim;
    std::sort(leaf, leaf + n, [](PrimRef a, PrimRef b) {
      return a.geomID != b.geomID ? a.geomID < b.geomID : a.primID < b.primID;
    });
    std::copy_n(leaf, n, it);
    return uint32_t(first);
  }

  uint32_t storeNode(Candidate* const (&lanes)[N], int n, TimeRange range, const uint32_t (&child)[N]) {
    WideNode<N, Motion> node;
    node.clear();
    // Lanes serving less than the node's range get time ranges (§3.3).
    bool timed = false;
    for (int i = 0; i < n; ++i) timed |= !(lanes[i]->range == range);
    if (Motion && timed) node.times = storeTimes(lanes, n);
    LBounds bounds[N];
    for (int i = 0; i < n; ++i) bounds[i] = globalBounds(*lanes[i]);
    node.encode(bounds, (1u << n) - 1u);
    for (int i = 0; i < n; ++i) {
      node.child[i] = child[i];
      node.count[i] = lanes[i]->inner() ? 0 : uint8_t(lanes[i]->refs.size());
    }
    const auto it = tree_.nodes.push_back(node);
    const size_t id = size_t(it - tree_.nodes.begin());
    chargeBlocks<WideNode<N, Motion>>(tree_.charge, id, 1, "the BVH build's nodes");
    return uint32_t(id);
  }

  uint32_t storeTimes(Candidate* const (&lanes)[N], int n) {
    LaneTimes<N> lt;
    std::memset(static_cast<void*>(&lt), 0, sizeof(lt));  // padding too: bytes are compared
    for (int i = 0; i < N; ++i) {
      lt.t0[i] = kInf;
      lt.t1[i] = -kInf;
    }
    const float end = s_.range.hi;
    for (int i = 0; i < n; ++i) {
      const TimeRange r = lanes[i]->range;
      lt.t0[i] = r.lo;
      // The end of the tree's range is inclusive: store the next float up.
      lt.t1[i] = r.hi >= end ? std::nextafter(r.hi, kInf) : r.hi;
    }
    const auto it = tree_.times.push_back(lt);
    const size_t id = size_t(it - tree_.times.begin());
    chargeBlocks<LaneTimes<N>>(tree_.charge, id, 1, "the BVH build's nodes");
    return uint32_t(id);
  }

  const BuildSettings& s_;
  UnorderedWideBvh<N, Motion>& tree_;
  SplitChooser chooser_;
};

}  // namespace

template <int N, bool Motion>
void buildWideTree(std::span<BuildRef> refs, const BuildSettings& settings, BuildBudget& budget,
                   WideBvh<N, Motion>& out) {
  out = WideBvh<N, Motion>();
  if (refs.empty()) return;
  UnorderedWideBvh<N, Motion> tree(budget);
  tree.root = Driver<N, Motion>(settings, tree, budget).buildRoot(refs);
  layOut(tree, out, budget, settings.leafBlock);
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
