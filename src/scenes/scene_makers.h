// Internal: one maker per built-in scene (one file each) and the helpers they
// share. The public entry point is makeProceduralScene() in mbrt/scenes.h.
#pragma once

#include <cstdint>

#include "mbrt/scenes.h"

namespace mbrt::scenes {

ProceduralScene makeTranslate(double size, uint64_t seed);
ProceduralScene makeRotate(double size, uint64_t seed);
ProceduralScene makeCrowd(double size, uint64_t seed);
ProceduralScene makeHairball(double size, uint64_t seed);
ProceduralScene makeHair(double size, uint64_t seed);
ProceduralScene makeDeform(double size, uint64_t seed);
ProceduralScene makeSkinned(double size, uint64_t seed);
ProceduralScene makeDemo(double size, uint64_t seed);
ProceduralScene makeSlide(double size, uint64_t seed);
ProceduralScene makeRibbons(double size, uint64_t seed);

// A camera looking at the box's centre from `direction` (need not be unit),
// far enough back that the box's bounding sphere fills the vertical field of
// view (times `margin`).
CameraSpec viewFrom(const Box3f& box, Vec3f direction, float verticalFovDegrees = 40.0f,
                    float margin = 1.0f);

}  // namespace mbrt::scenes
