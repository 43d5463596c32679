#include "bvh/collapse.h"

#include "geometry/primitive_bounds.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace mbrt::detail {
namespace {

// A lane that is not opened further: a leaf, or a soft node as one leaf
// holding its whole subtree's primitives.
inline bool leafLane(const BinaryNode& c) { return c.isLeaf() || c.soft; }

// Opens the lane with the largest area among the inner nodes that are
// `soft` (or not) until the node has N lanes; returns the lane count.
template <int N>
int openLargest(const BinaryTree& tree, uint32_t (&lanes)[N], int n, bool soft) {
  while (n < N) {
    int best = -1;
    for (int i = 0; i < n; ++i) {
      const BinaryNode& c = tree.nodes[lanes[i]];
      if (!c.isLeaf() && c.soft == soft && (best < 0 || c.area > tree.nodes[lanes[best]].area)) best = i;
    }
    if (best < 0) break;
    const BinaryNode& open = tree.nodes[lanes[best]];
    for (int i = n; i > best + 1; --i) lanes[i] = lanes[i - 1];  // keep spatial order
    lanes[best] = open.child[0];
    lanes[best + 1] = open.child[1];
    ++n;
  }
  return n;
}

// The binary nodes that become the lanes of the wide node made for `id`:
// its children, then the largest inner children opened (each saves a wide
// node), then, in the lanes still free, the largest soft children (smaller
// leaves at no node cost: Embree fills a node by splitting its largest
// child whatever the SAH says, GeneralBVHBuilder::recurse).
template <int N>
int openChildren(const BinaryTree& tree, uint32_t id, uint32_t (&lanes)[N]) {
  const BinaryNode& node = tree.nodes[id];
  if (node.isLeaf()) {  // only a leaf root gets here
    lanes[0] = id;
    return 1;
  }
  lanes[0] = node.child[0];
  lanes[1] = node.child[1];
  return openLargest<N>(tree, lanes, openLargest<N>(tree, lanes, 2, false), true);
}

struct Counts {
  size_t nodes = 0, timed = 0;
};

template <int N>
void countNodes(const BinaryTree& tree, uint32_t id, Counts& c) {
  uint32_t lanes[N];
  const int n = openChildren<N>(tree, id, lanes);
  ++c.nodes;
  const TimeRange range = tree.nodes[id].range;
  bool timed = false;
  for (int i = 0; i < n; ++i) {
    const BinaryNode& child = tree.nodes[lanes[i]];
    timed |= !(child.range == range);
    if (!leafLane(child)) countNodes<N>(tree, lanes[i], c);
  }
  c.timed += timed;
}

// The node's bounds extrapolated to t = 0 and 1 (one FMA per plane in
// traversal, STBVH §3.1); outside the node's range they may invert, which is
// fine: no ray outside the range reaches the node. Should the extrapolation
// overflow (a tiny range far from the origin), the constant hull of the
// local bounds stands in.
inline LBounds globalBounds(const BinaryNode& c) {
  const LBounds g = toGlobal(c.bounds, c.range);
  if (isFinite(g.b0.lower) && isFinite(g.b0.upper) && isFinite(g.b1.lower) && isFinite(g.b1.upper)) return g;
  const Box3f hull = c.bounds.hull();
  return LBounds(hull, hull);
}

template <int N, bool Motion>
class Emitter {
 public:
  Emitter(const BinaryTree& tree, WideBvh<N, Motion>& out) : tree_(tree), out_(out) {}

  uint32_t emit(uint32_t id, uint32_t depth) {
    const uint32_t index = uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    out_.nodes[index].clear();
    out_.depth = std::max(out_.depth, depth);
    uint32_t lanes[N];
    const int n = openChildren<N>(tree_, id, lanes);
    // Stack bound: every level leaves at most N-1 siblings behind.
    out_.stackSize = std::max(out_.stackSize, (N - 1) * depth + 1);
    // Lanes serving less than the node's range get time ranges.
    const TimeRange range = tree_.nodes[id].range;
    bool timed = false;
    for (int i = 0; i < n; ++i) timed |= !(tree_.nodes[lanes[i]].range == range);
    if (Motion && timed) {
      LaneTimes<N> lt;
      std::memset(static_cast<void*>(&lt), 0, sizeof(lt));  // padding too: bytes are compared
      for (int i = 0; i < N; ++i) {
        lt.t0[i] = kInf;
        lt.t1[i] = -kInf;
      }
      const float end = tree_.range.hi;
      for (int i = 0; i < n; ++i) {
        const TimeRange r = tree_.nodes[lanes[i]].range;
        lt.t0[i] = r.lo;
        // The end of the tree's range is inclusive: store the next float up.
        lt.t1[i] = r.hi >= end ? std::nextafter(r.hi, kInf) : r.hi;
      }
      out_.nodes[index].times = uint32_t(out_.times.size());
      out_.times.push_back(lt);
    }
    for (int i = 0; i < n; ++i) {
      const BinaryNode& c = tree_.nodes[lanes[i]];
      out_.nodes[index].setBounds(i, globalBounds(c));
      if (leafLane(c)) {
        out_.nodes[index].child[i] = uint32_t(out_.prims.size());
        out_.nodes[index].count[i] = uint8_t(c.count);
        // Sorted by geometry: the leaf test handles one geometry's run at a
        // time (leaf_intersect.h).
        const size_t first = out_.prims.size();
        for (uint32_t k = 0; k < c.count; ++k) out_.prims.push_back(tree_.prims[c.begin + k]);
        std::sort(out_.prims.begin() + std::ptrdiff_t(first), out_.prims.end(), [](PrimRef a, PrimRef b) {
          return a.geomID != b.geomID ? a.geomID < b.geomID : a.primID < b.primID;
        });
      } else {
        const uint32_t childIndex = emit(lanes[i], depth + 1);
        out_.nodes[index].child[i] = childIndex;
      }
    }
    return index;
  }

 private:
  const BinaryTree& tree_;
  WideBvh<N, Motion>& out_;
};

}  // namespace

template <int N, bool Motion>
void collapse(const BinaryTree& tree, WideBvh<N, Motion>& out, BuildBudget& budget) {
  out = WideBvh<N, Motion>();
  if (tree.empty()) return;
  Counts counts;
  countNodes<N>(tree, tree.root, counts);
  if (!Motion) counts.timed = 0;
  budget.charge(counts.nodes * sizeof(WideNode<N, Motion>) + tree.prims.size() * sizeof(PrimRef) +
                    counts.timed * sizeof(LaneTimes<N>),
                "the BVH nodes");
  out.nodes.reserve(counts.nodes);
  out.times.reserve(counts.timed);
  out.prims.reserve(tree.prims.size());
  Emitter<N, Motion>(tree, out).emit(tree.root, 1);
}

template void collapse<2, true>(const BinaryTree&, WideBvh<2, true>&, BuildBudget&);
template void collapse<4, true>(const BinaryTree&, WideBvh<4, true>&, BuildBudget&);
template void collapse<8, true>(const BinaryTree&, WideBvh<8, true>&, BuildBudget&);
template void collapse<2, false>(const BinaryTree&, WideBvh<2, false>&, BuildBudget&);
template void collapse<4, false>(const BinaryTree&, WideBvh<4, false>&, BuildBudget&);
template void collapse<8, false>(const BinaryTree&, WideBvh<8, false>&, BuildBudget&);

}  // namespace mbrt::detail
