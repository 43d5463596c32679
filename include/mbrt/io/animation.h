// An input over its timeline, frame by frame: a glTF clip, an OBJ keyframe
// sequence, a built-in scene or a mesh with a procedural motion, loaded
// once (a glTF file is read and its textures decoded once), and the scene
// over any shutter on its timeline, updated in place from one frame to the
// next (docs/renderer.md, "Time" and "Frame sequences").
//
// Timeline, in seconds:
//   glTF          the clip's own seconds (a file without a clip: [0, inf),
//                 static);
//   OBJ sequence  key k at k / keysPerSecond seconds;
//   built-in scenes and meshes: their motion over one second, [0, 1] s.
// Every scene the animation hands out has its motion normalized to the
// shutter [0, 1] it was sampled over.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "mbrt/io/gltf.h"
#include "mbrt/io/scene_description.h"

namespace mbrt {

namespace io {
class AnimationSource;
struct FrameGeometry;
}

struct Timeline {
  double start = 0.0, end = 1.0;  // seconds; end is +inf for a glTF file without a clip
  std::string what;               // "clip 0 'Walk'", "29 keys at 24 fps", "motion over one second", ...
};

// Frame f's shutter: open at f / fps seconds, for shutterAngleDegrees / 360
// of a frame (180: half of it).
struct FrameClock {
  double fps = 24.0;
  double shutterAngleDegrees = 180.0;
  double openAt(int64_t frame) const { return double(frame) / fps; }
  double closeAt(int64_t frame) const { return openAt(frame) + shutterAngleDegrees / 360.0 / fps; }
};

// The frames first, first + 1, ..., first + count - 1 whose shutters lie in
// a timeline; count is INT64_MAX for an unbounded one (a static glTF file).
struct FrameRange {
  int64_t first = 0, count = 0;
};

struct AnimationOptions {
  std::string clip;            // glTF animation by name or index; empty: the first
  StepOptions steps;           // glTF: time steps per moving mesh or instance
  double keysPerSecond = 24.0; // OBJ sequences: key k at k / keysPerSecond seconds
  std::string motion;          // procedural motion of a static .obj/.ply mesh (parseProceduralMotion)
  double size = 1.0;           // built-in scenes
  uint64_t seed = 1;
  // A loaded model (glTF, OBJ, PLY) stands on a stage (addStage, loaders.h)
  // placed once from the timeline's first instant, the same in every frame.
  bool stage = false;
};

// Whether an Animation can be made of `input`: every input but a JSON scene
// file (whose objects keep clocks of their own).
bool canAnimate(const std::string& input);

// How the last frame changed the scene.
enum class SceneChange {
  None,      // no frame yet: the scene is empty
  Vertices,  // the same geometries, primitive counts, steps, time ranges and masks: vertices replaced in place
  Layout,    // anything else (the first frame, an instance's keys, a step count that changed): geometries replaced
};

// Not thread-safe. Sampling a frame changes the scene: it needs exclusive
// access (no Accel over the scene may be used meanwhile, mbrt/accel.h).
class Animation {
 public:
  // Loads `input`: a .gltf/.glb file (options.clip), an OBJ keyframe
  // sequence (a folder or a glob), a built-in scene name, an .obj/.ply mesh
  // (options.motion). Throws Error for a JSON scene file (its objects keep
  // clocks of their own), unknown names, missing or bad files and bad
  // options. `report`: what the loader chose.
  explicit Animation(const std::string& input, const AnimationOptions& options = {}, LoadReport* report = nullptr);
  ~Animation();
  Animation(const Animation&) = delete;
  Animation& operator=(const Animation&) = delete;

  const std::string& input() const { return input_; }
  const Timeline& timeline() const;
  // The whole frames of the timeline at `clock`. Throws Error for a bad clock.
  FrameRange frames(const FrameClock& clock) const;
  // Throws Error naming the frames the timeline allows when frame f's
  // shutter lies outside it (or f < 0), and for a bad clock (fps <= 0, an
  // angle outside [0, 360]).
  void checkFrame(int64_t frame, const FrameClock& clock) const;

  // The scene over frame f's shutter (checkFrame first): sceneOver(
  // clock.openAt(f), clock.closeAt(f)).
  SceneDescription& frame(int64_t frame, const FrameClock& clock, LoadReport* report = nullptr);
  // The scene over the shutter [open, close] seconds of the timeline. The
  // description and its Scene are the same objects from call to call (their
  // addresses stay): when the layout stays (change() == Vertices) the
  // scene's vertex buffers are replaced in place, so that an Accel built over
  // it can refit; otherwise the scene is assigned anew, which expires every
  // Accel built over it (Scene::lifetime()). The caller may change the
  // description's camera; every call replaces it. Throws Error for a shutter
  // that is not finite, has open > close or lies outside the timeline.
  SceneDescription& sceneOver(double open, double close, LoadReport* report = nullptr);
  SceneDescription& current() { return current_; }
  const SceneDescription& current() const { return current_; }
  SceneChange change() const { return change_; }

  // A separate description over [open, close] seconds (its own Scene,
  // untouched by later frames), as loadSceneSpec loads one picture.
  SceneDescription describe(double open, double close, LoadReport* report = nullptr);
  // The shutter loadSceneSpec gives one picture: a glTF clip's start, open
  // shutterAngleDegrees / 360 of a frame at fps (clamped to the clip); the
  // whole timeline of the other inputs. Throws Error for fps <= 0.
  std::pair<double, double> pictureShutter(double fps, double shutterAngleDegrees = 180.0) const;

 private:
  void checkShutter(double open, double close) const;
  void placeStage();
  io::FrameGeometry sample(double open, double close, LoadReport* report);

  std::string input_;
  std::unique_ptr<io::AnimationSource> source_;
  SceneDescription current_;            // current_.scene: the one Scene handed out
  std::shared_ptr<Scene> vertexOwner_;  // owns the vertex buffers current_.scene points at (Vertices)
  SceneChange change_ = SceneChange::None;
  // The stage's ground plane, added to every frame (empty: no stage).
  std::vector<Triangle> groundTriangles_;
  std::vector<Vec3f> groundVertices_;
};

}  // namespace mbrt
