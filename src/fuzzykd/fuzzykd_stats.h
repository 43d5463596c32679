// The figures of a fuzzy kd-tree: its sizes (FuzzyKdStats) and the SAH of
// docs/design.md with its node counts (AccelStats).
#pragma once

#include "fuzzykd/fuzzykd.h"
#include "fuzzykd/fuzzykd_trees.h"

namespace mbrt::detail {

// Sets the tree sizes of `stats` (clusters, primitives, nodes, references,
// bytes).
void countTrees(const FuzzyKdTrees& trees, FuzzyKdStats& stats);

// the SAH of docs/design.md (C_T = C_I = 1, areas averaged over 8 times). The top
// tree's lanes count with their linear bounds, a leaf lane as one entry
// into its item; a cluster with its world key box and its tree's cells,
// whose area is that of the cell's image in world space (a parallelepiped
// under the cluster's map at each time, §3: the ray is mapped into the
// cell's frame, so that is the area it must hit); a leaf counts the active
// segments of its triangles. The world tree's cells count as mbkd's.
double fuzzySahCost(const SceneContext& ctx, const FuzzyKdTrees& trees);

// AccelStats of the trees: nodes, leaves, references and depth of the kd
// trees (the top tree's nodes count as inner nodes), bytes of them all.
void fillFuzzyStats(const FuzzyKdTrees& trees, const FuzzyKdStats& stats, double sahCost, AccelStats& s);

}  // namespace mbrt::detail
