// Random strands for `hairball` and `hair`, and their per-strand motion.
#pragma once

#include <cstdint>
#include <vector>

#include "mbrt/math.h"

namespace mbrt::scenes {

// A wandering polyline of `points` points inside the ball of `ballRadius`
// around the origin, starting anywhere in it.
std::vector<Vec3f> wanderingStrand(uint64_t seed, uint64_t stream, int points, float segmentLength,
                                   float ballRadius);

// A strand rooted on the sphere of `rootRadius`, growing outwards and
// drooping a little (a fuzzy head of hair).
std::vector<Vec3f> rootedStrand(uint64_t seed, uint64_t stream, int points, float segmentLength,
                                float rootRadius);

// Per-strand motion over 3 steps: offsets for steps 0, 1, 2. The strand moves
// by `distance` in its own direction, and the middle step sits off the
// straight line by `bend` times that distance (a bent path).
struct StrandMotion {
  Vec3f offset[3];
};
StrandMotion strandMotion(uint64_t seed, uint64_t stream, float distance, float bend);

}  // namespace mbrt::scenes
