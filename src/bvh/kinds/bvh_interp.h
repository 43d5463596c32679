// `bvh-interp`: one N-wide BVH whose nodes hold linear bounds over the whole
// shutter, interpolated at the ray's time (STBVH without temporal splits).
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeBvhInterp(const SceneContext& context);

}  // namespace mbrt::detail
