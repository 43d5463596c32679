// `frozen`: a static SAH BVH of the scene frozen at BuildOptions::frozenTime;
// every ray sees the geometry at that time. The "nothing moves" bound.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeFrozen(const SceneContext& context);

}  // namespace mbrt::detail
