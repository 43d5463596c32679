// Top-down kd-tree build over primitive paths (kd_motion.h) with MBKD's
// duplication and propagation (Yang et al. 2017, §3.1.1).
//
// Every node holds Normal references (placed by their box at the placement
// time, t = 0.5 or the nearest time alive: they choose the split with the
// time-weighted SAH) and BP references (primitives whose box enters the cell
// during the shutter only: carried along, never choosing splits). Each
// reference carries the hull of the times it can be inside the cell. At a
// split, per reference and per child, the times its box reaches that side:
//  - Normal, placed on that side -> the child's Normal set (straddlers go to
//    both, as in a static kd-tree);
//  - Normal, placed on the other side but reaching this one during its
//    interval -> duplicated into the child's BP set (the 8 cases of Fig. 3);
//  - BP reaching that side -> propagated into the child's BP set (the six
//    cases: left, right or both, each with its time interval).
// A reference that never reaches a side is dropped there; one that leaves a
// side and comes back gets one reference per time window (kd_motion.h), the
// window holding its placement time staying Normal. The plane is chosen by
// the Normal references; whether to split at all counts every reference,
// weighted by its window length (the paper counts Normal ones only, which
// let BP references multiply without bound). The root cell
// holds every primitive over the whole shutter. Without motion (one key per
// primitive) there are no BP references: a static SAH kd-tree.
#pragma once

#include "core/build_budget.h"
#include "kd/kd_node.h"
#include "kd/kd_sah.h"

namespace mbrt::detail {

struct KdBuildParams {
  KdSahParams sah;
  int maxDepth = 0;  // 0: 8 + 1.3 log2(N), at most kKdMaxDepth
};

inline constexpr int kKdMaxDepth = 60;

// The paper's Table 2 figures and a few more.
struct KdBuildStats {
  size_t primitives = 0;
  size_t normalRefs = 0;        // references in leaves placed there
  size_t duplicatedRefs = 0;    // references in leaves from BP sets
  size_t duplications = 0;      // Normal -> BP events (Fig. 3 cases)
  size_t propagations = 0;      // BP -> BP events
  double sahSeconds = 0.0;
  double duplicationSeconds = 0.0;  // classifying Normal references
  double propagationSeconds = 0.0;  // classifying BP references
  double totalSeconds = 0.0;
};

// Builds `out` over refs[i] = primitive i alive over its range. `root` must
// contain every primitive's box over the whole shutter.
void buildKdTree(const KdPaths& paths, const Box3f& root, const KdBuildParams& params, BuildBudget& budget,
                 KdTree& out, KdBuildStats& stats);

}  // namespace mbrt::detail
