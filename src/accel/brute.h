// `brute`: tests every primitive. The correctness oracle.
#pragma once

#include <memory>

#include "core/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeBrute(const SceneContext& context);

}  // namespace mbrt::detail
