// The stage for a loaded model that brings no surroundings: a ground plane
// under it (y up, as in glTF), checkered so that motion over it reads,
// lit by the description's sun and sky, so the model casts a shadow.
#include <algorithm>
#include <cmath>

#include "mbrt/io/loaders.h"

namespace mbrt {

bool addStage(SceneDescription& d, const Box3f* over) {
  if (d.bringsEnvironment || !d.scene) return false;
  const Box3f box = over ? *over : sceneBounds(*d.scene);
  if (box.empty() || !isFinite(box.lower) || !isFinite(box.upper)) return false;
  const Vec3f size = box.size(), c = box.center();
  const float extent = std::max({size.x, size.y, size.z});
  if (!(extent > 0.0f)) return false;
  // Just below the lowest point over the shutter, far wider than the model.
  const float y = box.lower.y - 1e-3f * extent;
  const float half = 25.0f * extent;
  // Two checker squares per texture repeat, each a quarter of the model's extent.
  const float square = 0.25f * extent;
  std::vector<Vec3f> corners;
  std::vector<TexCoord> uvs;
  for (const auto& [dx, dz] : {std::pair{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}) {
    corners.push_back({c.x + dx * half, y, c.z + dz * half});
    uvs.push_back({dx * half / (2.0f * square), dz * half / (2.0f * square)});
  }
  // Wound so that the geometric normal points up.
  const uint32_t id = d.scene->addTriangleMesh({{0, 2, 1}, {0, 3, 2}}, std::vector<std::vector<Vec3f>>{corners});

  Texture checker;
  checker.name = "stage checker";
  checker.width = checker.height = 2;
  constexpr uint8_t kLight = 200, kDark = 165;  // sRGB
  checker.rgb = {kLight, kLight, kLight, kDark, kDark, kDark, kDark, kDark, kDark, kLight, kLight, kLight};
  checker.nearest = true;
  d.textures.push_back(std::move(checker));

  // A sun from the upper left, in front of the default camera (which looks
  // along -z): the lit side faces the camera and the shadow falls to the
  // right, behind the model, where it shows.
  d.lights = {DirectionalLight{normalize(Vec3f{0.45f, -0.75f, -0.5f}), {2.6f, 2.45f, 2.2f}}};

  // The ground's material is its own (a face material), so that a
  // description without materials keeps its per-geometry palette.
  d.surfaces.resize(id + 1);
  GeometrySurface& ground = d.surfaces[id];
  ground.texcoords = std::move(uvs);
  ground.materials = {Material{{1.0f, 1.0f, 1.0f}, int32_t(d.textures.size() - 1)}};
  ground.faceMaterials = {0, 0};
  return true;
}

}  // namespace mbrt
