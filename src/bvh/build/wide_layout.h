// The wide nodes as the parallel build makes them (children before their
// parent, in whatever order the threads finish), and their layout into a
// WideBvh: nodes and leaf primitives in one fixed depth-first order, so the
// tree is bit-identical whatever the thread count of the build.
#pragma once

#include <memory>

#include <tbb/concurrent_vector.h>

#include "bvh/build/builder.h"
#include "bvh/nodes/wide_bvh.h"
#include "core/huge_pages.h"

namespace mbrt::detail {

template <int N, bool Motion>
struct UnorderedWideBvh {
  static constexpr uint32_t kNone = 0xFFFFFFFFu;
  // Inner lanes' `child` index `nodes`, leaf lanes' index `prims`, `times` of
  // a node indexes `times`. The segments (a few dozen per build) come from
  // the system allocator rather than TBB's: its recycling of one build's
  // freed memory into another's is invisible to ThreadSanitizer, which then
  // reports the reuse as a race between the two builds. Large segments are
  // advised onto huge pages (core/huge_pages.h).
  template <class T>
  using Vector = tbb::concurrent_vector<T, HugePageAllocator<T>>;
  Vector<WideNode<N, Motion>> nodes;
  Vector<LaneTimes<N>> times;
  Vector<PrimRef> prims;
  uint32_t root = kNone;
  GrowingCharge charge;  // the storage above, as it grows

  explicit UnorderedWideBvh(BuildBudget& budget) : charge(budget) {}
  // Built in place (concurrent_vector's moves are not to be relied on).
  UnorderedWideBvh(const UnorderedWideBvh&) = delete;
  UnorderedWideBvh& operator=(const UnorderedWideBvh&) = delete;
};

// Lays `tree` out into `out` (replaced) from its root; charges `out`'s
// storage to `budget`. leafBlock <= 1: one-reference leaves are kept in
// their node (kInlineLeaf). leafBlock > 1 (trees whose leaves are tested as
// blocks, BuildSettings::leafBlock): no leaf is kept in a node, and every
// leaf starts at a multiple of leafBlock in the reference table (the gaps
// repeat the leaf's last reference; WideBvh::paddingRefs counts them), so
// that the leaf's k-th block is the table's block begin / leafBlock + k and
// traversal reaches it without a map (leaves/triangle_blocks.h).
template <int N, bool Motion>
void layOut(const UnorderedWideBvh<N, Motion>& tree, WideBvh<N, Motion>& out, BuildBudget& budget,
            int leafBlock = 1);

}  // namespace mbrt::detail
