#include "kd/kd_sah.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace mbrt::detail {
namespace {

// The weight a piece of duration d puts on one side as a function of the
// plane: a ramp from 0 at `lo` to d at `hi` (a step when lo == hi).
struct Ramp {
  float lo, hi, d;
};

// Ramps of the lower sides (left weight: time with lower <= p) and of the
// upper sides (right weight = total - time with upper < p).
void collectRamps(const KdPaths& paths, std::span<const KdBuildRef> refs, int axis, std::vector<Ramp>& lower,
                  std::vector<Ramp>& upper, double& total) {
  lower.clear();
  upper.clear();
  total = 0.0;
  for (const KdBuildRef& r : refs) {
    if (!(r.t1 > r.t0)) continue;  // a point in time weighs nothing
    paths.forEachPiece(r.prim, r.t0, r.t1, [&](float sa, float sb, const Box3f& A, const Box3f& B) {
      const float d = sb - sa;
      if (!(d > 0.0f)) return;
      lower.push_back({std::min(A.lower[axis], B.lower[axis]), std::max(A.lower[axis], B.lower[axis]), d});
      upper.push_back({std::min(A.upper[axis], B.upper[axis]), std::max(A.upper[axis], B.upper[axis]), d});
      total += d;
    });
  }
}

struct Planes {
  std::vector<float> pos;
  std::vector<double> left, right;  // weights at each plane
};

// Binned: planes cl + j w, j = 1..B-1; ramps go to difference arrays of
// constant and slope terms, so each plane's weight is exact for it.
void evalBinned(std::span<const Ramp> lower, std::span<const Ramp> upper, double total, float cl, float cu,
                int bins, Planes& out) {
  const double w = (double(cu) - double(cl)) / bins;
  std::vector<double> cL(size_t(bins) + 1, 0.0), sL(size_t(bins) + 1, 0.0), cU(size_t(bins) + 1, 0.0),
      sU(size_t(bins) + 1, 0.0);
  auto index = [&](float x) {
    const double j = std::floor((double(x) - cl) / w) + 1.0;
    return size_t(std::clamp(j, 1.0, double(bins)));
  };
  auto add = [&](const Ramp& r, std::vector<double>& c, std::vector<double>& s) {
    const size_t a = index(r.lo), b = index(r.hi);
    if (a == b || !(r.hi > r.lo)) {
      c[a] += r.d;
      return;
    }
    const double slope = double(r.d) / (double(r.hi) - double(r.lo));
    c[a] -= slope * r.lo;
    s[a] += slope;
    c[b] += slope * r.lo + r.d;
    s[b] -= slope;
  };
  for (const Ramp& r : lower) add(r, cL, sL);
  for (const Ramp& r : upper) add(r, cU, sU);
  double accCL = cL[0], accSL = sL[0], accCU = cU[0], accSU = sU[0];
  for (int j = 1; j < bins; ++j) {
    accCL += cL[size_t(j)];
    accSL += sL[size_t(j)];
    accCU += cU[size_t(j)];
    accSU += sU[size_t(j)];
    const double p = double(cl) + w * j;
    out.pos.push_back(float(p));
    out.left.push_back(std::clamp(accCL + accSL * p, 0.0, total));
    out.right.push_back(std::clamp(total - (accCU + accSU * p), 0.0, total));
  }
}

// Exact: planes at the references' placement bounds; one sorted sweep over
// the ramps' start and end events.
void evalExact(std::span<const Ramp> lower, std::span<const Ramp> upper, double total, std::vector<float> planes,
               Planes& out) {
  std::sort(planes.begin(), planes.end());
  planes.erase(std::unique(planes.begin(), planes.end()), planes.end());
  struct Event {
    float pos;
    double c, s;
  };
  auto events = [](std::span<const Ramp> ramps) {
    std::vector<Event> ev;
    ev.reserve(ramps.size() * 2);
    for (const Ramp& r : ramps) {
      if (!(r.hi > r.lo)) {
        ev.push_back({r.lo, double(r.d), 0.0});
        continue;
      }
      const double slope = double(r.d) / (double(r.hi) - double(r.lo));
      ev.push_back({r.lo, -slope * r.lo, slope});
      ev.push_back({r.hi, slope * r.lo + r.d, -slope});
    }
    std::sort(ev.begin(), ev.end(), [](const Event& a, const Event& b) { return a.pos < b.pos; });
    return ev;
  };
  const std::vector<Event> L = events(lower), U = events(upper);
  size_t iL = 0, iU = 0;
  double cL = 0, sL = 0, cU = 0, sU = 0;
  for (float p : planes) {
    // Left: lower < p counts; right: upper <= p leaves (a box ending at
    // the plane stays on its side).
    while (iL < L.size() && L[iL].pos < p) cL += L[iL].c, sL += L[iL].s, ++iL;
    while (iU < U.size() && U[iU].pos <= p) cU += U[iU].c, sU += U[iU].s, ++iU;
    out.pos.push_back(p);
    out.left.push_back(std::clamp(cL + sL * p, 0.0, total));
    out.right.push_back(std::clamp(total - (cU + sU * p), 0.0, total));
  }
}

}  // namespace

KdSplit findKdSplit(const KdPaths& paths, std::span<const KdBuildRef> refs, const Box3f& cell,
                    const KdSahParams& params, float& leafCost) {
  KdSplit best;
  std::vector<Ramp> lower, upper;
  Planes planes;
  const double areaN = cell.halfArea();
  leafCost = 0.0f;
  for (int axis = 0; axis < 3; ++axis) {
    double total;
    collectRamps(paths, refs, axis, lower, upper, total);
    leafCost = float(params.intersection * total);
    const float cl = cell.lower[axis], cu = cell.upper[axis];
    if (!(cu > cl) || !(areaN > 0.0) || total <= 0.0) continue;
    planes.pos.clear();
    planes.left.clear();
    planes.right.clear();
    if (refs.size() < params.exactBelow) {
      std::vector<float> candidates;
      for (const KdBuildRef& r : refs) {
        const Box3f b = paths.boxAt(r.prim, paths.placementTime(r.prim));
        candidates.push_back(b.lower[axis]);
        candidates.push_back(b.upper[axis]);
      }
      evalExact(lower, upper, total, std::move(candidates), planes);
    } else {
      evalBinned(lower, upper, total, cl, cu, params.bins, planes);
    }
    const double eps = total * 1e-9;
    for (size_t j = 0; j < planes.pos.size(); ++j) {
      const float p = planes.pos[j];
      if (!(p > cl && p < cu)) continue;
      Box3f l = cell, r = cell;
      l.upper[axis] = p;
      r.lower[axis] = p;
      const double wl = planes.left[j], wr = planes.right[j];
      double cost = params.traversal + params.intersection * (wl * l.halfArea() + wr * r.halfArea()) / areaN;
      if (wl <= eps || wr <= eps) cost *= params.emptyBonus;
      if (cost < best.cost) best = {axis, p, float(cost)};
    }
  }
  return best;
}

}  // namespace mbrt::detail
