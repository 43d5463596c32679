// An input's timeline in seconds and its scene over any shutter on it: the
// one meaning of --shutter and of a frame's shutter for every input
// (docs/renderer.md, "Time"):
//   glTF          seconds of the clip (the clip's own time axis);
//   OBJ sequence  key k at k / fps seconds;
//   built-in scenes and meshes with --motion: their motion over one second,
//                 [0, 1] s.
// glTF files are sampled by the loader over the shutter; the other inputs
// are loaded once over their whole timeline and sliced (resampled on
// equidistant steps) to the shutter.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "scene_loading.h"

namespace mbrt::tools {

struct Timeline {
  double start = 0.0, end = 1.0;  // seconds
  std::string what;               // "clip 0 'Walk'", "29 keys at 24 fps", ...
};

// Whether `spec` is a glTF file (its clock: the clip's seconds).
bool isGltfSpec(const std::string& spec);

class FrameSource {
 public:
  // Loads what the frames share: the whole timeline of inputs without a
  // clip, the clip's span of glTF files. UsageError for JSON scene files.
  explicit FrameSource(const SceneArgs& args);

  const Timeline& timeline() const { return timeline_; }
  // The scene over the shutter [open, close] seconds, its motion normalized
  // to [0, 1]. The result owns its data (nothing is shared with the source
  // but static instanced scenes).
  SceneDescription sceneOver(double open, double close);

 private:
  SceneArgs args_;
  bool gltf_ = false;
  Timeline timeline_;
  SceneDescription whole_;  // inputs without a clip: the whole timeline
};

// `scene`'s motion over the part [a, b] of its normalized shutter, stretched
// to [0, 1]: every moving geometry gets max(2, ceil(its steps over [a, b]))
// equidistant steps sampled from its interpolated motion (exact at the old
// step times); a geometry that does not exist in [a, b] gets mask 0.
std::shared_ptr<Scene> sliceScene(const Scene& scene, double a, double b);

// True when `next` can replace `current`'s vertices in place: the same
// geometries (types, primitive counts, steps, time ranges, masks), none of
// them instances (whose keys a scene cannot replace).
bool sameLayout(const Scene& current, const Scene& next);
// Points every step of `current`'s meshes and segments at `next`'s vertex
// buffers: `next` must outlive their use. Needs sameLayout.
void adoptVertices(Scene& current, const Scene& next);

}  // namespace mbrt::tools
