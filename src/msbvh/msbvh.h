// `msbvh`: the Motion SBVH of Grünschloß, Stich, Nawaz and Keller (HPG 2011).
// An SBVH topology built at t = 0.5 (sbvh_builder.h), collapsed to N-wide
// nodes; every lane stores n + 1 boxes for the key times t_i = i/n
// (key_bounds.h), interpolated between the two keys around the ray's time.
// Children are visited by entry distance into their interpolated boxes
// (§6.2). Refitting (§5) keeps the topology and recomputes the keys.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeMsbvh(const SceneContext& context);

// The build figures of an MSBVH (core/inspect.h: statsOf<MsbvhStats>).
struct MsbvhStats {
  uint32_t keySegments = 0;  // n: the keys kept (fitKeySegments)
};

}  // namespace mbrt::detail
