#include "bvh/kinds/bvh_interp.h"

#include "bvh/kinds/bvh_structure.h"
#include "bvh/sah_cost.h"
#include "leaves/leaf_width.h"
#include "leaves/motion_blocks.h"

namespace mbrt::detail {
namespace {

// Leaves: motion blocks, the vertices of four triangles at every step.
template <int N>
class BvhInterp final : public WideBvhStructure<N, true, MotionBlockLeaves> {
  using Base = WideBvhStructure<N, true, MotionBlockLeaves>;
  using Base::bvh_;
  using Base::ctx_;

 public:
  explicit BvhInterp(const SceneContext& ctx) : Base(ctx) {
    const std::vector<PrimRef> prims = ctx.primitives();
    numPrims_ = prims.size();
    buildWideBvh(ctx, prims, ShutterRefs(ctx), bvh_, {.leafBlock = triangleLeafBlockWidth(ctx)});
    Base::layOutLeaves();
  }

  void fillStats(AccelStats& s) const override {
    SahSums sums;
    addTreeCost(bvh_, 1.0, [&](PrimRef p, TimeRange) { return activeSegments(ctx_, p, {0.0f, 1.0f}); }, sums);
    sums.bytes += Base::leaves_.bytes();
    sums.fill(s, sceneSahArea(ctx_));
    s.leafBlockBytes = Base::leaves_.bytes();
  }

  // Same topology, new bounds: leaves from the primitives, inner lanes from
  // their children, bottom-up.
  bool refit() override {
    if (bvh_.numReferences() != numPrims_) return false;  // a primitive was dropped: rebuild
    // Instance bounds come from the context's key boxes and the instanced
    // structures, which are made once: rebuild instead.
    for (uint32_t g = 0; g < ctx_.scene().numGeometries(); ++g)
      if (ctx_.geometry(g).type() == GeometryType::Instance) return false;
    if (bvh_.empty()) return true;
    bool ok = true;
    refitNode(0, ok);
    if (!ok) return false;
    // The vertices moved: the blocks are made again.
    const size_t before = Base::leaves_.bytes();
    Base::layOutLeaves();
    ctx_.budget().release(before);
    return true;
  }

  void forEachLane(const std::function<void(const LaneView&)>& fn) const override {
    if (bvh_.empty()) return;
    walkLanes(bvh_, 0, [&](const WideNode<N, true>& node, int lane, std::span<const PrimRef> below) {
      fn(LaneView{{0.0f, 1.0f}, [&node, lane](float t) { return node.boxAt(lane, t); }, below, {}});
    });
  }

 private:
  LBounds refitNode(uint32_t index, bool& ok) {
    LBounds all, lanes[N];
    uint32_t present = 0;
    for (int i = 0; i < N; ++i) {
      const auto& node = bvh_.nodes[index];
      if (node.isEmpty(i)) continue;
      LBounds& b = lanes[i];
      if (node.isLeaf(i)) {
        PrimRef one;
        for (const PrimRef& p : bvh_.leafRefs(node, i, one)) b.extend(linearBounds(ctx_, p, {0.0f, 1.0f}));
        ok = ok && isUsable(b);
      } else {
        b = refitNode(node.child[i], ok);
      }
      present |= 1u << i;
      all.extend(b);
    }
    bvh_.nodes[index].encode(lanes, present);
    return all;
  }

  size_t numPrims_ = 0;
};

}  // namespace

std::unique_ptr<Structure> makeBvhInterp(const SceneContext& context) {
  return makeForBranching<BvhInterp>(context);
}

}  // namespace mbrt::detail
