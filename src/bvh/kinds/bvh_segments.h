// `bvh-segments`: one linear-bounds BVH per global time segment (Embree
// before 2.16, the STBVH paper's baseline); a ray traverses its segment's.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeBvhSegments(const SceneContext& context);

}  // namespace mbrt::detail
