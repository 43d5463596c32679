// `brute`: tests every primitive. The correctness oracle.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeBrute(const SceneContext& context);

}  // namespace mbrt::detail
