// The built-in procedural scene suite (docs/design.md, "The scene suite"):
// deterministic, seeded, with a size knob. size = 1 gives the default sizes
// every issue's figures refer to; tests use small sizes (e.g. 0.005).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/camera.h"
#include "mbrt/scene.h"

namespace mbrt {

struct ProceduralScene {
  std::string name;
  std::shared_ptr<Scene> scene;  // owns its data and any instanced scenes
  CameraSpec camera;             // a view that frames the scene
};

// Names of the built-in scenes, in suite order:
// translate, rotate, crowd, hairball, hair, deform, skinned, demo, slide,
// ribbons (the last two: the simplest motion, 2 time steps).
std::vector<std::string> proceduralSceneNames();

// Builds a built-in scene. Throws Error for an unknown name or size <= 0.
ProceduralScene makeProceduralScene(std::string_view name, double size = 1.0, uint64_t seed = 1);

// A camera that frames the box, looking along -z from its front.
CameraSpec frameBox(const Box3f& box);

}  // namespace mbrt
