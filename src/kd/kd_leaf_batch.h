// The primitive test of the kd kinds' leaves: the references of a leaf that
// pass the kd checks (time interval, MBKD §3.2; mailbox; the box at the
// ray's time) are collected and tested together by the kind's leaf format
// (leaves/leaf_format.h: plain references, whose runs of two or more
// triangles of one geometry are gathered four at a time into SIMD blocks at
// the ray's time, as in the BVH kinds' leaves). The hits are those of
// intersectPrimitive on each survivor (bit-identical; among equal t the
// first in geometry order wins, as in a BVH leaf sorted by geometry).
#pragma once

#include <cstdint>

#include "core/prim_ref.h"
#include "core/ray_query.h"
#include "leaves/gathered_runs.h"
#include "leaves/leaf_format.h"

namespace mbrt::detail {

class KdLeafBatch {
 public:
  // Enough for a leaf block's eight lanes on top of a part block left over.
  static constexpr uint32_t kCapacity = 16;

  bool empty() const { return n_ == 0; }
  bool full() const { return n_ == kCapacity; }
  // A full block's worth waits: testing it now lets its hits shorten the
  // ray before the leaf's next references are checked.
  bool holdsABlock() const { return n_ >= uint32_t(kLeafBlockWidth); }
  void add(PrimRef p) { prims_[n_++] = p; }

  // Tests the collected references and empties the batch: closest hit
  // (AnyHit = false: `hit` updated, ray.tfar shrinks; true when one was
  // found) or any hit. Counts one primitive test per reference, and the
  // gathered ones as block tests (as the BVH leaves count them).
  template <bool AnyHit, bool Count, LeafFormat Leaves>
  bool test(const Leaves& leaves, const SceneContext& ctx, RayQuery& ray, Hit* hit, TraversalCounters* counters,
            const typename Leaves::RayState& state) {
    const uint32_t n = n_;
    n_ = 0;
    if (n == 0) return false;
    sortByGeometry(n);
    if constexpr (Count) counters->primitiveTests += n;
    return leaves.template test<AnyHit, Count>(ctx, LeafRefs{prims_, n}, ray, state, hit, counters);
  }

 private:
  // Stable, so that one geometry's references keep their leaf order; the
  // leaf test takes one run per geometry.
  void sortByGeometry(uint32_t n) {
    for (uint32_t i = 1; i < n; ++i) {
      const PrimRef p = prims_[i];
      uint32_t j = i;
      for (; j > 0 && prims_[j - 1].geomID > p.geomID; --j) prims_[j] = prims_[j - 1];
      prims_[j] = p;
    }
  }

  PrimRef prims_[kCapacity];
  uint32_t n_ = 0;
};

}  // namespace mbrt::detail
