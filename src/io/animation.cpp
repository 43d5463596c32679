// Animation (mbrt/io/animation.h): the timeline's checks, and the one scene
// handed out, updated in place from frame to frame.
#include "mbrt/io/animation.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>

#include "io/animation_source.h"
#include "mbrt/io/loaders.h"

namespace mbrt {
namespace {

std::string lowerExtension(const std::string& spec) {
  std::string ext = std::filesystem::path(spec).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// True when `next` can replace `current`'s vertices in place: the same
// geometries (types, primitive counts, steps, time ranges, masks), none of
// them instances (whose keys a scene cannot replace).
bool sameLayout(const Scene& current, const Scene& next) {
  if (current.numGeometries() != next.numGeometries() || current.numGeometries() == 0) return false;
  for (uint32_t id = 0; id < current.numGeometries(); ++id) {
    const Geometry &c = current.geometry(id), &n = next.geometry(id);
    if (c.type() == GeometryType::Instance || c.type() != n.type() || c.numPrimitives() != n.numPrimitives() ||
        c.numSteps() != n.numSteps() || !(c.timeRange() == n.timeRange()) || c.mask() != n.mask() ||
        c.vertices(0).count != n.vertices(0).count)
      return false;
  }
  return true;
}

// Points every step of `current`'s meshes and segments at `next`'s vertex
// buffers (sameLayout): `next` must outlive their use.
void adoptVertices(Scene& current, const Scene& next) {
  for (uint32_t id = 0; id < current.numGeometries(); ++id)
    for (uint32_t k = 0; k < current.geometry(id).numSteps(); ++k) current.setVertices(id, k, next.geometry(id).vertices(k));
}

void checkClock(const FrameClock& clock) {
  if (!(clock.fps > 0.0 && std::isfinite(clock.fps)))
    throw Error("the frame rate must be a positive number, got " + number(clock.fps));
  if (!(clock.shutterAngleDegrees >= 0.0 && clock.shutterAngleDegrees <= 360.0))
    throw Error("the shutter angle must be in [0, 360] degrees, got " + number(clock.shutterAngleDegrees));
}

// The tolerance of the timeline's ends (relative to its size).
double slack(const Timeline& t) {
  return 1e-6 * std::max(1.0, std::isfinite(t.end) ? std::fabs(t.end) : std::fabs(t.start));
}

}  // namespace

bool canAnimate(const std::string& input) { return isObjSequenceSpec(input) || lowerExtension(input) != ".json"; }

Animation::Animation(const std::string& input, const AnimationOptions& options, LoadReport* report) : input_(input) {
  const bool sequence = isObjSequenceSpec(input);
  const std::string ext = lowerExtension(input);
  if (!canAnimate(input))
    throw Error("'" + input + "' is a JSON scene file: an animation is made of a glTF clip, an OBJ keyframe "
                "sequence, a built-in scene or a mesh (a scene file's objects keep clocks of their own)");
  source_ = !sequence && (ext == ".gltf" || ext == ".glb") ? io::gltfSource(input, options, report)
                                                           : io::slicedSource(input, options, report);
  if (options.stage) placeStage();
  current_ = source_->shared();
  current_.scene = std::make_shared<Scene>();
}

Animation::~Animation() = default;

const Timeline& Animation::timeline() const { return source_->timeline(); }

// The ground is placed from the scene at the timeline's first instant, so
// that it stays put while the model moves (and is the same whatever frame
// is sampled first).
void Animation::placeStage() {
  const Timeline& t = timeline();
  SceneDescription staged = source_->shared();
  staged.scene = source_->over(t.start, t.start, nullptr).scene;
  const uint32_t ground = staged.scene->numGeometries();
  if (!addStage(staged)) return;
  const Geometry& plane = staged.scene->geometry(ground);
  groundTriangles_.assign(plane.triangles().begin(), plane.triangles().end());
  for (size_t i = 0; i < plane.vertices(0).count; ++i) groundVertices_.push_back(plane.vertices(0)[i]);
  staged.scene.reset();
  source_->shared() = std::move(staged);
}

FrameRange Animation::frames(const FrameClock& clock) const {
  checkClock(clock);
  const Timeline& t = timeline();
  const double length = clock.closeAt(0) - clock.openAt(0);
  const double first = std::max(0.0, std::ceil(t.start * clock.fps - 1e-6));
  if (!std::isfinite(t.end)) return {int64_t(first), std::numeric_limits<int64_t>::max()};
  const double last = std::floor((t.end - length) * clock.fps + 1e-6);
  return {int64_t(first), last >= first ? int64_t(last - first) + 1 : 0};
}

void Animation::checkFrame(int64_t frame, const FrameClock& clock) const {
  checkClock(clock);
  const Timeline& t = timeline();
  const double open = clock.openAt(frame), close = clock.closeAt(frame), eps = slack(t);
  if (frame >= 0 && open >= t.start - eps && close <= t.end + eps) return;
  const FrameRange r = frames(clock);
  const std::string allowed =
      r.count > 0 ? "frames " + std::to_string(r.first) + " to " + std::to_string(r.first + r.count - 1) + " at " +
                        number(clock.fps) + " fps with a " + number(clock.shutterAngleDegrees) + " degree shutter"
                  : "no whole frame at " + number(clock.fps) + " fps";
  throw Error("frame " + std::to_string(frame) + "'s shutter [" + number(open) + ", " + number(close) +
              "] s lies outside the timeline of '" + input_ + "' (" + t.what + ", " + number(t.start) + " to " +
              number(t.end) + " s): " + allowed);
}

void Animation::checkShutter(double open, double close) const {
  const Timeline& t = timeline();
  const double eps = slack(t);
  if (!std::isfinite(open) || !std::isfinite(close) || close < open)
    throw Error("'" + input_ + "': a shutter [open, close] needs finite seconds with open <= close, got [" +
                number(open) + ", " + number(close) + "]");
  if (open < t.start - eps || close > t.end + eps)
    throw Error("the shutter [" + number(open) + ", " + number(close) + "] s lies outside the timeline of '" + input_ +
                "' (" + t.what + ", " + number(t.start) + " to " + number(t.end) + " s)");
}

io::FrameGeometry Animation::sample(double open, double close, LoadReport* report) {
  checkShutter(open, close);
  io::FrameGeometry g = source_->over(open, close, report);
  if (!groundTriangles_.empty())
    g.scene->addTriangleMesh(groundTriangles_, std::vector<std::vector<Vec3f>>{groundVertices_});
  return g;
}

SceneDescription& Animation::frame(int64_t frame, const FrameClock& clock, LoadReport* report) {
  checkFrame(frame, clock);
  return sceneOver(clock.openAt(frame), clock.closeAt(frame), report);
}

SceneDescription& Animation::sceneOver(double open, double close, LoadReport* report) {
  io::FrameGeometry next = sample(open, close, report);
  Scene& scene = *current_.scene;
  if (sameLayout(scene, *next.scene)) {
    adoptVertices(scene, *next.scene);
    vertexOwner_ = std::move(next.scene);
    change_ = SceneChange::Vertices;
  } else {
    scene = std::move(*next.scene);  // expires the accels built over the old layout
    vertexOwner_.reset();
    change_ = SceneChange::Layout;
  }
  current_.camera = std::move(next.camera);
  current_.shutterOpen = open;
  current_.shutterClose = close;
  return current_;
}

SceneDescription Animation::describe(double open, double close, LoadReport* report) {
  io::FrameGeometry g = sample(open, close, report);
  SceneDescription out = source_->shared();
  out.scene = std::move(g.scene);
  out.camera = std::move(g.camera);
  out.shutterOpen = open;
  out.shutterClose = close;
  return out;
}

std::pair<double, double> Animation::pictureShutter(double fps, double shutterAngleDegrees) const {
  checkClock({fps, shutterAngleDegrees});
  return source_->pictureShutter(fps, shutterAngleDegrees);
}

}  // namespace mbrt
