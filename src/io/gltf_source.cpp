// A glTF clip as an animation source (animation_source.h): the file read
// once, the scene of each shutter sampled by the loader.
#include <limits>

#include "io/animation_source.h"
#include "io/gltf_sampler.h"

namespace mbrt::io {
namespace {

class GltfSource : public AnimationSource {
 public:
  GltfSource(const std::string& path, const AnimationOptions& options, LoadReport* report)
      : sampler_(path, options.clip, options.steps, report) {
    shared_ = sampler_.surfaces();
    if (sampler_.clip() < 0) {
      timeline_.start = 0.0;
      timeline_.end = std::numeric_limits<double>::infinity();
      timeline_.what = "no clip (static)";
    } else {
      timeline_.start = sampler_.clipStart();
      timeline_.end = sampler_.clipEnd();
      timeline_.what = "clip " + sampler_.clipName();
    }
  }

  FrameGeometry over(double open, double close, LoadReport* report) override {
    return sampler_.sample(open, close, report);
  }

  std::pair<double, double> pictureShutter(double fps, double shutterAngleDegrees) const override {
    GltfOptions o;
    o.fps = fps;
    o.shutterAngleDegrees = shutterAngleDegrees;
    return sampler_.shutter(o);
  }

 private:
  gltf::ClipSampler sampler_;
};

}  // namespace

std::unique_ptr<AnimationSource> gltfSource(const std::string& path, const AnimationOptions& options,
                                            LoadReport* report) {
  return std::make_unique<GltfSource>(path, options, report);
}

}  // namespace mbrt::io
