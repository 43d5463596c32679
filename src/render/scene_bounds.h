// Bounds of a scene over the whole shutter (every vertex step, every
// instance key), for camera framing and ray offsets. Not conservative
// between instance keys: good enough for those uses, not for traversal.
#pragma once

#include "mbrt/scene.h"

namespace mbrt::renderer {

Box3f sceneBounds(const Scene& scene);

}  // namespace mbrt::renderer
