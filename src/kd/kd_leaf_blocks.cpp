#include "kd/kd_leaf_blocks.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

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

// The references of `refs` (sorted by interval start) alive in each slice
// of `slices`, in the same order: reference r is in slice i when r.t0 <= (i
// + 1) / slices and r.t1 >= i / slices, i.e. from ceil(t0 * slices) - 1 to
// floor(t1 * slices) (exact products: slices is a power of two).
void sliceReferences(const std::vector<KdLeafRef>& refs, uint32_t slices, std::vector<std::vector<KdLeafRef>>& out) {
  out.resize(slices);
  for (auto& in : out) in.clear();
  for (const KdLeafRef& r : refs) {
    const float first = std::max(std::ceil(r.t0 * float(slices)) - 1.0f, 0.0f);
    const float last = std::min(std::floor(r.t1 * float(slices)), float(slices - 1));
    if (!(first <= last)) continue;  // alive in no slice: an empty interval
    for (uint32_t i = uint32_t(first), end = uint32_t(last); i <= end; ++i)
      out[i].push_back(r);
  }
}

// The blocks a ray at a uniform time in slice [lo, hi] tests among those of
// `refs` (sorted by start): a block is tested from its first start on.
double blocksTested(const std::vector<KdLeafRef>& refs, float lo, float hi) {
  double tested = 0.0;
  for (size_t i = 0; i < refs.size(); i += kKdBlockLanes)
    tested += std::clamp(double(hi - std::max(refs[i].t0, lo)) / double(hi - lo), 0.0, 1.0);
  return tested;
}

size_t blocksFor(size_t refs) { return (refs + kKdBlockLanes - 1) / kKdBlockLanes; }

// Slices per leaf, at most; and the blocks a slicing may lay out, at most, as
// a multiple of the unsliced leaf's.
constexpr uint32_t kMaxSlices = 64;
constexpr double kSliceBlockBound = 1.5;
// A leaf is sliced only where that saves a fifth of its tested blocks.
constexpr double kSliceGain = 0.8;

// The slices of a leaf (`chosen`, each one's references): among the powers
// of two up to kMaxSlices whose blocks stay within kSliceBlockBound times
// the unsliced ones, the fewest that test within 5% of the fewest blocks a
// ray at a uniform time tests; one where slicing saves less than
// kSliceGain. (Bounds chosen by measurement, docs/performance.md: more
// blocks read cost more time than the tests they save.)
void chooseSlices(const std::vector<KdLeafRef>& refs, std::vector<std::vector<KdLeafRef>>& chosen) {
  const double bound = kSliceBlockBound * double(std::max<size_t>(blocksFor(refs.size()), 1));
  std::vector<std::vector<std::vector<KdLeafRef>>> slicings;
  std::vector<double> tested;  // per ray, of each slicing
  for (uint32_t slices = 1; slices <= kMaxSlices; slices *= 2) {
    std::vector<std::vector<KdLeafRef>> in;
    sliceReferences(refs, slices, in);
    size_t blocks = 0;
    double sum = 0.0;
    for (uint32_t i = 0; i < slices; ++i) {
      blocks += blocksFor(in[i].size());
      sum += blocksTested(in[i], kdSliceStart(i, slices), kdSliceStart(i + 1, slices));
    }
    if (double(blocks) > bound) break;
    slicings.push_back(std::move(in));
    tested.push_back(sum / slices);
  }
  const double fewest = *std::min_element(tested.begin(), tested.end());
  size_t pick = 0;
  if (fewest <= kSliceGain * tested[0])
    while (tested[pick] > 1.05 * fewest) ++pick;
  chosen = std::move(slicings[pick]);
}

}  // namespace

KdLeafBlocks KdLeafBlocks::build(const KdTree& tree, const PrimRef* prims,
                                 const std::function<LBounds(uint32_t, TimeRange)>& bounds) {
  KdLeafBlocks out;
  out.cells.nodes = tree.nodes;
  out.cells.root = tree.root;
  out.cells.depth = tree.depth;
  std::vector<KdLeafRef> refs;
  std::vector<std::vector<KdLeafRef>> slices;
  for (KdNode& n : out.cells.nodes) {
    if (!n.isLeaf()) continue;
    refs.assign(tree.refs.begin() + n.first(), tree.refs.begin() + n.first() + n.count());
    // By interval start: the references alive at one time sit in few blocks.
    std::sort(refs.begin(), refs.end(), [](const KdLeafRef& a, const KdLeafRef& b) {
      return a.t0 < b.t0 || (a.t0 == b.t0 && a.t1 < b.t1);
    });
    chooseSlices(refs, slices);
    const size_t firstSlice = out.sliceStarts.size();
    for (const std::vector<KdLeafRef>& in : slices) {
      const size_t first = out.blocks.size(), count = blocksFor(in.size());
      if (first + count > kKdMaxIndex) throw Error("kd-tree: too many leaf blocks");
      out.sliceStarts.push_back(uint32_t(first));
      out.blocks.resize(first + count);
      for (size_t j = 0; j < count * kKdBlockLanes; ++j) {
        KdLeafBlock& b = out.blocks[first + j / kKdBlockLanes];
        const int lane = int(j % kKdBlockLanes);
        if (j < in.size())
          setLane(b, lane, in[j], prims[in[j].prim], bounds(in[j].prim, {in[j].t0, in[j].t1}));
        else
          clearLane(b, lane);
      }
    }
    out.sliceStarts.push_back(uint32_t(out.blocks.size()));
    if (out.sliceStarts.size() > kKdMaxIndex) throw Error("kd-tree: too many leaf slices");
    n = KdNode::leaf(uint32_t(firstSlice), refs.empty() ? 0u : uint32_t(slices.size()));  // 0: an empty leaf, as the tree's
  }
  return out;
}

}  // namespace mbrt::detail
