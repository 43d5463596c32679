#include "kd/kd_builder.h"

#include <chrono>
#include <cmath>

namespace mbrt::detail {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// Cost of skipping a reference by its interval, relative to a test.
constexpr double kCheckWeight = 0.02;

class Builder {
 public:
  Builder(const KdPaths& paths, const KdBuildParams& params, BuildBudget& budget, KdTree& out, KdBuildStats& stats)
      : paths_(paths), params_(params), budget_(budget), out_(out), stats_(stats) {}

  void build(const Box3f& cell, std::vector<KdBuildRef> normal, std::vector<KdBuildRef> bp, int depth) {
    const uint32_t index = uint32_t(out_.nodes.size());
    if (index > kKdMaxIndex) throw Error("kd-tree: too many nodes");
    out_.nodes.push_back({});
    out_.depth = std::max(out_.depth, uint32_t(depth) + 1);
    KdSplit split;
    float leafCost = 0.0f;
    if (depth < params_.maxDepth && !normal.empty()) {
      const auto t = Clock::now();
      split = findKdSplit(paths_, normal, cell, params_.sah, leafCost);
      stats_.sahSeconds += since(t);
    }
    if (split.axis < 0 || !(split.cost < leafCost)) {
      makeLeaf(index, normal, bp);
      return;
    }
    const int axis = split.axis;
    const float pos = split.pos;
    std::vector<KdBuildRef> nl, nr, bl, br;
    auto t = Clock::now();
    TimeRange winL[kKdMaxWindows], winR[kKdMaxWindows];
    for (const KdBuildRef& r : normal) {
      const Box3f placed = paths_.boxAt(r.prim, paths_.placementTime(r.prim));
      const bool onLeft = placed.lower[axis] < pos || (placed.lower[axis] == pos && placed.upper[axis] == pos);
      const bool onRight = placed.upper[axis] > pos;
      const int nl_ = paths_.sideWindows(r.prim, axis, pos, true, r.t0, r.t1, winL);
      const int nr_ = paths_.sideWindows(r.prim, axis, pos, false, r.t0, r.t1, winR);
      route(r, onLeft, winL, nl_, nl, bl);
      route(r, onRight, winR, nr_, nr, br);
    }
    stats_.duplicationSeconds += since(t);
    t = Clock::now();
    for (const KdBuildRef& r : bp) {
      const int nl_ = paths_.sideWindows(r.prim, axis, pos, true, r.t0, r.t1, winL);
      const int nr_ = paths_.sideWindows(r.prim, axis, pos, false, r.t0, r.t1, winR);
      for (int k = 0; k < nl_; ++k) bl.push_back({r.prim, winL[k].lo, winL[k].hi}), ++stats_.propagations;
      for (int k = 0; k < nr_; ++k) br.push_back({r.prim, winR[k].lo, winR[k].hi}), ++stats_.propagations;
    }
    stats_.propagationSeconds += since(t);
    // The plane was chosen by the Normal references alone; whether to split
    // at all counts every reference with the time it can be tested (its
    // interval) plus a small constant for the interval check itself.
    const double areaN = cell.halfArea();
    Box3f lc = cell, rc = cell;
    lc.upper[axis] = pos;
    rc.lower[axis] = pos;
    const double wl = weight(nl) + weight(bl), wr = weight(nr) + weight(br);
    double splitCost = params_.sah.traversal +
                       params_.sah.intersection * (wl * lc.halfArea() + wr * rc.halfArea()) / areaN;
    if (nl.empty() && bl.empty()) splitCost *= params_.sah.emptyBonus;
    if (nr.empty() && br.empty()) splitCost *= params_.sah.emptyBonus;
    if (!(splitCost < params_.sah.intersection * (weight(normal) + weight(bp)))) {
      makeLeaf(index, normal, bp);
      return;
    }
    const size_t scratch = (nl.size() + nr.size() + bl.size() + br.size()) * sizeof(KdBuildRef);
    ScopedCharge charge(budget_, scratch, "the kd-tree build references");
    normal = {};
    bp = {};
    build(lc, std::move(nl), std::move(bl), depth + 1);
    const uint32_t right = uint32_t(out_.nodes.size());
    out_.nodes[index] = KdNode::inner(axis, pos, right);
    build(rc, std::move(nr), std::move(br), depth + 1);
  }

 private:
  // One child of a Normal reference. Placed there: the window holding the
  // placement time stays Normal (a point when rounding left none). Every
  // other window (the primitive leaves and comes back, or was placed on the
  // other side) is duplicated into the child's BP set.
  void route(const KdBuildRef& r, bool placed, const TimeRange* w, int n, std::vector<KdBuildRef>& normal,
             std::vector<KdBuildRef>& bp) {
    const float tp = paths_.placementTime(r.prim);
    int home = -1;
    if (placed) {
      for (int k = 0; k < n; ++k)
        if (w[k].lo <= tp && tp <= w[k].hi) home = k;
      if (home < 0) normal.push_back({r.prim, tp, tp});
    }
    for (int k = 0; k < n; ++k) {
      if (k == home) {
        normal.push_back({r.prim, w[k].lo, w[k].hi});
      } else {
        bp.push_back({r.prim, w[k].lo, w[k].hi});
        ++stats_.duplications;
      }
    }
  }

  static double weight(const std::vector<KdBuildRef>& refs) {
    double w = 0.0;
    for (const KdBuildRef& r : refs) w += double(r.t1 - r.t0) + kCheckWeight;
    return w;
  }

  void makeLeaf(uint32_t index, const std::vector<KdBuildRef>& normal, const std::vector<KdBuildRef>& bp) {
    const size_t first = out_.refs.size(), count = normal.size() + bp.size();
    if (first + count > 0xffffffffull || count > kKdMaxIndex) throw Error("kd-tree: too many references");
    budget_.charge(count * sizeof(KdLeafRef) + sizeof(KdNode), "the kd-tree");
    for (const KdBuildRef& r : normal) out_.refs.push_back({r.prim, r.t0, r.t1});
    for (const KdBuildRef& r : bp) out_.refs.push_back({r.prim, r.t0, r.t1});
    out_.nodes[index] = KdNode::leaf(uint32_t(first), uint32_t(count));
    stats_.normalRefs += normal.size();
    stats_.duplicatedRefs += bp.size();
  }

  const KdPaths& paths_;
  KdBuildParams params_;
  BuildBudget& budget_;
  KdTree& out_;
  KdBuildStats& stats_;
};

}  // namespace

void buildKdTree(const KdPaths& paths, const Box3f& root, const KdBuildParams& params, BuildBudget& budget,
                 KdTree& out, KdBuildStats& stats) {
  const auto start = Clock::now();
  out = {};
  stats = {};
  stats.primitives = paths.size();
  out.root = root;
  if (paths.size() == 0) return;
  KdBuildParams p = params;
  if (p.maxDepth <= 0) p.maxDepth = int(8.0 + 1.3 * std::log2(double(paths.size())));
  p.maxDepth = std::min(p.maxDepth, kKdMaxDepth);
  std::vector<KdBuildRef> refs(paths.size());
  for (uint32_t i = 0; i < paths.size(); ++i) {
    const TimeRange r = paths.range(i);
    refs[i] = {i, r.lo, r.hi};
  }
  ScopedCharge charge(budget, refs.size() * sizeof(KdBuildRef), "the kd-tree build references");
  Builder(paths, p, budget, out, stats).build(root, std::move(refs), {}, 0);
  out.nodes.shrink_to_fit();
  out.refs.shrink_to_fit();
  stats.totalSeconds = since(start);
}

}  // namespace mbrt::detail
