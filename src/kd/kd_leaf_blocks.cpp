#include "kd/kd_leaf_blocks.h"

#include <algorithm>

#include "mbrt/scene.h"

namespace mbrt::detail {
namespace {

// A lane nobody is alive in: t0 > t1 fails every interval check.
void clearLane(KdLeafBlock& b, int lane) {
  b.t0[lane] = kInf;
  b.t1[lane] = -kInf;
  b.prim[lane] = {kInvalidId, kInvalidId};
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 4; ++k) b.plane[a][k][lane] = 0.0f;
}

void setLane(KdLeafBlock& b, int lane, const KdLeafRef& r, PrimRef prim, const LBounds& lb) {
  b.t0[lane] = r.t0;
  b.t1[lane] = r.t1;
  b.prim[lane] = prim;
  for (int a = 0; a < 3; ++a) {
    b.plane[a][0][lane] = lb.b0.lower[a];
    b.plane[a][1][lane] = lb.b0.upper[a];
    b.plane[a][2][lane] = lb.b1.lower[a] - lb.b0.lower[a];
    b.plane[a][3][lane] = lb.b1.upper[a] - lb.b0.upper[a];
  }
}

}  // namespace

KdLeafBlocks KdLeafBlocks::build(const KdTree& tree, const PrimRef* prims,
                                 const std::function<LBounds(uint32_t, TimeRange)>& bounds) {
  KdLeafBlocks out;
  out.cells.nodes = tree.nodes;
  out.cells.root = tree.root;
  out.cells.depth = tree.depth;
  std::vector<KdLeafRef> refs;
  for (KdNode& n : out.cells.nodes) {
    if (!n.isLeaf()) continue;
    refs.assign(tree.refs.begin() + n.first(), tree.refs.begin() + n.first() + n.count());
    // By interval start: the references alive at one time sit in few blocks.
    std::sort(refs.begin(), refs.end(), [](const KdLeafRef& a, const KdLeafRef& b) {
      return a.t0 < b.t0 || (a.t0 == b.t0 && a.t1 < b.t1);
    });
    const size_t first = out.blocks.size(), count = (refs.size() + kKdBlockLanes - 1) / kKdBlockLanes;
    if (first + count > kKdMaxIndex) throw Error("kd-tree: too many leaf blocks");
    out.blocks.resize(first + count);
    for (size_t i = 0; i < count * kKdBlockLanes; ++i) {
      KdLeafBlock& b = out.blocks[first + i / kKdBlockLanes];
      const int lane = int(i % kKdBlockLanes);
      if (i < refs.size())
        setLane(b, lane, refs[i], prims[refs[i].prim], bounds(refs[i].prim, {refs[i].t0, refs[i].t1}));
      else
        clearLane(b, lane);
    }
    n = KdNode::leaf(uint32_t(first), uint32_t(count));
  }
  return out;
}

}  // namespace mbrt::detail
