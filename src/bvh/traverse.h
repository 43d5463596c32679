// Stack-based, front-to-back traversal of a WideBvh. The node test is
// written once over Pack<W> (simd.h): AVX2 runs an 8-wide node in one pack,
// SSE a 4-wide node, the scalar pack anything. Slab distances follow Ize
// (JCGT 2013, "Robust BVH Ray Traversal"): (plane - org) * rdir with the far
// distance scaled by 1 + 2*gamma(3); node bounds are already widened.
#pragma once

#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "core/cache_size.h"
#include "core/robust_slab.h"
#include "bvh/nodes/wide_bvh.h"
#include "leaves/leaf_format.h"

namespace mbrt::detail {


// The ray in the form the node test wants, broadcast to W lanes.
template <int W>
struct NodeRay {
  Pack<W> org[3], rdir[3], tnear, time;
  float t, omt;            // the time, and 1 - t (motion nodes' grid weights)
  alignas(16) float orgs[4], rdirs[4];  // org and rdir as scalars (motion nodes; [3] = 0)
  // |org| < 2^60 and |rdir| < 2^56: a motion node's distance terms cannot
  // overflow (motion_node.h, distanceTerms).
  bool tame;
  int nearPlane[3];        // 0: lower plane is the entry plane; 1: upper

  // Inlined: each tree type reads only its members, the others are dropped.
  [[gnu::always_inline]] NodeRay(const RayQuery& ray, float boxTime) : t(boxTime), omt(1.0f - boxTime) {
    using P4 = Pack<4>;  // org and rdir as packs, lane 3 cleared: one compare each for `tame`
    static_assert(offsetof(RayQuery, org) + 16 <= sizeof(RayQuery) &&
                  offsetof(RayQuery, rdir) + 16 <= sizeof(RayQuery));
    const P4 o = clearLastLane(P4::loadu(&ray.org.x)), d = clearLastLane(P4::loadu(&ray.rdir.x));
    o.store(orgs);
    d.store(rdirs);
    tame = (lessMask(abs(o), P4::set1(0x1p60f)) & lessMask(abs(d), P4::set1(0x1p56f))) == 0xFu;
    for (int a = 0; a < 3; ++a) {
      org[a] = Pack<W>::set1(ray.org[a]);
      rdir[a] = Pack<W>::set1(ray.rdir[a]);
      nearPlane[a] = std::signbit(ray.rdir[a]) ? 1 : 0;
    }
    tnear = Pack<W>::set1(ray.tnear);
    time = Pack<W>::set1(boxTime);
  }
};

// Slab distances (plane - org) * rdir of lanes [base, base + W) on one
// axis, entry plane first. Static nodes: float planes. Motion nodes
// (motion_node.h): the plane is at + q0 * w0 + q1 * w1 (gridAt), so its
// distance is A + q0 * B0 + q1 * B1 with A = (at - org) * rdir and B = w *
// rdir per node and axis: two FMAs per plane on the decoded levels, the
// ray's subtraction and product folded into the node's scalars.
template <int W, int N>
inline void slabDistances(const WideNode<N, false>& node, const NodeRay<W>& r, int a, int base, Pack<W>& tn,
                          Pack<W>& tf) {
  const int nearK = r.nearPlane[a];
  tn = (Pack<W>::load(&node.plane[a][nearK][base]) - r.org[a]) * r.rdir[a];
  tf = (Pack<W>::load(&node.plane[a][1 - nearK][base]) - r.org[a]) * r.rdir[a];
}
template <int W, int N>
inline void slabDistances(const WideNode<N, true>& node, int a, int base, int nearK, Pack<W> A, Pack<W> B0,
                          Pack<W> B1, Pack<W>& tn, Pack<W>& tf) {
  using P = Pack<W>;
  // The entry plane's levels at t = 0 and t = 1 are 2 * N bytes apart, and
  // so are the exit plane's: one offset per axis, the rest displacements.
  const uint8_t* levels = &node.q[a][0][base];
  const uint8_t* nearLevels = levels + nearK * N;
  const uint8_t* farLevels = levels + (N - nearK * N);
  tn = fmadd(P::loadBytes(nearLevels + 2 * N), B1, fmadd(P::loadBytes(nearLevels), B0, A));
  tf = fmadd(P::loadBytes(farLevels + 2 * N), B1, fmadd(P::loadBytes(farLevels), B0, A));
}

// Bit i set when lane i is hit within [tnear, tfar] (and, for a
// spatial-temporal node, serves the ray's time); dist[i] = entry distance.
template <int W, int N, bool Motion>
inline uint32_t intersectNode(const WideNode<N, Motion>& node, const NodeRay<W>& r, float tfar, float* dist,
                              const LaneTimes<N>* times = nullptr) {
  static_assert(N % W == 0);
  using P = Pack<W>;
  const P far = P::set1(tfar), inf = P::set1(kInf);
  alignas(16) float A[4], B0[4], B1[4];
  if constexpr (Motion) node.distanceTerms(r.t, r.omt, r.orgs, r.rdirs, r.tame, A, B0, B1);
  uint32_t mask = 0;
  for (int base = 0; base < N; base += W) {
    P tn = r.tnear, tf = inf;
    for (int a = 0; a < 3; ++a) {
      P dn, df;
      if constexpr (Motion)
        slabDistances<W>(node, a, base, r.nearPlane[a], P::set1(A[a]), P::set1(B0[a]), P::set1(B1[a]), dn, df);
      else
        slabDistances<W>(node, r, a, base, dn, df);
      tn = vmax(dn, tn);
      tf = vmin(df, tf);
    }
    tf = vmin(robustFar(tf, Motion ? kRobustGammaGrid : kRobustGamma2), far);
    uint32_t hit = lessEqualMask(tn, tf);
    if (times) hit &= lessEqualMask(P::load(&times->t0[base]), r.time) & lessMask(r.time, P::load(&times->t1[base]));
    mask |= hit << base;
    tn.store(dist + base);
  }
  if constexpr (Motion) mask &= node.occupiedLanes();
  return mask;
}

// A lane the ray enters: an inner node, a leaf of references in the tree's
// table, or one reference that its node kept (kInlineLeaf, wide_node.h).
struct TraversalItem {
  static constexpr uint32_t kInline = 0x80000000u;  // in count: inline reference, geomID below
  uint32_t child;  // node index, first reference, or (inline) primID
  uint32_t count;  // 0: inner node; leaf size; or kInline | geomID
  float dist;      // entry distance

  bool inner() const { return count == 0; }
  uint32_t leafSize() const { return count & kInline ? 1u : count; }
  // The leaf's references: in `table`, or the inline one, made in `one`.
  const PrimRef* references(const PrimRef* table, PrimRef& one) const {
    if (!(count & kInline)) return table + child;
    one = {count & ~kInline, child};
    return &one;
  }
};

// The item of a lane of `node` entered at `dist`. Nodes with a leafGeom can
// keep a one-reference leaf inline (wide_node.h); others (msbvh) cannot.
template <class Node>
inline TraversalItem laneItem(const Node& node, int lane, float dist) {
  if constexpr (requires { node.leafGeom; })
    if (node.count[lane] == kInlineLeaf) return {node.child[lane], TraversalItem::kInline | node.leafGeom, dist};
  return {node.child[lane], node.count[lane], dist};
}

// Asks for the cache lines of [p, p + bytes).
[[gnu::always_inline]] inline void prefetchLines(const void* p, size_t bytes) {
  const char* c = static_cast<const char*>(p);
  for (size_t line = 0; line < bytes; line += 64) __builtin_prefetch(c + line);
}

// Whether prefetching pays: the tree's nodes do not fit in a core's cache
// (core/cache_size.h). Prefetching the hit children of trees that do costs
// their instructions and gains nothing (docs/performance.md).
inline bool prefetchPays(size_t nodeBytes) { return nodeBytes > kCoreCacheBytes; }

// The cache lines a visit of node i of `nodeAt` reads: the node itself;
// nothing when `on` is false.
template <class NodeAt>
struct NodeLines {
  const NodeAt& nodeAt;
  bool on;
  void operator()(uint32_t i) const {
    const auto& node = nodeAt(i);
    prefetchLines(&node, sizeof(node));
  }
};

// Asks for the lines of the inner children in `lanes` of `node`.
template <class Node, class Prefetch>
[[gnu::always_inline]] inline void prefetchChildren(const Node& node, uint32_t lanes, const Prefetch& prefetch) {
  if (!prefetch.on) return;
  for (; lanes != 0; lanes &= lanes - 1) {
    const int lane = __builtin_ctz(lanes);
    if (node.count[lane] == kInnerLane) prefetch(node.child[lane]);
  }
}

// The front-to-back loop of every N-wide tree (the BVH kinds and `msbvh`).
// nodeAt(i) gives node i (its lanes, as laneItem reads them); testNode(node,
// i, dist) returns the mask of lanes the ray enters, with their entry
// distances in dist; leaf(item) tests a leaf's references and returns true
// on a hit (for AnyHit: the ray is occluded, the walk stops); prefetch(i)
// asks for the cache lines a visit of node i reads (when prefetch.on). The nearest child is
// visited next, the others go on the stack farthest first.
template <bool AnyHit, bool Count, int N, class NodeAt, class TestNode, class Leaf, class Prefetch>
bool wideTraverse(uint32_t stackSize, const RayQuery& ray, TraversalCounters* counters, NodeAt&& nodeAt,
                  TestNode&& testNode, Leaf&& leaf, Prefetch&& prefetch) {
  constexpr uint32_t kLocalStack = 256;
  TraversalItem local[kLocalStack];
  std::vector<TraversalItem> big;
  TraversalItem* stack = local;
  if (stackSize + 1 > kLocalStack) {  // + 1: a node's lanes are sorted on the stack
    big.resize(stackSize + 1);
    stack = big.data();
  }
  alignas(32) float dist[N];
  bool found = false;
  uint32_t sp = 0;
  stack[sp++] = {0, 0, ray.tnear};
  while (sp != 0) {
    TraversalItem item = stack[--sp];
    if (!AnyHit && item.dist > ray.tfar) continue;
    while (true) {
      if (item.inner()) {
        const auto& node = nodeAt(item.child);
        if constexpr (Count) {
          ++counters->nodesVisited;
          counters->boxTests += N;
        }
        uint32_t mask = testNode(node, item.child, dist);
        if (mask == 0) break;
        int lane = __builtin_ctz(mask);
        mask &= mask - 1;
        if (mask == 0) {
          item = laneItem(node, lane, dist[lane]);
          continue;
        }
        // Two or more lanes: their nodes are fetched into the cache now, so
        // that the loads of the one visited next and of those popped later
        // overlap this node's work (as Embree prefetches each hit child).
        prefetchChildren(node, mask | 1u << lane, prefetch);
        // The nearest is visited next, the others are pushed farthest
        // first. Two lanes (the common case) take one compare; more are
        // insertion-sorted in place on the stack, ties keeping lane order,
        // as a stable descending sort would.
        TraversalItem first = laneItem(node, lane, dist[lane]);
        lane = __builtin_ctz(mask);
        mask &= mask - 1;
        TraversalItem second = laneItem(node, lane, dist[lane]);
        if (mask == 0) {
          if (first.dist < second.dist) {
            stack[sp++] = second;
            item = first;
          } else {
            stack[sp++] = first;
            item = second;
          }
          continue;
        }
        lane = __builtin_ctz(mask);
        mask &= mask - 1;
        TraversalItem third = laneItem(node, lane, dist[lane]);
        if (mask == 0) {
          // Three lanes (the next most common case): sorted in registers by
          // adjacent exchanges on strictly nearer, which keep ties in lane
          // order as the sort below does.
          if (first.dist < second.dist) std::swap(first, second);
          if (second.dist < third.dist) std::swap(second, third);
          if (first.dist < second.dist) std::swap(first, second);
          stack[sp++] = first;
          stack[sp++] = second;
          item = third;
          continue;
        }
        const uint32_t base = sp;
        stack[sp++] = first;
        stack[sp++] = second;
        if (first.dist < second.dist) std::swap(stack[base], stack[base + 1]);
        mask |= 1u << lane;  // the third is inserted with the rest
        do {
          lane = __builtin_ctz(mask);
          mask &= mask - 1;
          const TraversalItem h = laneItem(node, lane, dist[lane]);
          uint32_t j = sp++;
          while (j > base && stack[j - 1].dist < h.dist) {  // sort by descending distance
            stack[j] = stack[j - 1];
            --j;
          }
          stack[j] = h;
        } while (mask != 0);
        item = stack[--sp];
        continue;
      }
      if constexpr (Count) {
        ++counters->leavesVisited;
        counters->primitiveTests += item.leafSize();
      }
      if (leaf(item)) {
        if constexpr (AnyHit) return true;
        found = true;
      }
      break;
    }
  }
  return found;
}

// traverse (below) of a tree whose nodes have lane time ranges (TimedLanes:
// stbvh's spatial-temporal nodes) or of one without (the others, whose
// visits then skip the lanes' time check).
template <bool AnyHit, bool Count, bool TimedLanes, int N, bool Motion, LeafFormat Leaves>
bool traverseTree(const WideBvh<N, Motion>& bvh, const Leaves& leaves, const SceneContext& ctx, RayQuery& nodeRay,
                  RayQuery& leafRay, float boxTime, Hit* hit, TraversalCounters* counters) {
  const NodeRay<packWidth<N>()> r(nodeRay, boxTime);
  const typename Leaves::RayState state = leaves.rayState(leafRay);
  const auto nodeAt = [&](uint32_t i) -> const WideNode<N, Motion>& { return bvh.nodes[i]; };
  return wideTraverse<AnyHit, Count, N>(
      bvh.stackSize, nodeRay, counters, nodeAt,
      [&](const WideNode<N, Motion>& node, uint32_t, float* dist) {
        const LaneTimes<N>* times = nullptr;
        if constexpr (TimedLanes)
          if (node.hasTimes()) times = &bvh.times[node.times];
        return intersectNode<packWidth<N>()>(node, r, nodeRay.tfar, dist, times);
      },
      [&](const TraversalItem& item) {
        PrimRef one;
        const LeafRefs refs{item.references(bvh.prims.data(), one), item.leafSize(),
                            item.count & TraversalItem::kInline ? LeafRefs::kNoTable : item.child};
        const bool found = leaves.template test<AnyHit, Count>(ctx, refs, leafRay, state, hit, counters);
        if constexpr (!AnyHit) nodeRay.tfar = leafRay.tfar;
        return found;
      },
      NodeLines<decltype(nodeAt)>{nodeAt, prefetchPays(bvh.nodes.size() * sizeof(WideNode<N, Motion>))});
}

// Closest hit (AnyHit = false: `hit` updated, ray.tfar shrinks) or any hit
// of a wide BVH whose leaves are laid out in `leaves` (a leaf format,
// leaves/leaf_format.h). boxTime is the ray's time in the tree's time
// parameter; the leaf test uses ray.time. Count adds nodes and leaves
// visited, box tests and primitive tests.
//
// The nodes may be tested with another ray than the leaves, of the same
// parameter t: a near-rigid cluster's tree (cluster_bvh.h) has its nodes in
// the cluster's frame and its leaves in world space. `nodeRay` and
// `leafRay` may be the same object; a hit shortens both.
template <bool AnyHit, bool Count, int N, bool Motion, LeafFormat Leaves>
bool traverse(const WideBvh<N, Motion>& bvh, const Leaves& leaves, const SceneContext& ctx, RayQuery& nodeRay,
              RayQuery& leafRay, float boxTime, Hit* hit, TraversalCounters* counters) {
  if (bvh.empty()) return false;
  if (bvh.times.empty())
    return traverseTree<AnyHit, Count, false>(bvh, leaves, ctx, nodeRay, leafRay, boxTime, hit, counters);
  return traverseTree<AnyHit, Count, true>(bvh, leaves, ctx, nodeRay, leafRay, boxTime, hit, counters);
}

template <bool AnyHit, bool Count, int N, bool Motion, LeafFormat Leaves>
bool traverse(const WideBvh<N, Motion>& bvh, const Leaves& leaves, const SceneContext& ctx, RayQuery& ray,
              float boxTime, Hit* hit, TraversalCounters* counters) {
  return traverse<AnyHit, Count>(bvh, leaves, ctx, ray, ray, boxTime, hit, counters);
}

}  // namespace mbrt::detail
