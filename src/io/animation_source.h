// What an Animation (mbrt/io/animation.h) samples: one source per kind of
// input, each loaded once.
//   gltf_source.cpp    a glTF clip, sampled over each shutter by the loader
//   sliced_source.cpp  the other inputs: loaded over their whole timeline,
//                      sliced to each shutter
#pragma once

#include <memory>
#include <string>
#include <utility>

#include "mbrt/io/animation.h"

namespace mbrt::io {

// The geometry and camera of one shutter.
struct FrameGeometry {
  std::shared_ptr<Scene> scene;
  Camera camera;
};

class AnimationSource {
 public:
  virtual ~AnimationSource() = default;
  const Timeline& timeline() const { return timeline_; }
  // What every shutter shares: name, materials, surfaces, textures, lights,
  // sky (no scene, the default camera).
  const SceneDescription& shared() const { return shared_; }
  SceneDescription& shared() { return shared_; }
  // The geometry over [open, close] seconds, inside the timeline (checked by
  // the caller), its motion normalized to [0, 1]; owns its data.
  virtual FrameGeometry over(double open, double close, LoadReport* report) = 0;
  // Animation::pictureShutter.
  virtual std::pair<double, double> pictureShutter(double fps, double shutterAngleDegrees) const = 0;

 protected:
  Timeline timeline_;
  SceneDescription shared_;
};

std::unique_ptr<AnimationSource> gltfSource(const std::string& path, const AnimationOptions& options,
                                            LoadReport* report);
std::unique_ptr<AnimationSource> slicedSource(const std::string& spec, const AnimationOptions& options,
                                              LoadReport* report);

}  // namespace mbrt::io
