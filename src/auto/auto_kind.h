// `auto` (docs/auto.md): rigid motion extracted into instances of static
// rest poses, every object (extracted part, the world-space rest, user
// instance) given the structure its cost favours, and an stbvh over the
// objects. Hits name the original scene's geometries and primitives.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeAuto(const SceneContext& context);

}  // namespace mbrt::detail
