#include "kd/mbkd.h"

#include <bit>

#include "core/inspect.h"
#include "core/sah_sums.h"
#include "core/traced_structure.h"
#include "kd/kd_leaf_batch.h"
#include "kd/kd_leaf_blocks.h"
#include "kd/kd_traverse.h"
#include "leaves/reference_leaves.h"
#include "scene/primitive_bounds.h"
#include "scene/scene_area.h"

namespace mbrt::detail {
namespace {

// Leaves: the survivors of each leaf's block tests in the format `Leaves`.
template <LeafFormat Leaves>
class Mbkd final : public TracedStructure<Mbkd<Leaves>>, public Inspect {
 public:
  explicit Mbkd(const SceneContext& ctx) : ctx_(ctx) {
    const std::vector<PrimRef> all = ctx.primitives();
    // Primitives whose bounds are not finite can never be hit inside a
    // finite cell; the BVHs drop them too.
    for (const PrimRef& p : all) {
      const LBounds b = linearBounds(ctx, p, {0.0f, 1.0f});
      if (isUsable(b)) prims_.push_back(p);
    }
    ctx.budget().charge(prims_.size() * sizeof(PrimRef), "the kd-tree primitive list");
    {
      const KdPaths paths = KdPaths::fromContext(ctx, prims_);  // the build's key boxes
      ctx.budget().charge(paths.bytes(), "the kd-tree key boxes");
      Box3f root;  // extended root cell: every primitive over the whole shutter
      for (uint32_t i = 0; i < paths.size(); ++i) root.extend(paths.hull(i));
      KdBuildParams params;
      params.sah.traversal = ctx.options().traversalCost * kBlockStepWeight;
      buildKdTree(paths, root, params, ctx.budget(), tree_, stats_);
    }
    computeSah();
    ctx.budget().charge(tree_.refs.size() / kKdBlockLanes * sizeof(KdLeafBlock), "the kd-tree leaf blocks");
    blocks_ = KdLeafBlocks::build(tree_, prims_.data(), [&](uint32_t prim, TimeRange r) { return referenceBounds(prim, r); });
    tree_.refs = {};  // now in the blocks
  }

  template <bool AnyHit, bool Count>
  bool trace(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    return traceBlocks<AnyHit, Count>(ray, hit, counters);
  }

  void fillStats(AccelStats& s) const override {
    sums_.fill(s, sceneArea_);
    s.bytes = tree_.bytes() + blocks_.bytes() + prims_.size() * sizeof(PrimRef);
  }

  // Leaf cells with the references of their blocks' lanes and each one's
  // time interval.
  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    std::vector<PrimRef> below;
    std::vector<TimeRange> times;
    walk([&](uint32_t node, const Box3f& cell, int) {
      const KdNode& n = blocks_.cells.nodes[node];
      if (!n.isLeaf()) return;
      below.clear();
      times.clear();
      blocks_.forEachReference(n, [&](PrimRef prim, TimeRange t) {
        below.push_back(prim);
        times.push_back(t);
      });
      fn(LaneView{{0.0f, 1.0f}, [&cell](float) { return cell; }, below, times});
    });
  }
  std::any buildStats() const override { return &stats_; }

 private:
  template <class Fn>
  void walk(const Fn& fn) const {
    if (!tree_.empty()) forEachKdCell(tree_.nodes, 0, tree_.root, fn);
  }

  // the SAH of docs/design.md: a cell is a node with its cell box over the whole
  // shutter; a leaf counts the active segments of its references' intervals.
  void computeSah() {
    sceneArea_ = sceneSahArea(ctx_);
    sums_ = {};
    sums_.references = tree_.refs.size();
    walk([&](uint32_t node, const Box3f& cell, int depth) {
      const KdNode& n = tree_.nodes[node];
      const double area = cell.area();
      sums_.maxDepth = std::max(sums_.maxDepth, size_t(depth));
      if (!n.isLeaf()) {
        ++sums_.innerNodes;
        sums_.inner += area;
        return;
      }
      ++sums_.leafNodes;
      double seg = 0.0;
      for (uint32_t k = 0; k < n.count(); ++k) {
        const KdLeafRef& r = tree_.refs[n.first() + k];
        seg += activeSegments(ctx_, prims_[r.prim], {r.t0, r.t1});
      }
      sums_.leaves += area * seg;
    });
  }

  // A block lane's box: the primitive's linear bounds over the reference's
  // interval, extrapolated to t = 0 and 1; a short interval (where that
  // would magnify rounding) gets the constant box of the interval's hull.
  LBounds referenceBounds(uint32_t prim, TimeRange r) const {
    const LBounds local = linearBounds(ctx_, prims_[prim], r);
    if (!(r.size() >= kShortestExtrapolated)) return LBounds(local.hull());
    return toGlobal(local, r);
  }
  static constexpr float kShortestExtrapolated = 1.0f / 64;

  // Traversal with SIMD leaves: each block's references are checked eight at
  // a time (kd_leaf_blocks.h; blocks are sorted by interval start, so the
  // first block starting after the ray's time ends the leaf), and the
  // survivors' triangles are tested four at a time (kd_leaf_batch.h).
  template <bool AnyHit, bool Count>
  bool traceBlocks(RayQuery& ray, Hit* hit, TraversalCounters* counters) const {
    KdPrimMailbox mailbox;
    const KdBlockRay blockRay(ray);
    const typename Leaves::RayState state = leaves_.rayState(ray);
    const float time = ray.time;
    return kdWalk<AnyHit, Count>(blocks_.cells, ray, counters, [&](const KdNode& n) {
      bool found = false;
      KdLeafBatch batch;
      const KdLeafBlocks::Range r = blocks_.blocksAt(n, time);
      blocks_.prefetch(r);
      for (uint32_t k = r.begin; k < r.end; ++k) {
        const KdLeafBlock& block = blocks_.blocks[k];
        if (block.t0[0] > time) break;
        uint32_t hits;
        const uint32_t alive = kdBlockTest(block, blockRay, ray.tfar, hits);
        if constexpr (Count) counters->boxTests += uint64_t(std::popcount(alive));
        for (; hits != 0; hits &= hits - 1) {
          const PrimRef prim = block.prim[std::countr_zero(hits)];
          if (!mailbox.seen(prim)) batch.add(prim);
        }
        if (batch.holdsABlock()) {
          if (batch.test<AnyHit, Count>(leaves_, ctx_, ray, hit, counters, state)) {
            if constexpr (AnyHit) return true;
            found = true;
          }
        }
      }
      if (batch.test<AnyHit, Count>(leaves_, ctx_, ray, hit, counters, state)) {
        if constexpr (AnyHit) return true;
        found = true;
      }
      return found;
    });
  }

  const SceneContext& ctx_;
  std::vector<PrimRef> prims_;
  KdPaths paths_;
  // A reference costs a lane of a streamed 8-wide block test (our leaves,
  // kd_leaf_blocks.h, not the paper's), while a cell step is a dependent
  // load: the build weighs a step as this many reference tests more than
  // the paper's K_T (the sweep that chose it: docs/mbkd.md).
  static constexpr float kBlockStepWeight = 16.0f;
  KdLeafBlocks blocks_;
  Leaves leaves_;
  KdTree tree_;  // the build's tree: its nodes give the cells; its references are in the blocks
  KdBuildStats stats_;
  SahSums sums_;
  double sceneArea_ = 0.0;
};

}  // namespace

std::unique_ptr<Structure> makeMbkd(const SceneContext& context) {
  return std::make_unique<Mbkd<ReferenceLeaves>>(context);
}

}  // namespace mbrt::detail
