// A ray through one cluster (Günther et al. 2006 §3): the cluster's world box
// at the ray's time first, then the ray in the cluster's local frame
// (scene/instance_space.h, the map interpolated at its time) down the
// cluster's fuzzy tree; leaf triangles are tested in world space at the ray's
// time (scene/primitive_intersect.h), so a hit shortens the world ray and the
// local one alike (same parameter t). A leaf's triangles are tested
// together in the format `leaves` (kd/kd_leaf_batch.h); `state` is its
// per-ray state, made once per ray.
#pragma once

#include "fuzzykd/cluster.h"
#include "kd/kd_traverse.h"
#include "scene/instance_space.h"

namespace mbrt::detail {

template <bool AnyHit, bool Count, LeafFormat Leaves>
bool traverseCluster(const SceneContext& ctx, const Cluster& c, RayQuery& ray, Hit* hit,
                     TraversalCounters* counters, const Leaves& leaves, const typename Leaves::RayState& state) {
  const Geometry& geo = ctx.geometry(c.geomID);
  if constexpr (Count) ++counters->boxTests;
  if (!rayHitsBox(ray, c.boxAt(geo, ray.time))) return false;
  RayQuery local;
  // No frame: hits are found in world space. A flat map reaches nothing.
  if (!toLocalSpace(c.mapAt(geo, ray.time), ray, local, nullptr)) return false;
  const FuzzyTree& tree = c.tree;
  KdMailbox mailbox;
  return kdWalk<AnyHit, Count>(tree, local, counters, [&](const KdNode& n) {
    KdLeafBatch batch;
    bool found = false;
    const uint32_t* refs = tree.refs.data() + n.first();
    for (uint32_t i = 0, cnt = n.count(); i < cnt; ++i) {
      const uint32_t prim = refs[i];
      if (mailbox.seen(prim)) continue;
      batch.add(c.prims[prim]);
      if (batch.full() && batch.test<AnyHit, Count>(leaves, ctx, ray, hit, counters, state)) {
        if constexpr (AnyHit) return true;
        found = true;
      }
    }
    found = batch.test<AnyHit, Count>(leaves, ctx, ray, hit, counters, state) || found;
    if (found) local.tfar = ray.tfar;
    return found;
  });
}

}  // namespace mbrt::detail
