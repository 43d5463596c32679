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
//
// A leaf whose references live for short intervals (many keys: a skinned
// character's triangles cross many cells over the shutter) is cut into 2^k
// equal time slices, each with the blocks of the references alive in it (a
// reference spanning several slices is in each): a ray tests the blocks of
// its time's slice only. The slicing per leaf minimises the blocks a ray at
// a uniform time tests, within a bound on the leaf's blocks (build, in
// kd_leaf_blocks.cpp).
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

// The time slice of `time` in [0, 1] among `slices` (a power of two): slice
// i holds [i / slices, (i + 1) / slices], time 1 the last. Exact: time *
// slices and i / slices are powers of two apart.
inline uint32_t kdSliceOf(float time, uint32_t slices) {
  return std::min(uint32_t(time * float(slices)), slices - 1u);
}
inline float kdSliceStart(uint32_t slice, uint32_t slices) { return float(slice) / float(slices); }

// The blocks of a kd-tree's leaves. `cells` is the tree without its
// references; a leaf's word indexes `sliceStarts` and its count is its
// number of time slices S: the blocks of slice i are [sliceStarts[word +
// i], sliceStarts[word + i + 1]).
struct KdLeafBlocks {
  KdTree cells;
  std::vector<KdLeafBlock> blocks;
  std::vector<uint32_t> sliceStarts;

  size_t bytes() const {
    return cells.bytes() + blocks.size() * sizeof(KdLeafBlock) + sliceStarts.size() * sizeof(uint32_t);
  }

  struct Range {
    uint32_t begin, end;
  };
  // The blocks of leaf `leaf` that a ray at `time` tests (an empty leaf, of
  // count 0, has one slice start and the end, equal).
  Range blocksAt(const KdNode& leaf, float time) const {
    const uint32_t* s = sliceStarts.data() + leaf.first() + kdSliceOf(time, leaf.count());
    return {s[0], s[1]};
  }
  // fn(prim, [t0, t1]) once per reference of the leaf (a reference in
  // several slices is reported from the first).
  template <class Fn>
  void forEachReference(const KdNode& leaf, const Fn& fn) const {
    const uint32_t slices = leaf.count();
    for (uint32_t i = 0; i < slices; ++i)
      for (uint32_t k = sliceStarts[leaf.first() + i]; k < sliceStarts[leaf.first() + i + 1]; ++k)
        for (int lane = 0; lane < kKdBlockLanes; ++lane) {
          const KdLeafBlock& b = blocks[k];
          // In slice i - 1 too when it starts at or before slice i's start.
          const bool earlier = i > 0 && b.t0[lane] <= kdSliceStart(i, slices);
          if (b.t0[lane] <= b.t1[lane] && !earlier) fn(b.prim[lane], TimeRange{b.t0[lane], b.t1[lane]});
        }
  }

  // The references' primitives are prims[ref.prim]; bounds(ref.prim,
  // [t0, t1]) = conservative (widened) linear bounds of the primitive over
  // the reference's interval, at t = 0 and t = 1.
  static KdLeafBlocks build(const KdTree& tree, const PrimRef* prims,
                            const std::function<LBounds(uint32_t, TimeRange)>& bounds);

  // Starts loading the blocks' first lines (their intervals) before the test.
  void prefetch(Range r) const {
    for (uint32_t k = r.begin, end = std::min(r.end, r.begin + 8u); k < end; ++k) detail::prefetch(&blocks[k]);
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
