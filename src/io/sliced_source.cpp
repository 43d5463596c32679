// Inputs without a clip of their own as animation sources
// (animation_source.h): an OBJ keyframe sequence, a built-in scene, a mesh
// with a procedural motion, loaded once over their whole timeline and
// sliced to each shutter: every moving geometry resampled on equidistant
// steps of its interpolated motion, exact at the old step times.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <span>

#include "io/animation_source.h"
#include "mbrt/io/loaders.h"

namespace mbrt::io {
namespace {

// The value of a step-interpolated quantity at normalized time t, exact at
// step times: keys(k) for k in [0, S), lerp(a, b, f) between.
template <class Value, class Keys, class Lerp>
Value sampleSteps(const Geometry& g, double t, const Keys& keys, const Lerp& mix) {
  const uint32_t s = g.numSteps();
  if (s == 1) return keys(0u);
  const TimeRange r = g.timeRange();
  const double local = std::clamp((t - double(r.lo)) / double(r.size()) * double(s - 1), 0.0, double(s - 1));
  const double nearest = std::round(local);
  if (std::fabs(local - nearest) < 1e-6) return keys(uint32_t(nearest));
  const uint32_t k = std::min(uint32_t(local), s - 2);
  return mix(keys(k), keys(k + 1), float(local - double(k)));
}

// `scene`'s motion over the part [a, b] of its normalized shutter,
// stretched to [0, 1]: every moving geometry gets max(2, ceil(its steps
// over [a, b])) equidistant steps; a geometry that does not exist in [a, b]
// gets mask 0. Static instanced scenes are shared, moving ones sliced once.
class Slicer {
 public:
  Slicer(double a, double b) : a_(a), b_(b) {}

  std::shared_ptr<Scene> slice(const Scene& in) {
    auto out = std::make_shared<Scene>();
    for (uint32_t id = 0; id < in.numGeometries(); ++id) add(in.geometry(id), *out);
    return out;
  }

 private:
  // The step times, in the old normalized time, of a geometry over [a, b],
  // and its new time range; empty when it does not exist in [a, b].
  std::vector<double> stepTimes(const Geometry& g, TimeRange& range) const {
    const TimeRange r = g.timeRange();
    const double lo = std::max(double(r.lo), a_), hi = std::min(double(r.hi), b_);
    if (hi < lo || (hi == lo && !(b_ == a_ && r.contains(float(a_))))) return {};
    const double span = b_ - a_;
    range = span > 0.0 ? TimeRange{float((lo - a_) / span), float((hi - a_) / span)} : TimeRange{};
    if (range.hi <= range.lo) range = TimeRange{};
    if (g.numSteps() == 1) return {lo};
    const double stepsOver = (hi - lo) / double(r.size()) * double(g.numSteps() - 1);
    const uint32_t n = std::max<uint32_t>(2, uint32_t(std::ceil(stepsOver - 1e-9)) + 1);
    std::vector<double> times(n);
    for (uint32_t k = 0; k < n; ++k) times[k] = lo + (hi - lo) * double(k) / double(n - 1);
    return times;
  }

  std::vector<std::vector<Vec3f>> vertexSteps(const Geometry& g, const std::vector<double>& times) const {
    const size_t count = g.vertices(0).count;
    std::vector<std::vector<Vec3f>> steps(times.size(), std::vector<Vec3f>(count));
    for (size_t k = 0; k < times.size(); ++k)
      for (size_t i = 0; i < count; ++i)
        steps[k][i] = sampleSteps<Vec3f>(
            g, times[k], [&](uint32_t s) { return g.vertexAtStep(s, uint32_t(i)); },
            [](const Vec3f& x, const Vec3f& y, float f) { return lerp(x, y, f); });
    return steps;
  }

  std::shared_ptr<const Scene> child(const Geometry& g) {
    const auto& shared = g.instancedSceneShared();
    if (shared->maxSegments() == 0) return shared;
    auto found = children_.find(shared.get());
    if (found != children_.end()) return found->second;
    return children_.emplace(shared.get(), slice(*shared)).first->second;
  }

  template <class Key>
  std::vector<Key> keysAt(const Geometry& g, const std::vector<double>& times, std::span<const Key> keys) const {
    std::vector<Key> out;
    for (double t : times)
      out.push_back(sampleSteps<Key>(
          g, t, [&](uint32_t s) { return keys[s]; }, [](const Key& x, const Key& y, float f) { return lerp(x, y, f); }));
    return out;
  }

  void add(const Geometry& g, Scene& out) {
    TimeRange range;
    std::vector<double> times = stepTimes(g, range);
    const bool absent = times.empty();
    if (absent) times = {std::clamp(a_, double(g.timeRange().lo), double(g.timeRange().hi))};
    uint32_t id = 0;
    if (g.type() == GeometryType::Instance) {
      id = g.hasSRTKeys() ? out.addInstance(child(g), keysAt<SRTKey>(g, times, g.srtKeys()), range)
                          : out.addInstance(child(g), keysAt<Affine3f>(g, times, g.transforms()), range);
    } else if (g.type() == GeometryType::Segments) {
      id = out.addSegments({g.segments().begin(), g.segments().end()}, vertexSteps(g, times),
                           {g.radii().begin(), g.radii().end()}, range);
    } else {
      id = out.addTriangleMesh({g.triangles().begin(), g.triangles().end()}, vertexSteps(g, times), range);
    }
    out.setMask(id, absent ? 0u : g.mask());
  }

  double a_, b_;
  std::map<const Scene*, std::shared_ptr<const Scene>> children_;
};

CameraSpec mixCamera(const CameraSpec& x, const CameraSpec& y, float f) {
  CameraSpec c;
  c.eye = lerp(x.eye, y.eye, f);
  c.target = lerp(x.target, y.target, f);
  c.up = lerp(x.up, y.up, f);
  c.verticalFovDegrees = x.verticalFovDegrees + (y.verticalFovDegrees - x.verticalFovDegrees) * f;
  return c;
}

// The camera's equidistant keys over [a, b] (two when it moves).
Camera sliceCamera(const Camera& in, double a, double b) {
  Camera out = in;
  if (in.keys.size() < 2) return out;
  out.keys.clear();
  for (double t : {a, b}) {
    const double x = t * double(in.keys.size() - 1);
    const size_t k = std::min(size_t(x), in.keys.size() - 2);
    out.keys.push_back(mixCamera(in.keys[k], in.keys[k + 1], float(x - double(k))));
  }
  return out;
}

class SlicedSource : public AnimationSource {
 public:
  SlicedSource(const std::string& spec, const AnimationOptions& options, LoadReport* report) {
    if (!(options.keysPerSecond > 0.0 && std::isfinite(options.keysPerSecond)))
      throw Error("'" + spec + "': keys per second must be a positive number");
    LoadOptions load;
    load.motion = options.motion;
    load.size = options.size;
    load.seed = options.seed;
    shared_ = loadSceneSpec(spec, load, report);
    whole_ = std::move(shared_.scene);
    camera_ = shared_.camera;
    if (isObjSequenceSpec(spec)) {
      const uint32_t keys = whole_->maxSegments() + 1;
      timeline_.end = double(keys - 1) / options.keysPerSecond;
      char buf[96];
      std::snprintf(buf, sizeof buf, "%u keys at %g fps", keys, options.keysPerSecond);
      timeline_.what = buf;
    } else {
      timeline_.what = "motion over one second";
    }
  }

  FrameGeometry over(double open, double close, LoadReport*) override {
    const double span = timeline_.end - timeline_.start;
    const double a = span > 0.0 ? std::clamp((open - timeline_.start) / span, 0.0, 1.0) : 0.0;
    const double b = span > 0.0 ? std::clamp((close - timeline_.start) / span, 0.0, 1.0) : 0.0;
    Slicer slicer(a, b);
    return {slicer.slice(*whole_), sliceCamera(camera_, a, b)};
  }

  std::pair<double, double> pictureShutter(double, double) const override {
    return {timeline_.start, timeline_.end};
  }

 private:
  std::shared_ptr<const Scene> whole_;
  Camera camera_;
};

}  // namespace

std::unique_ptr<AnimationSource> slicedSource(const std::string& spec, const AnimationOptions& options,
                                              LoadReport* report) {
  return std::make_unique<SlicedSource>(spec, options, report);
}

}  // namespace mbrt::io
