// Materials at a hit: diffuse colour times a texture looked up at the
// texture coordinates interpolated with the hit's barycentrics.
#include <algorithm>
#include <array>
#include <cmath>

#include "mbrt/render.h"

namespace mbrt {
namespace {

// The sRGB transfer curve undone, per 8-bit value.
const std::array<float, 256>& srgbToLinear() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) {
      const double c = i / 255.0;
      t[size_t(i)] = float(c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4));
    }
    return t;
  }();
  return table;
}

// A coordinate folded into the range its wrap mode repeats: [0,1) for
// Repeat, [0,2) for MirroredRepeat, [0,1] for ClampToEdge; NaN and
// infinities give 0.
float fold(float c, TextureWrap wrap) {
  if (!std::isfinite(c)) return 0.0f;
  switch (wrap) {
    case TextureWrap::Repeat: return std::clamp(c - std::floor(c), 0.0f, 1.0f);
    case TextureWrap::MirroredRepeat: return std::clamp(c - 2.0f * std::floor(0.5f * c), 0.0f, 2.0f);
    case TextureWrap::ClampToEdge: break;
  }
  return std::clamp(c, 0.0f, 1.0f);
}

// A texel index (of a folded coordinate, so within [-1, 2n]) mapped into [0, n).
int wrapIndex(int i, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::Repeat: return ((i % n) + n) % n;
    case TextureWrap::MirroredRepeat: {
      const int m = ((i % (2 * n)) + 2 * n) % (2 * n);
      return m < n ? m : 2 * n - 1 - m;
    }
    case TextureWrap::ClampToEdge: break;
  }
  return std::clamp(i, 0, n - 1);
}

Vec3f texel(const Texture& t, int x, int y) {
  const auto& lut = srgbToLinear();
  const uint8_t* p = &t.rgb[(size_t(y) * size_t(t.width) + size_t(x)) * 3];
  return {lut[p[0]], lut[p[1]], lut[p[2]]};
}

// A fixed palette for descriptions without materials: the first colour
// (often a floor or the only mesh) is light grey.
Vec3f paletteColor(uint32_t geomID) {
  static constexpr Vec3f kPalette[] = {{0.60f, 0.60f, 0.58f}, {0.75f, 0.18f, 0.12f}, {0.12f, 0.35f, 0.75f},
                                       {0.25f, 0.55f, 0.15f}, {0.85f, 0.60f, 0.10f}, {0.50f, 0.25f, 0.60f},
                                       {0.15f, 0.60f, 0.60f}, {0.80f, 0.45f, 0.55f}};
  constexpr uint32_t n = sizeof(kPalette) / sizeof(kPalette[0]);
  return geomID == kInvalidId ? kPalette[0] : kPalette[geomID % n];
}

// The triangle mesh a surface describes: the geometry itself, or geometry 0
// of an instance's scene; null otherwise.
const Geometry* surfaceMesh(const Scene& scene, uint32_t top) {
  const Geometry& g = scene.geometry(top);
  const Geometry* mesh = &g;
  if (g.type() == GeometryType::Instance) {
    const Scene* child = g.instancedScene();
    mesh = child && child->numGeometries() > 0 ? &child->geometry(0) : nullptr;
  }
  return mesh && mesh->type() == GeometryType::Triangles ? mesh : nullptr;
}

}  // namespace

Vec3f textureColor(const Texture& t, TexCoord uv) {
  if (t.width < 1 || t.height < 1 || t.rgb.size() != size_t(t.width) * size_t(t.height) * 3) return Vec3f(0.0f);
  const float x = fold(uv.u, t.wrapU) * float(t.width), y = fold(uv.v, t.wrapV) * float(t.height);
  if (t.nearest)
    return texel(t, wrapIndex(int(std::floor(x)), t.width, t.wrapU), wrapIndex(int(std::floor(y)), t.height, t.wrapV));
  // Bilinear between the four texel centres around (x, y).
  const float fx = x - 0.5f, fy = y - 0.5f;
  const float x0f = std::floor(fx), y0f = std::floor(fy);
  const float ax = fx - x0f, ay = fy - y0f;
  const int x0 = int(x0f), y0 = int(y0f);
  const int xa = wrapIndex(x0, t.width, t.wrapU), xb = wrapIndex(x0 + 1, t.width, t.wrapU);
  const int ya = wrapIndex(y0, t.height, t.wrapV), yb = wrapIndex(y0 + 1, t.height, t.wrapV);
  const Vec3f top = texel(t, xa, ya) * (1.0f - ax) + texel(t, xb, ya) * ax;
  const Vec3f bottom = texel(t, xa, yb) * (1.0f - ax) + texel(t, xb, yb) * ax;
  return top * (1.0f - ay) + bottom * ay;
}

Vec3f albedoAt(const SceneDescription& scene, const Hit& hit) {
  // Materials belong to top-level geometries: the instance when the hit is inside one.
  const uint32_t top = hit.instID != kInvalidId ? hit.instID : hit.geomID;
  const GeometrySurface* surf = top < scene.surfaces.size() ? &scene.surfaces[top] : nullptr;
  // Only geometry 0 of an instanced scene has the surface's per-vertex data.
  const bool onSurfaceMesh = hit.instID == kInvalidId || hit.geomID == 0;
  const Material* mat = nullptr;
  if (surf && onSurfaceMesh && hit.primID < surf->faceMaterials.size())
    mat = &surf->materials[surf->faceMaterials[hit.primID]];
  else if (scene.materials.empty())
    return paletteColor(top);
  else
    mat = &scene.material(top);
  if (mat->texture < 0 || !surf || surf->texcoords.empty() || !onSurfaceMesh || size_t(mat->texture) >= scene.textures.size())
    return mat->diffuse;
  const Geometry* mesh = surfaceMesh(*scene.scene, top);
  if (!mesh || hit.primID >= mesh->numPrimitives()) return mat->diffuse;
  const Triangle tri = mesh->triangles()[hit.primID];
  const std::vector<TexCoord>& tc = surf->texcoords;
  if (std::max({tri.v0, tri.v1, tri.v2}) >= tc.size()) return mat->diffuse;
  const float w0 = 1.0f - hit.u - hit.v;
  const TexCoord uv{w0 * tc[tri.v0].u + hit.u * tc[tri.v1].u + hit.v * tc[tri.v2].u,
                    w0 * tc[tri.v0].v + hit.u * tc[tri.v1].v + hit.v * tc[tri.v2].v};
  return mat->diffuse * textureColor(scene.textures[size_t(mat->texture)], uv);
}

void validateSurfaces(const SceneDescription& d) {
  auto fail = [](const std::string& what) { throw Error("render: " + what); };
  for (size_t i = 0; i < d.textures.size(); ++i) {
    const Texture& t = d.textures[i];
    if (t.width < 1 || t.height < 1 || t.rgb.size() != size_t(t.width) * size_t(t.height) * 3)
      fail("texture " + std::to_string(i) + " '" + t.name + "' has " + std::to_string(t.rgb.size()) +
           " bytes, not width x height x 3");
  }
  auto checkMaterial = [&](const Material& m, const std::string& what) {
    if (m.texture >= 0 && size_t(m.texture) >= d.textures.size())
      fail(what + " uses texture " + std::to_string(m.texture) + " of " + std::to_string(d.textures.size()));
    if (!isFinite(m.diffuse)) fail(what + " has a non-finite diffuse colour");
  };
  for (size_t i = 0; i < d.materials.size(); ++i) checkMaterial(d.materials[i], "material " + std::to_string(i));
  if (d.surfaces.size() > d.scene->numGeometries())
    fail(std::to_string(d.surfaces.size()) + " geometry surfaces for " + std::to_string(d.scene->numGeometries()) +
         " geometries");
  for (uint32_t id = 0; id < d.surfaces.size(); ++id) {
    const GeometrySurface& s = d.surfaces[id];
    const std::string what = "geometry " + std::to_string(id);
    if (s.texcoords.empty() && s.faceMaterials.empty()) continue;
    const Geometry* mesh = surfaceMesh(*d.scene, id);
    if (!mesh) fail(what + " has texture coordinates or face materials but no triangle mesh");
    if (!s.texcoords.empty() && s.texcoords.size() != mesh->vertices(0).count)
      fail(what + " has " + std::to_string(s.texcoords.size()) + " texture coordinates for " +
           std::to_string(mesh->vertices(0).count) + " vertices");
    if (!s.faceMaterials.empty() && s.faceMaterials.size() != mesh->numPrimitives())
      fail(what + " has " + std::to_string(s.faceMaterials.size()) + " face materials for " +
           std::to_string(mesh->numPrimitives()) + " triangles");
    for (uint32_t f : s.faceMaterials)
      if (f >= s.materials.size())
        fail(what + " uses face material " + std::to_string(f) + " of " + std::to_string(s.materials.size()));
    for (size_t m = 0; m < s.materials.size(); ++m) checkMaterial(s.materials[m], what + " material " + std::to_string(m));
  }
}

}  // namespace mbrt
