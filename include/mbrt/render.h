// The renderer: a camera over the shutter, deterministic samplers, the
// integrators (normals, ambient occlusion, diffuse path tracing, heat maps of
// traversal work) and tiles rendered in parallel over TBB.
//
// Determinism: every random number is a hash of (seed, pixel, sample,
// dimension), and each pixel is finished by one task, so an image depends on
// the seed only, never on the thread count or the tile order.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/io/image.h"
#include "mbrt/io/scene_description.h"

namespace mbrt {

enum class IntegratorKind {
  Normals,     // primary visibility: the geometric normal facing the viewer
  Ao,          // ambient occlusion with occluded() shadow rays (MSBVH paper)
  Path,        // diffuse path tracing, directional lights + sky (STBVH paper)
  HeatSteps,   // nodes visited per primary ray, colour-mapped, with a colour bar
  HeatIsects,  // ray-primitive tests per primary ray, likewise
  Clusters,    // primary visibility coloured by fuzzykd's motion cluster (fuzzykd only)
};

std::string_view toString(IntegratorKind kind);
std::optional<IntegratorKind> parseIntegratorKind(std::string_view name);
// "normals, ao, path, heat-steps, heat-isects, clusters"
std::string integratorKindList();
inline bool isHeatMap(IntegratorKind k) { return k == IntegratorKind::HeatSteps || k == IntegratorKind::HeatIsects; }

struct RenderOptions {
  int width = 640;
  int height = 360;
  int spp = 16;                 // camera samples per pixel, each at its own stratified time
  float shutterOpen = 0.0f;     // the part of the normalized shutter [0,1] the camera sees
  float shutterClose = 1.0f;
  IntegratorKind integrator = IntegratorKind::Ao;
  uint64_t seed = 1;
  int tileSize = 16;            // pixels per tile side
  // Renders only tiles [tileBegin, tileEnd) in row-major tile order (the
  // rest stays black and the result counts only these): to split one
  // picture over processes. The pixels do not depend on the split.
  size_t tileBegin = 0, tileEnd = SIZE_MAX;
  // Ambient occlusion.
  int aoSamples = 2;            // occlusion rays per camera sample
  float aoDistance = 0.0f;      // occlusion ray length; 0: 5% of the scene's diagonal
  // Path tracing.
  int maxDepth = 4;             // diffuse bounces after the primary hit
  // Heat maps: the value shown at the top of the colour map; 0 picks the
  // 99th percentile of the image's per-pixel means. Fix it to compare images.
  float heatMax = 0.0f;
  bool colorBar = true;         // heat maps: a colour bar along the bottom
};

// Thrown-free progress report, called from worker threads (serialize as
// needed); tilesDone counts up to tilesTotal.
struct RenderProgress {
  size_t tilesDone = 0, tilesTotal = 0;
  uint64_t rays = 0;            // rays traced so far (all kinds)
  double seconds = 0.0;         // since the start
};
using ProgressCallback = std::function<void(const RenderProgress&)>;

struct RenderResult {
  Image image;                  // linear RGB; heat maps already colour-mapped (with their bar)
  bool complete = true;         // false when cancelled: unrendered tiles are black
  size_t tilesDone = 0, tilesTotal = 0;
  double seconds = 0.0;
  uint64_t rays = 0;            // camera + occlusion + shadow + bounce rays
  // Heat maps: per-pixel mean work per primary ray (row-major), the value at
  // the top of the colour map, the image's mean and maximum.
  std::vector<float> heat;
  float heatScale = 0.0f, heatMean = 0.0f, heatMaxValue = 0.0f;
  double raysPerSecond() const { return seconds > 0.0 ? double(rays) / seconds : 0.0; }
};

// Camera rays over the shutter: pinhole or thin lens, possibly moving (the
// camera's keys are interpolated at the ray's time).
class RenderCamera {
 public:
  // A camera without keys is framed on the scene's bounds. Throws Error for a
  // shutter outside [0,1] or open > close, or a degenerate camera.
  RenderCamera(const SceneDescription& scene, int width, int height, float shutterOpen, float shutterClose);

  // (px, py): position on the image in pixels (y down); (lu, lv) in [0,1)^2
  // on the lens; u in [0,1) over the shutter interval.
  Ray generate(float px, float py, float lu, float lv, float u) const;
  float shutterTime(float u) const { return open_ + (close_ - open_) * u; }

 private:
  // The view at a time (keys interpolated) and its distance of focus.
  CameraSpec viewAt(float time) const;
  float focusOf(const CameraSpec& view) const;

  std::vector<CameraSpec> keys_;
  float aperture_ = 0.0f, focusDistance_ = 0.0f;
  float aspect_ = 1.0f, width_ = 1.0f, height_ = 1.0f;
  float open_ = 0.0f, close_ = 1.0f;
};

// The camera ray of sample `s` of pixel (x, y), exactly as render() makes it.
Ray primaryRay(const RenderCamera& camera, const RenderOptions& options, int x, int y, int s);

// Renders in the caller's TBB arena (wrap in a task_arena to choose the
// thread count). When *cancel becomes true, tiles not yet started are
// skipped and the result is marked incomplete. Throws Error for bad options.
RenderResult render(const SceneDescription& scene, const Accel& accel, const RenderOptions& options,
                    const std::atomic<bool>* cancel = nullptr, const ProgressCallback& progress = {});

// Colour-maps heat values (RenderResult::heat, width x height) with `scale`
// at the top of the map, and a colour bar below when asked: e.g. to show two
// structures' heat maps on one scale.
Image heatImage(std::span<const float> heat, int width, int height, float scale, bool colorBar);

// ---- materials (docs/renderer.md, "Materials, textures and the stage") ----

// The linear colour of a texture at (u, v): the sRGB curve undone per
// texel, then nearest or bilinear filtering between texel centres, the wrap
// modes applied to each texel index.
Vec3f textureColor(const Texture& texture, TexCoord uv);

// The albedo at a hit, as the integrators see it: the material of the hit's
// top-level geometry (or of its triangle, GeometrySurface::faceMaterials),
// its diffuse colour times its texture at the texture coordinates
// interpolated with the hit's barycentrics (u, v weigh vertices 1 and 2). A
// description without any materials gets a fixed palette, one colour per
// geometry, so parts are told apart.
Vec3f albedoAt(const SceneDescription& scene, const Hit& hit);

// Throws Error when the description's surfaces do not fit its scene: a
// texture index out of range, texture coordinates whose count is not the
// geometry's vertex count, face materials not one per triangle or out of
// range. render() calls it first.
void validateSurfaces(const SceneDescription& scene);

// Display transform for PNG: exposure (2^ev), then a filmic curve; normals
// and heat maps are left as they are. Returns a new linear image (the PNG
// writer applies the sRGB curve).
Image tonemap(const Image& linear, IntegratorKind kind, float exposureEv = 0.0f);

}  // namespace mbrt
