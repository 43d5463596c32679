// stbvh's settings of the shared BVH build (docs/stbvh.md): temporal splits
// over the scene's steps, and the two costs that trade them against leaves.
#pragma once

#include "bvh/build/build_wide.h"

namespace mbrt::detail {

// C_T relative to C_I: the builder fills spare lanes by splitting leaves
// (builder.h), so a leaf costs less than its segments say; 1.5 trades the
// nodes this saves for a few more intersections (docs/stbvh.md).
inline constexpr float kFilledTraversalScale = 1.5f;

// λ against a leaf (BuildSettings::temporalLeafPenalty). With C_T = 1.5, a
// one-primitive leaf of straight motion over 5 segments (a temporal split
// halves its segments, not its area) is split in time only below
// λ = (1 - 1.5 / 5) / 0.52 = 1.35: 1.4 keeps such leaves whole, so linear
// bounds carry linear motion (docs/stbvh.md, "Quantised motion nodes and
// the MBSAH's own leaf test").
inline constexpr float kTemporalLeafPenalty = 1.4f;

inline WideBuildTuning stbvhTuning(const TemporalSource& timing, int leafBlock) {
  WideBuildTuning t;
  t.temporal = &timing;
  t.leafBlock = leafBlock;
  t.traversalScale = kFilledTraversalScale;
  t.temporalLeafPenalty = kTemporalLeafPenalty;
  return t;
}

}  // namespace mbrt::detail
