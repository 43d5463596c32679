// Leaf formats: how a tree's leaves are laid out and tested. A tree (the BVH
// kinds, msbvh, the kd kinds) finds the leaves a ray enters; the format it
// was built with tests them. Every format is one type in one file of this
// folder, with its lay-out (made from the tree's reference table after the
// build) and its test; a kind names the format it uses once, as a template
// argument (Embree names each node/leaf pair once; madmann91/bvh hands the
// leaf test to the traversal as a callback). Adding a format is adding a
// file here and naming it where a kind picks it.
//
// A format F has
//   using RayState = ...;                 what its tests share per ray, made once:
//   RayState rayState(const RayQuery&) const;
//   template <bool AnyHit, bool Count>
//   bool test(const SceneContext&, const LeafRefs&, RayQuery&, const RayState&, Hit*, TraversalCounters*) const;
//       closest hit (AnyHit = false: *hit updated, ray.tfar shrinks; true when
//       one was found) or any hit among the leaf's references, with exactly
//       the hits of intersectPrimitive on each (scene/primitive_intersect.h);
//       Count: counters is non-null, and the format adds its block tests;
//   size_t bytes() const;                 what its lay-out adds to the tree.
// A leaf it has not laid out (a reference kept in its node, a batch of a kd
// leaf's survivors, a leaf it could not block) is tested as plain
// references (reference_leaves.h), so every format answers every leaf.
#pragma once

#include <concepts>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/prim_ref.h"
#include "core/ray_query.h"
#include "mbrt/accel_stats.h"
#include "scene/scene_context.h"

namespace mbrt::detail {

// The references of one leaf a ray entered.
struct LeafRefs {
  static constexpr uint32_t kNoTable = 0xFFFFFFFFu;
  const PrimRef* prims;
  uint32_t count;
  // Index of prims[0] in the tree's reference table (what a format's
  // lay-out is found by), or kNoTable: a reference kept in its node, or
  // references gathered from elsewhere (a kd leaf's survivors).
  uint32_t first = kNoTable;
  bool inTable() const { return first != kNoTable; }
};

// A tree's leaves as a format lays them out: its reference table, and each
// leaf in the table as a range, in the tree's order.
struct LeafRange {
  uint32_t begin, count;
};
struct LeafTable {
  std::span<const PrimRef> prims;
  bool someInNodes = false;  // some one-reference leaves are kept in their node, not in `prims`
  std::vector<LeafRange> leaves;
  // A static tree's one time (`frozen`: every ray is traced then), for the
  // formats that lay out the primitives at it; none for motion trees.
  std::optional<float> fixedTime;
};

template <class F>
concept LeafFormat = requires(const F& f, const SceneContext& ctx, const LeafRefs& leaf, RayQuery& ray,
                              const typename F::RayState& state, Hit* hit, TraversalCounters* counters) {
  { f.rayState(ray) } -> std::convertible_to<typename F::RayState>;
  { f.template test<false, false>(ctx, leaf, ray, state, hit, counters) } -> std::same_as<bool>;
  { f.template test<true, true>(ctx, leaf, ray, state, hit, counters) } -> std::same_as<bool>;
  { f.bytes() } -> std::convertible_to<size_t>;
};

}  // namespace mbrt::detail
