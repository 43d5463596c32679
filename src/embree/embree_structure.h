// `embree`: the scene fed to Intel Embree 3 (only built with MBRT_HAVE_EMBREE).
#pragma once

#include <memory>

#include "scene/scene_context.h"

namespace mbrt::detail {

std::unique_ptr<Structure> makeEmbree(const SceneContext& context);

// Embree's device-wide memory, as its memory monitor reports it.
struct EmbreeMemory {
  long long current = 0;
  long long peak = 0;
};
EmbreeMemory embreeMemory();

// Tests: apply geometry masks in filter functions even when Embree's ray
// masks are available (the fallback for Embree builds without them).
void embreeForceFilterMasks(bool on);

}  // namespace mbrt::detail
