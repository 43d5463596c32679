// What a user's scene is beyond geometry: the camera over the shutter,
// materials and lights. Produced by the loaders (procedural suite, OBJ,
// OBJ sequences, glTF, PLY, scene files) and consumed by the renderer.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mbrt/scene.h"
#include "mbrt/scenes.h"

namespace mbrt {

struct Material {
  Vec3f diffuse{0.7f, 0.7f, 0.7f};  // albedo
};

struct DirectionalLight {
  Vec3f direction{-0.4f, -1.0f, -0.3f};  // direction the light travels
  Vec3f radiance{2.5f, 2.4f, 2.2f};
};

// A camera over the normalized shutter [0,1]: `keys` holds one pose (static)
// or several equidistant poses (a moving camera, interpolated linearly).
// Pinhole when apertureRadius == 0, thin lens otherwise.
struct Camera {
  std::vector<CameraSpec> keys{CameraSpec{}};
  float apertureRadius = 0.0f;
  float focusDistance = 0.0f;  // 0: the distance from the eye to the target
};

struct SceneDescription {
  std::string name;
  std::shared_ptr<Scene> scene;
  Camera camera;                      // always set (framed automatically when the input has none)
  std::vector<Material> materials;    // per top-level geometry id; missing entries use Material{}
  std::vector<DirectionalLight> lights{DirectionalLight{}};
  Vec3f skyColor{0.55f, 0.65f, 0.8f}; // radiance of the environment (AO and path tracing)
  // The shutter the scene was sampled for, in the source's own units (e.g.
  // seconds of a glTF clip); informational.
  double shutterOpen = 0.0, shutterClose = 1.0;

  const Material& material(uint32_t geomID) const {
    static const Material fallback;
    return geomID < materials.size() ? materials[geomID] : fallback;
  }
};

}  // namespace mbrt
