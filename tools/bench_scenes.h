// The scenes of `mbrt bench`: the procedural suite and, when ../shared is
// present, the real scenes (Wood Doll keys, CesiumMan walking, Sponza and
// the bunny with procedural motion).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mbrt/scenes.h"

namespace mbrt::tools {

// Names of the real scenes ("wooddoll", "cesiumman", "sponza", "bunny").
std::vector<std::string> realBenchSceneNames();

// The shared scenes folder: $MBRT_SHARED_DIR/scenes, ../shared/scenes from
// the working directory, or from the executable's repository; none if absent.
std::optional<std::string> sharedScenesDir();

// Loads a real scene by name; throws Error when ../shared is absent.
ProceduralScene loadRealBenchScene(const std::string& name);

}  // namespace mbrt::tools
