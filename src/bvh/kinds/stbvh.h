// `stbvh`: the spatial-temporal BVH of Woop et al. 2017 (docs/stbvh.md): one
// N-wide BVH with linear bounds over the whole shutter, whose builder may
// also split time (temporal splits), so nodes below a temporal split serve
// only part of the shutter and store per-lane time ranges.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeStbvh(const SceneContext& context);

}  // namespace mbrt::detail
