// Binary tree -> N-wide BVH (STBVH §3.3, last paragraph): a wide node starts
// with the two children of a binary node and repeatedly opens the inner child
// with the largest area until it has N children; lanes still free go to the
// largest soft nodes (builder.h), and a soft node left in a lane is one leaf
// with its whole subtree's primitives. Nodes and leaf primitives
// are laid out in one fixed depth-first order, so the result is bit-identical
// whatever the thread count of the build. A wide node whose lanes serve
// different time ranges (below a temporal split) gets a LaneTimes entry.
// Charges the nodes and references to the budget.
#pragma once

#include <span>

#include "bvh/build_ref.h"
#include "bvh/builder.h"
#include "bvh/wide_bvh.h"

namespace mbrt::detail {

template <int N, bool Motion>
void collapse(const BinaryTree& tree, WideBvh<N, Motion>& out, BuildBudget& budget);

}  // namespace mbrt::detail
