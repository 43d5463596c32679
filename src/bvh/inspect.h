// Debug access to a built BVH for tests: every lane with its box at a time
// and the references below it, and the raw bytes of the trees.
#pragma once

#include <cstring>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "bvh/wide_bvh.h"

namespace mbrt::detail {

struct LaneView {
  TimeRange range;                             // global times the tree serves
  std::function<Box3f(float globalTime)> box;  // as the node test computes it
  std::span<const PrimRef> below;              // references under the lane
};

class BvhInspect {
 public:
  virtual ~BvhInspect() = default;
  virtual void forEachLane(const std::function<void(const LaneView&)>& fn) const = 0;
  virtual std::vector<uint8_t> bytes() const = 0;
};

// Visits the lanes below `node`: fn(node, lane, references below the lane).
// Returns the reference range of the subtree (contiguous by construction).
template <int N, bool Motion, class Fn>
std::pair<uint32_t, uint32_t> walkLanes(const WideBvh<N, Motion>& bvh, uint32_t node, const Fn& fn) {
  uint32_t first = ~0u, end = 0;
  const auto& n = bvh.nodes[node];
  for (int i = 0; i < N; ++i) {
    if (n.isEmpty(i)) continue;
    std::pair<uint32_t, uint32_t> r{n.child[i], n.child[i] + n.count[i]};
    if (!n.isLeaf(i)) r = walkLanes(bvh, n.child[i], fn);
    fn(n, i, std::span<const PrimRef>(bvh.prims.data() + r.first, r.second - r.first));
    first = std::min(first, r.first);
    end = std::max(end, r.second);
  }
  return {first, end};
}

template <int N, bool Motion>
void appendBytes(const WideBvh<N, Motion>& bvh, std::vector<uint8_t>& out) {
  const size_t a = out.size(), nb = bvh.nodes.size() * sizeof(bvh.nodes[0]);
  out.resize(a + nb + bvh.prims.size() * sizeof(PrimRef));
  if (nb) std::memcpy(out.data() + a, bvh.nodes.data(), nb);
  if (!bvh.prims.empty()) std::memcpy(out.data() + a + nb, bvh.prims.data(), bvh.prims.size() * sizeof(PrimRef));
}

}  // namespace mbrt::detail
