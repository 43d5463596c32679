// SIMD leaves for `mbkd` (our extension of MBKD §3.2, not in the paper).
//
// The paper's leaf skips a reference whose cell-wide time interval excludes
// the ray's time and tests every other one. Here each leaf's references are
// sorted by interval start and packed 8 to a block, each lane holding the
// reference's interval and its primitive's linear bounds over that interval
// (extrapolated to t = 0 and 1, as bvh-interp's nodes store them). One block
// test does, for 8 references at once, the interval check and a slab test of
// the ray against the primitive's box at the ray's time; only the surviving
// lanes reach the mailbox and the primitive test. A block none of whose
// intervals holds the ray's time stops after its first 64 bytes.
#pragma once

#include <algorithm>
#include <functional>
#include <vector>

#include "core/robust_slab.h"
#include "core/simd.h"
#include "core/prim_ref.h"
#include "mbrt/math.h"
#include "core/ray_query.h"
#include "kd/kd_node.h"

namespace mbrt::detail {

inline constexpr int kKdBlockLanes = 8;

struct alignas(32) KdLeafBlock {
  float t0[kKdBlockLanes], t1[kKdBlockLanes];  // lane alive in [t0, t1]; empty lanes never
  // plane[axis][0|1][lane]: lower|upper side at t = 0; [2|3]: its change to t = 1.
  float plane[3][4][kKdBlockLanes];
  PrimRef prim[kKdBlockLanes];  // the primitive itself: no indirection before its test
};
static_assert(sizeof(KdLeafBlock) == 512);

// The blocks of a kd-tree's leaves. `cells` is the tree without its
// references, each leaf's word = first block and count = number of blocks.
struct KdLeafBlocks {
  KdTree cells;
  std::vector<KdLeafBlock> blocks;

  size_t bytes() const { return cells.bytes() + blocks.size() * sizeof(KdLeafBlock); }

  // The references' primitives are prims[ref.prim]; bounds(ref.prim,
  // [t0, t1]) = conservative (widened) linear bounds of the primitive over
  // the reference's interval, at t = 0 and t = 1.
  static KdLeafBlocks build(const KdTree& tree, const PrimRef* prims,
                            const std::function<LBounds(uint32_t, TimeRange)>& bounds);

  // Starts loading a leaf's blocks (their interval lines) before the test.
  void prefetch(const KdNode& leaf) const {
    for (uint32_t k = leaf.first(), end = leaf.first() + std::min(leaf.count(), 8u); k < end; ++k)
      detail::prefetch(&blocks[k]);
  }
};

// The kd mailbox (kd_traverse.h) keyed by the primitive itself.
struct KdPrimMailbox {
  PrimRef slot[16];
  KdPrimMailbox() {
    for (PrimRef& s : slot) s = {kInvalidId, kInvalidId};
  }
  // True when `p` was tested already; records it otherwise.
  bool seen(PrimRef p) {
    PrimRef& s = slot[(p.primID ^ (p.geomID * 0x9e3779b1u)) & 15u];
    if (s.primID == p.primID && s.geomID == p.geomID) return true;
    s = p;
    return false;
  }
};

// The ray broadcast for the block test.
struct KdBlockRay {
  static constexpr int W = packWidth<kKdBlockLanes>();
  Pack<W> org[3], rdir[3], tnear, time;
  int nearPlane[3];  // 0: the lower side is entered first; 1: the upper

  explicit KdBlockRay(const RayQuery& ray) {
    for (int a = 0; a < 3; ++a) {
      org[a] = Pack<W>::set1(ray.org[a]);
      rdir[a] = Pack<W>::set1(ray.rdir[a]);
      nearPlane[a] = std::signbit(ray.rdir[a]) ? 1 : 0;
    }
    tnear = Pack<W>::set1(ray.tnear);
    time = Pack<W>::set1(ray.time);
  }
};

// Bit i set when lane i is alive at the ray's time; `boxHits` receives the
// alive lanes whose box at that time meets the ray over [tnear, tfar]
// (robust slab distances, Ize 2013, as in bvh/traverse.h).
inline uint32_t kdBlockTest(const KdLeafBlock& b, const KdBlockRay& r, float tfar, uint32_t& boxHits) {
  constexpr int W = KdBlockRay::W;
  using P = Pack<W>;
  uint32_t alive = 0;
  for (int base = 0; base < kKdBlockLanes; base += W)
    alive |= (lessEqualMask(P::load(&b.t0[base]), r.time) & lessEqualMask(r.time, P::load(&b.t1[base]))) << base;
  boxHits = 0;
  if (alive == 0) return 0;
  const P far = P::set1(tfar), inf = P::set1(kInf);
  for (int base = 0; base < kKdBlockLanes; base += W) {
    P tn = r.tnear, tf = inf;
    for (int a = 0; a < 3; ++a) {
      const int nearK = r.nearPlane[a], farK = 1 - nearK;
      const P lo = fmadd(r.time, P::load(&b.plane[a][2 + nearK][base]), P::load(&b.plane[a][nearK][base]));
      const P hi = fmadd(r.time, P::load(&b.plane[a][2 + farK][base]), P::load(&b.plane[a][farK][base]));
      tn = vmax((lo - r.org[a]) * r.rdir[a], tn);
      tf = vmin((hi - r.org[a]) * r.rdir[a], tf);
    }
    tf = vmin(robustFar(tf), far);
    boxHits |= lessEqualMask(tn, tf) << base;
  }
  boxHits &= alive;
  return alive;
}

}  // namespace mbrt::detail
