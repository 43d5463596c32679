// A(scene), the denominator of the SAH cost shared by every kind
// (core/sah_sums.h).
#pragma once

#include "scene/scene_context.h"

namespace mbrt::detail {

// Surface area of the union of every primitive's bounds over the whole
// shutter [0,1]. A pass over every primitive: computed when stats are asked
// for, not in the build.
double sceneSahArea(const SceneContext& ctx);

}  // namespace mbrt::detail
