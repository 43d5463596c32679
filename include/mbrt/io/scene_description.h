// What a user's scene is beyond geometry: the camera over the shutter,
// materials and lights. Produced by the loaders (procedural suite, OBJ,
// OBJ sequences, glTF, PLY, scene files) and consumed by the renderer.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mbrt/scene.h"
#include "mbrt/scenes.h"

namespace mbrt {

// How texture coordinates outside [0,1] map onto the image (glTF's sampler
// wrap modes).
enum class TextureWrap : uint8_t { Repeat, ClampToEdge, MirroredRepeat };

// An 8-bit sRGB image for colour lookups. Texture coordinates follow glTF:
// (0,0) is the top-left corner of the first (top) row, (1,1) the
// bottom-right corner. Lookups undo the sRGB curve, then filter.
struct Texture {
  std::string name;           // for messages: the file, or "file: image N"
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;   // width * height * 3 bytes, row-major, top row first
  TextureWrap wrapU = TextureWrap::Repeat, wrapV = TextureWrap::Repeat;
  bool nearest = false;       // nearest texel; else bilinear
};

struct Material {
  Vec3f diffuse{0.7f, 0.7f, 0.7f};  // albedo (glTF baseColorFactor, OBJ Kd)
  // Index into SceneDescription::textures, or -1: the albedo is `diffuse`
  // times the texture's colour at the hit's texture coordinates.
  int32_t texture = -1;
};

struct TexCoord {
  float u = 0.0f, v = 0.0f;
};

// Render-side data of one top-level geometry beyond its material. For an
// instance they describe geometry 0 of the instanced scene (as the glTF
// loader builds instances); hits on its other geometries get none.
struct GeometrySurface {
  // Per vertex (the same count as the geometry's vertices); empty: none, and
  // textures are not looked up.
  std::vector<TexCoord> texcoords;
  // Per triangle, an index into `materials` (OBJ usemtl); empty: the
  // geometry's material (SceneDescription::material).
  std::vector<uint32_t> faceMaterials;
  std::vector<Material> materials;
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
  std::vector<GeometrySurface> surfaces;  // per top-level geometry id; missing entries: none
  std::vector<Texture> textures;      // what Material::texture indexes
  std::vector<DirectionalLight> lights{DirectionalLight{}};
  Vec3f skyColor{0.55f, 0.65f, 0.8f}; // radiance of the environment (AO and path tracing)
  // The shutter the scene was sampled for, in the source's own units (e.g.
  // seconds of a glTF clip); informational.
  double shutterOpen = 0.0, shutterClose = 1.0;
  // True when the input set up its own surroundings (JSON scene files, the
  // built-in scenes); a loaded model (glTF, OBJ, PLY) does not, and the
  // renderer's command puts it on a stage (addStage in loaders.h).
  bool bringsEnvironment = false;

  const Material& material(uint32_t geomID) const {
    static const Material fallback;
    return geomID < materials.size() ? materials[geomID] : fallback;
  }
};

}  // namespace mbrt
