#include "bvh/build/wide_layout.h"

#include <algorithm>

#include "core/huge_pages.h"
#include "mbrt/ray.h"

namespace mbrt::detail {
namespace {

template <int N, bool Motion>
class Layout {
 public:
  Layout(const UnorderedWideBvh<N, Motion>& tree, WideBvh<N, Motion>& out, int leafBlock)
      : tree_(tree), out_(out), inline_(leafBlock <= 1), align_(size_t(std::max(leafBlock, 1))) {}

  uint32_t emit(uint32_t id, uint32_t depth) {
    const uint32_t index = uint32_t(out_.nodes.size());
    out_.nodes.push_back(tree_.nodes[id]);
    out_.depth = std::max(out_.depth, depth);
    // Stack bound: every level leaves at most N-1 siblings behind.
    out_.stackSize = std::max(out_.stackSize, (N - 1) * depth + 1);
    const WideNode<N, Motion>& from = tree_.nodes[id];
    if (from.hasTimes()) {
      out_.nodes[index].times = uint32_t(out_.times.size());
      out_.times.push_back(tree_.times[from.times]);
    }
    const uint32_t inlineGeom = inline_ ? mostCommonSingleGeometry(from) : kInvalidId;
    out_.nodes[index].leafGeom = inlineGeom;
    for (int i = 0; i < N; ++i) {
      if (from.isLeaf(i)) {
        const auto first = tree_.prims.begin() + std::ptrdiff_t(from.child[i]);
        // Traversal tags the geomID with bit 31 (TraversalItem::kInline).
        if (from.count[i] == 1 && first->geomID == inlineGeom && first->geomID < (1u << 31)) {
          out_.nodes[index].child[i] = first->primID;
          out_.nodes[index].count[i] = kInlineLeaf;
          ++out_.inlineRefs;
          continue;
        }
        out_.nodes[index].child[i] = uint32_t(out_.prims.size());
        out_.prims.insert(out_.prims.end(), first, first + from.count[i]);
        pad(out_.prims.back());
      } else if (!from.isEmpty(i)) {
        const uint32_t child = emit(from.child[i], depth + 1);
        out_.nodes[index].child[i] = child;
      }
    }
    return index;
  }

 private:
  // The geometry of most one-reference leaves of `node` (the smallest id on
  // a tie), whose references the node keeps inline; kInvalidId if none.
  uint32_t mostCommonSingleGeometry(const WideNode<N, Motion>& node) const {
    uint32_t geoms[N], votes[N] = {};
    int n = 0;
    for (int i = 0; i < N; ++i)
      if (node.isLeaf(i) && node.count[i] == 1) geoms[n++] = tree_.prims[node.child[i]].geomID;
    uint32_t best = kInvalidId, bestVotes = 0;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) votes[i] += geoms[j] == geoms[i];
      if (votes[i] > bestVotes || (votes[i] == bestVotes && geoms[i] < best)) {
        best = geoms[i];
        bestVotes = votes[i];
      }
    }
    return best;
  }

  // Fills the table up to the next multiple of the block width with `ref`.
  void pad(const PrimRef& ref) {
    while (out_.prims.size() % align_ != 0) {
      out_.prims.push_back(ref);
      ++out_.paddingRefs;
    }
  }

  const UnorderedWideBvh<N, Motion>& tree_;
  WideBvh<N, Motion>& out_;
  bool inline_;
  size_t align_;
};

// The reference table's size once every leaf is padded to a multiple of
// `align` references.
template <int N, bool Motion>
size_t paddedTableSize(const UnorderedWideBvh<N, Motion>& tree, size_t align) {
  if (align <= 1) return tree.prims.size();
  size_t total = 0;
  for (const auto& node : tree.nodes)
    for (int i = 0; i < N; ++i)
      if (node.isLeaf(i)) total += (size_t(node.count[i]) + align - 1) / align * align;
  return total;
}

}  // namespace

template <int N, bool Motion>
void layOut(const UnorderedWideBvh<N, Motion>& tree, WideBvh<N, Motion>& out, BuildBudget& budget,
            int leafBlock) {
  out = WideBvh<N, Motion>();
  if (tree.root == tree.kNone) return;
  const size_t tableSize = paddedTableSize(tree, size_t(std::max(leafBlock, 1)));
  budget.charge(tree.nodes.size() * sizeof(WideNode<N, Motion>) + tableSize * sizeof(PrimRef) +
                    tree.times.size() * sizeof(LaneTimes<N>),
                "the BVH nodes");
  reserveOnHugePages(out.nodes, tree.nodes.size());
  reserveOnHugePages(out.times, tree.times.size());
  reserveOnHugePages(out.prims, tableSize);
  Layout<N, Motion>(tree, out, leafBlock).emit(tree.root, 1);
}

#define MBRT_LAY_OUT(N, Motion) \
  template void layOut<N, Motion>(const UnorderedWideBvh<N, Motion>&, WideBvh<N, Motion>&, BuildBudget&, int);
MBRT_LAY_OUT(2, true)
MBRT_LAY_OUT(4, true)
MBRT_LAY_OUT(8, true)
MBRT_LAY_OUT(2, false)
MBRT_LAY_OUT(4, false)
MBRT_LAY_OUT(8, false)
#undef MBRT_LAY_OUT

}  // namespace mbrt::detail
