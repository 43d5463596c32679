// Time-weighted SAH for kd-tree splits (MBKD §3.1.1). A reference counts on
// each side of a candidate plane with the time it spends there within its
// interval, computed exactly per linear piece of its path:
//   cost = K_T + K_I (W_left SA(left) + W_right SA(right)) / SA(cell)
// with the empty-space bonus when one side gets no weight. Without motion
// every weight is 1 (or the interval's length) and this is the plain kd SAH.
// Large nodes are evaluated on bin planes, small ones at every reference's
// bound (an exact sweep, Wald & Havran 2006, with the time weights).
#pragma once

#include <span>

#include "kd/kd_motion.h"

namespace mbrt::detail {

struct KdSahParams {
  float traversal = 1.0f;     // K_T
  float intersection = 1.5f;  // K_I
  float emptyBonus = 0.8f;    // cost factor when one side is empty
  int bins = 64;              // planes per axis in binned nodes
  uint32_t exactBelow = 64;   // nodes with fewer references sweep exactly
};

struct KdSplit {
  int axis = -1;  // -1: none found
  float pos = 0.0f;
  float cost = kInf;
};

// The cheapest plane strictly inside `cell` for the references `refs`
// (placed at their placement time); leafCost receives K_I times their
// total weight.
KdSplit findKdSplit(const KdPaths& paths, std::span<const KdBuildRef> refs, const Box3f& cell,
                    const KdSahParams& params, float& leafCost);

}  // namespace mbrt::detail
