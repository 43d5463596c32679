#include "frame_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "mbrt/io/gltf.h"
#include "mbrt/io/mesh_files.h"

namespace mbrt::tools {
namespace {

std::string lowerExtension(const std::string& spec) {
  std::string ext = std::filesystem::path(spec).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

Timeline gltfTimeline(const std::string& path, const std::string& clip) {
  const GltfFileInfo info = inspectGltf(path);
  Timeline t;
  if (info.clips.empty()) {
    t.start = 0.0;
    t.end = std::numeric_limits<double>::infinity();
    t.what = "no clip (static)";
    return t;
  }
  size_t index = 0;
  bool found = clip.empty();
  for (size_t i = 0; i < info.clips.size() && !found; ++i)
    if (info.clips[i].name == clip) index = i, found = true;
  if (!found && std::all_of(clip.begin(), clip.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    index = std::stoul(clip);
    found = index < info.clips.size();
  }
  if (!found) {
    std::string names;
    for (size_t i = 0; i < info.clips.size(); ++i)
      names += (i ? ", " : "") + std::to_string(i) + (info.clips[i].name.empty() ? "" : " '" + info.clips[i].name + "'");
    throw UsageError("--clip: '" + path + "' has no clip '" + clip + "' (its clips: " + names + ")");
  }
  t.start = info.clips[index].start;
  t.end = info.clips[index].end;
  t.what = "clip " + std::to_string(index) + (info.clips[index].name.empty() ? "" : " '" + info.clips[index].name + "'");
  return t;
}

std::string seconds(double s) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", s);
  return buf;
}

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

  void add(const Geometry& g, Scene& out) {
    TimeRange range;
    std::vector<double> times = stepTimes(g, range);
    const bool absent = times.empty();
    if (absent) times = {std::clamp(a_, double(g.timeRange().lo), double(g.timeRange().hi))};
    uint32_t id = 0;
    if (g.type() == GeometryType::Instance) {
      if (g.hasSRTKeys()) {
        std::vector<SRTKey> keys;
        for (double t : times)
          keys.push_back(sampleSteps<SRTKey>(
              g, t, [&](uint32_t s) { return g.srtKeys()[s]; },
              [](const SRTKey& x, const SRTKey& y, float f) { return lerp(x, y, f); }));
        id = out.addInstance(child(g), std::move(keys), range);
      } else {
        std::vector<Affine3f> keys;
        for (double t : times)
          keys.push_back(sampleSteps<Affine3f>(
              g, t, [&](uint32_t s) { return g.transforms()[s]; },
              [](const Affine3f& x, const Affine3f& y, float f) { return lerp(x, y, f); }));
        id = out.addInstance(child(g), std::move(keys), range);
      }
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

}  // namespace

bool isGltfSpec(const std::string& spec) {
  const std::string ext = lowerExtension(spec);
  return ext == ".gltf" || ext == ".glb";
}

FrameSource::FrameSource(const SceneArgs& args) : args_(args) {
  resolveScene(args_);
  gltf_ = isGltfSpec(args_.scene) && !isObjSequenceSpec(args_.scene);
  if (lowerExtension(args_.scene) == ".json" && !isObjSequenceSpec(args_.scene))
    throw UsageError("--frames applies to glTF clips, OBJ keyframe sequences, built-in scenes and meshes, not to "
                     "the JSON scene file '" + args_.scene + "'");
  if (gltf_) {
    timeline_ = gltfTimeline(args_.scene, args_.clip);
    return;
  }
  args_.shutter.clear();
  whole_ = loadScene(args_);
  if (isObjSequenceSpec(args_.scene)) {
    const uint32_t keys = whole_.scene->maxSegments() + 1;
    timeline_.end = double(keys - 1) / args_.fps;
    char buf[96];
    std::snprintf(buf, sizeof buf, "%u keys at %g fps", keys, args_.fps);
    timeline_.what = buf;
  } else {
    timeline_.what = "motion over one second";
  }
}

SceneDescription FrameSource::sceneOver(double open, double close) {
  if (gltf_) {
    args_.shutter = seconds(open) + "," + seconds(close);
    return loadScene(args_);
  }
  const double span = timeline_.end - timeline_.start;
  const double a = span > 0.0 ? std::clamp((open - timeline_.start) / span, 0.0, 1.0) : 0.0;
  const double b = span > 0.0 ? std::clamp((close - timeline_.start) / span, 0.0, 1.0) : 0.0;
  SceneDescription out = whole_;
  out.scene = sliceScene(*whole_.scene, a, b);
  out.camera = sliceCamera(whole_.camera, a, b);
  out.shutterOpen = open;
  out.shutterClose = close;
  return out;
}

std::shared_ptr<Scene> sliceScene(const Scene& scene, double a, double b) {
  if (!(a >= 0.0 && a <= b && b <= 1.0)) throw Error("a scene slice needs 0 <= a <= b <= 1");
  Slicer slicer(a, b);
  return slicer.slice(scene);
}

bool sameLayout(const Scene& current, const Scene& next) {
  if (current.numGeometries() != next.numGeometries()) return false;
  for (uint32_t id = 0; id < current.numGeometries(); ++id) {
    const Geometry &c = current.geometry(id), &n = next.geometry(id);
    if (c.type() == GeometryType::Instance || c.type() != n.type() || c.numPrimitives() != n.numPrimitives() ||
        c.numSteps() != n.numSteps() || !(c.timeRange() == n.timeRange()) || c.mask() != n.mask() ||
        c.vertices(0).count != n.vertices(0).count)
      return false;
  }
  return true;
}

void adoptVertices(Scene& current, const Scene& next) {
  for (uint32_t id = 0; id < current.numGeometries(); ++id)
    for (uint32_t k = 0; k < current.geometry(id).numSteps(); ++k) current.setVertices(id, k, next.geometry(id).vertices(k));
}

}  // namespace mbrt::tools
