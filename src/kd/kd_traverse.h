// Front-to-back kd-tree traversal with a (node, tmin, tmax) stack.
//
// Hits: a leaf's reference is tested against the whole remaining ray
// [tnear, tfar] and a hit beyond the cell is kept as the current closest;
// a cell is skipped only when it starts beyond tfar. That is the
// "hits only inside the current cell" rule in its equivalent form: the
// reported hit is never one a nearer cell could beat, and a duplicated
// primitive tested once (mailbox) never needs a retest in a later cell.
// References whose time interval excludes the ray's time are skipped
// (MBKD §3.2). Child ranges overlap by a relative 2^-16 around the split
// distance, so rounding never opens a gap between cells; rays parallel to
// a plane (or lying in it) go to the side(s) they lie in.
#pragma once

#include <cmath>

#include "core/robust_slab.h"
#include "kd/kd_leaf_batch.h"
#include "kd/kd_node.h"

namespace mbrt::detail {

inline constexpr float kKdSplitSlack = 1.0f / (1 << 16);

// Clips [tnear, tfar] to a box; false when the ray misses it. NaN slab
// distances (origin on a face, direction parallel) leave the range as is.
// Always inlined: it is called per node and per reference of the kd walks,
// where a call costs more than the test (docs/performance.md).
[[gnu::always_inline]] inline bool clipToBox(const RayQuery& ray, const Box3f& box, float& tmin, float& tmax) {
  tmin = ray.tnear;
  tmax = ray.tfar;
  for (int a = 0; a < 3; ++a) {
    float t0 = (box.lower[a] - ray.org[a]) * ray.rdir[a];
    float t1 = (box.upper[a] - ray.org[a]) * ray.rdir[a];
    if (t0 > t1) std::swap(t0, t1);
    if (t0 > tmin) tmin = t0;
    t1 = enlargeFar(t1, kKdSplitSlack);
    if (t1 < tmax) tmax = t1;
  }
  return tmin <= tmax;
}

// A tiny direct-mapped mailbox of primitives already tested by this ray.
struct KdMailbox {
  uint32_t slot[16];
  KdMailbox() {
    for (uint32_t& s : slot) s = ~0u;
  }
  // True when `prim` was tested already; records it otherwise.
  bool seen(uint32_t prim) {
    uint32_t& s = slot[prim & 15u];
    if (s == prim) return true;
    s = prim;
    return false;
  }
};

// Slab test of the ray's remaining [tnear, tfar] against a box.
[[gnu::always_inline]] inline bool rayHitsBox(const RayQuery& ray, const Box3f& box) {
  float tmin, tmax;
  return clipToBox(ray, box, tmin, tmax);
}

// Accepts every reference that passed its time interval.
struct KdNoRefFilter {
  static constexpr bool kActive = false;
  bool operator()(uint32_t, const RayQuery&) const { return true; }
};

// One inner node of front-to-back traversal over [tmin, tmax]: returns the
// child to visit first (narrowing tmax to it) and pushes the other side when
// the ray reaches it too. The ray is on one side of the plane for t < tsplit
// and on the other beyond, whatever the sign of t (tnear may be negative);
// rays in the plane, or whose distance overflows, visit both sides.
template <class Push>
inline uint32_t kdInnerStep(const KdNode& n, uint32_t node, const RayQuery& ray, float tmin, float& tmax,
                            Push&& push) {
  const int a = n.axis();
  const float p = n.split();
  const float o = ray.org[a], da = ray.dir[a];
  const uint32_t left = node + 1, right = n.rightChild();
  if (da == 0.0f && o != p) return o < p ? left : right;  // parallel: the origin's side
  const float tsplit = (p - o) * ray.rdir[a];
  if (da == 0.0f || std::isnan(tsplit)) {
    push(right, tmin, tmax);
    return left;
  }
  const uint32_t before = da > 0.0f ? left : right, after = da > 0.0f ? right : left;
  const float slack = std::fabs(tsplit) * kKdSplitSlack;
  const float lo = tsplit - slack, hi = tsplit + slack;
  if (lo > tmax) return before;
  if (hi < tmin) return after;
  push(after, std::max(tmin, lo), tmax);
  tmax = std::min(tmax, hi);
  return before;
}

// The walk: visits the cells the ray crosses, front to back, and calls
// leaf(node) for each leaf; leaf returns true when it found a hit (any hit:
// the walk stops). Counts one node visit and one box test per node.
// Tree: a KdTree or anything with its `nodes` and `root` (the fuzzy trees).
template <bool AnyHit, bool Count, class Tree, class Leaf>
bool kdWalk(const Tree& tree, RayQuery& ray, TraversalCounters* counters, Leaf&& leaf) {
  if (tree.nodes.empty()) return false;
  float tmin, tmax;
  if (!clipToBox(ray, tree.root, tmin, tmax)) return false;
  struct Item {
    uint32_t node;
    float tmin, tmax;
  };
  Item stack[64];
  int sp = 0;
  bool found = false;
  uint32_t node = 0;
  while (true) {
    const KdNode& n = tree.nodes[node];
    if constexpr (Count) {
      ++counters->nodesVisited;
      ++counters->boxTests;
    }
    if (!n.isLeaf()) {
      node = kdInnerStep(n, node, ray, tmin, tmax, [&](uint32_t child, float t0, float t1) {
        stack[sp++] = {child, t0, t1};
      });
      continue;
    }
    if constexpr (Count) counters->leavesVisited += n.count() != 0;
    if (leaf(n)) {
      if constexpr (AnyHit) return true;
      found = true;
    }
    // Next cell that can still hold a closer hit.
    while (true) {
      if (sp == 0) return found;
      const Item& it = stack[--sp];
      if (!AnyHit && it.tmin > ray.tfar) continue;
      node = it.node;
      tmin = it.tmin;
      tmax = std::min(it.tmax, enlargeFar(ray.tfar, kKdSplitSlack));
      break;
    }
  }
}

// Closest hit (AnyHit = false: `hit` updated, ray.tfar shrinks) or any hit,
// the leaves tested in the format `leaves` (leaves/leaf_format.h).
// prims[i] is the primitive of reference index i. `filter(prim, ray)` may
// reject a reference before its test (counted as a box test when active).
// A leaf's surviving references are tested together (kd_leaf_batch.h).
template <bool AnyHit, bool Count, LeafFormat Leaves, class Filter = KdNoRefFilter>
bool kdTraverse(const KdTree& tree, const Leaves& leaves, const SceneContext& ctx, const PrimRef* prims,
                RayQuery& ray, Hit* hit, TraversalCounters* counters, const Filter& filter = {}) {
  KdMailbox mailbox;
  const typename Leaves::RayState state = leaves.rayState(ray);
  const float time = ray.time;
  return kdWalk<AnyHit, Count>(tree, ray, counters, [&](const KdNode& n) {
    KdLeafBatch batch;
    bool found = false;
    const KdLeafRef* refs = tree.refs.data() + n.first();
    for (uint32_t i = 0, c = n.count(); i < c; ++i) {
      const KdLeafRef& r = refs[i];
      if (time < r.t0 || time > r.t1 || mailbox.seen(r.prim)) continue;
      if constexpr (Filter::kActive) {
        if constexpr (Count) ++counters->boxTests;
        if (!filter(r.prim, ray)) continue;
      }
      batch.add(prims[r.prim]);
      if (batch.full() && batch.test<AnyHit, Count>(leaves, ctx, ray, hit, counters, state)) {
        if constexpr (AnyHit) return true;
        found = true;
      }
    }
    return batch.test<AnyHit, Count>(leaves, ctx, ray, hit, counters, state) || found;
  });
}

}  // namespace mbrt::detail
