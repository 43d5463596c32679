// rtcGetSceneBounds and rtcGetSceneLinearBounds: the box of every
// primitive over the whole shutter, and linear bounds over [0, 1] that
// contain each geometry's box at each of its time steps (Embree's fit: the
// line through the first and last step's boxes, widened by the largest
// excess of the steps between). Instances: the instanced scene's box under
// each key (as mbrt::sceneBounds; not conservative between rotating keys).
#pragma once

#include "mbrt/scene.h"

namespace mbrt::embree_api {

struct SceneBounds {
  Box3f box;
  LBounds linear;
};

SceneBounds boundsOf(const mbrt::Scene& scene);

}  // namespace mbrt::embree_api
