// How the BVH family and msbvh answer core/inspect.h: walks over every
// lane with its time range and the references below it, and the raw bytes
// of the trees.
#pragma once

#include <cstring>
#include <algorithm>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include "bvh/nodes/wide_bvh.h"
#include "core/inspect.h"

namespace mbrt::detail {

// The time range lane `lane` of `node` serves, inside the node's `range`
// (tree parameter; the stored inclusive end is mapped back).
template <int N, bool Motion>
TimeRange laneRange(const WideBvh<N, Motion>& bvh, const WideNode<N, Motion>& node, int lane, TimeRange range) {
  if (!node.hasTimes()) return range;
  const LaneTimes<N>& t = bvh.times[node.times];
  return {std::max(range.lo, t.t0[lane]), std::min(range.hi, t.t1[lane])};
}

// Visits the lanes below `node` (serving `range`): fn(node, lane, lane's time
// range, references below the lane). Returns the references of the subtree
// (copies: inline leaves keep theirs in the nodes).
template <int N, bool Motion, class Fn>
std::vector<PrimRef> walkTimedLanes(const WideBvh<N, Motion>& bvh, uint32_t node, TimeRange range, const Fn& fn) {
  std::vector<PrimRef> all;
  const auto& n = bvh.nodes[node];
  for (int i = 0; i < N; ++i) {
    if (n.isEmpty(i)) continue;
    const TimeRange r = laneRange(bvh, n, i, range);
    PrimRef one;
    std::vector<PrimRef> below;
    if (n.isLeaf(i)) {
      const std::span<const PrimRef> refs = bvh.leafRefs(n, i, one);
      below.assign(refs.begin(), refs.end());
    } else {
      below = walkTimedLanes(bvh, n.child[i], r, fn);
    }
    fn(n, i, r, std::span<const PrimRef>(below));
    all.insert(all.end(), below.begin(), below.end());
  }
  return all;
}

// As walkTimedLanes, for trees without time ranges: fn(node, lane, references).
template <int N, bool Motion, class Fn>
std::vector<PrimRef> walkLanes(const WideBvh<N, Motion>& bvh, uint32_t node, const Fn& fn) {
  return walkTimedLanes(bvh, node, TimeRange{0.0f, 1.0f},
                        [&](const WideNode<N, Motion>& n, int lane, TimeRange, std::span<const PrimRef> below) {
                          fn(n, lane, below);
                        });
}

template <int N, bool Motion>
void appendBytes(const WideBvh<N, Motion>& bvh, std::vector<uint8_t>& out) {
  const size_t a = out.size(), nb = bvh.nodes.size() * sizeof(bvh.nodes[0]);
  const size_t np = bvh.prims.size() * sizeof(PrimRef), nt = bvh.times.size() * sizeof(LaneTimes<N>);
  out.resize(a + nb + np + nt);
  if (nb) std::memcpy(out.data() + a, bvh.nodes.data(), nb);
  if (np) std::memcpy(out.data() + a + nb, bvh.prims.data(), np);
  if (nt) std::memcpy(out.data() + a + nb + np, bvh.times.data(), nt);
}

}  // namespace mbrt::detail
