// The kind registry: the structure of BuildOptions::kind over a context.
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

// Builds the structure of context.options().kind; the structures of
// instanced scenes are made through this same function.
std::unique_ptr<Structure> makeStructure(const SceneContext& context);

}  // namespace mbrt::detail
