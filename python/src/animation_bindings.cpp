// mbrt.load and what it returns: a Document (a Scene over one shutter, and
// the input's timeline and frames through mbrt::Animation) and its frames,
// each with the one frame Scene updated in place and an Accel following it.
#include <chrono>
#include <limits>
#include <mutex>
#include <optional>

#include "bindings.h"
#include "mbrt/accel_update.h"
#include "mbrt/io/animation.h"
#include "mbrt/io/loaders.h"

namespace mbrt::python {
namespace {

using namespace pybind11::literals;

struct PyDocument : PyScene {
  std::string input;
  std::shared_ptr<Animation> animation;  // null for JSON scene files
  std::shared_ptr<PyScene> frameScene;   // the scene of its frames, made by the first frames()

  Animation& animated() const {
    if (!animation)
      fail("'" + input + "' is a JSON scene file: timelines and frames belong to glTF clips, OBJ keyframe "
           "sequences, built-in scenes and meshes");
    return *animation;
  }
};

struct PyFrame {
  int64_t index = 0;
  std::pair<double, double> shutter;
  std::shared_ptr<PyScene> scene;
  py::object accel = py::none();   // the PyAccel following the frames, or None
  py::object update = py::none();  // a dict of what it did, or None
  double sceneSeconds = 0.0;
  std::string change;              // "vertices" or "layout"
};

// The frames of a document in order, the scene updated in place at each.
struct PyFrames {
  std::shared_ptr<PyDocument> document;
  FrameClock clock;
  std::vector<int64_t> frames;
  size_t next = 0;
  std::shared_ptr<PyAccel> accel;  // null: no structure
  BuildOptions build;
  std::optional<AccelUpdater> updater;

  PyFrame step() {
    if (next == frames.size()) throw py::stop_iteration();
    const int64_t f = frames[next++];
    Animation& a = document->animated();
    PyFrame out;
    out.index = f;
    std::optional<AccelUpdate> done;
    {
      py::gil_scoped_release nogil;
      std::unique_lock lock(sceneLock());  // the frame's scene changes
      const auto start = std::chrono::steady_clock::now();
      SceneDescription& d = a.frame(f, clock);
      out.sceneSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      out.shutter = {d.shutterOpen, d.shutterClose};
      if (accel) {
        done = updater->update(accel->accel, *d.scene, build);
        accel->builtVersion = deepVersion(*d.scene);
      }
    }
    out.scene = document->frameScene;
    out.change = a.change() == SceneChange::Vertices ? "vertices" : "layout";
    if (done) {
      out.accel = py::cast(accel);
      py::dict u;
      u["what"] = done->what;
      u["refitted"] = done->refitted;
      u["seconds"] = done->seconds;
      u["sah_cost"] = done->sah;
      out.update = u;
    }
    return out;
  }
};

std::shared_ptr<PyDocument> load(const std::string& path, const py::object& shutter, const py::object& steps,
                                 const std::string& clip, double fps, const std::string& motion, double size,
                                 uint64_t seed, bool stage) {
  LoadOptions o;
  o.gltf.clip = clip;
  o.gltf.fps = fps;
  o.motion = motion;
  o.size = size;
  o.seed = seed;
  if (!shutter.is_none()) {
    const auto range = shutter.cast<std::pair<double, double>>();
    if (!(range.first <= range.second)) fail("load: shutter must be (open, close) with open <= close (seconds)");
    o.gltf.shutterOpen = range.first;
    o.gltf.shutterClose = range.second;
  }
  if (!steps.is_none() && !(py::isinstance<py::str>(steps) && steps.cast<std::string>() == "auto")) {
    const long n = steps.cast<long>();
    if (n < 1 || n > 1024) fail("load: steps must be from 1 to 1024 or 'auto', got " + std::to_string(n));
    o.gltf.steps.steps = uint32_t(n);
  }
  auto doc = std::make_shared<PyDocument>();
  doc->input = path;
  py::gil_scoped_release nogil;
  if (!canAnimate(path)) {
    doc->description = std::make_shared<SceneDescription>(loadSceneSpec(path, o));
    return doc;
  }
  AnimationOptions a;
  a.clip = clip;
  a.steps = o.gltf.steps;
  a.keysPerSecond = fps;
  a.motion = motion;
  a.size = size;
  a.seed = seed;
  a.stage = stage;
  doc->animation = std::make_shared<Animation>(path, a);
  const auto [open, close] = o.gltf.shutterOpen ? std::pair{*o.gltf.shutterOpen, *o.gltf.shutterClose}
                                                : doc->animation->pictureShutter(fps);
  doc->description = std::make_shared<SceneDescription>(doc->animation->describe(open, close));
  return doc;
}

py::object frameRange(PyDocument& doc, double fps, double shutterAngle) {
  const FrameRange r = doc.animated().frames({fps, shutterAngle});
  return py::module_::import("builtins").attr("range")(r.first, py::int_(r.first) + py::int_(r.count));
}

PyFrames frames(const std::shared_ptr<PyDocument>& doc, double fps, double shutterAngle, const py::object& which,
                const py::object& accelKind, const std::string& update, double rebuildFactor) {
  Animation& a = doc->animated();
  PyFrames out;
  out.document = doc;
  out.clock = {fps, shutterAngle};
  if (which.is_none()) {
    const FrameRange r = a.frames(out.clock);
    if (r.count == std::numeric_limits<int64_t>::max())
      fail("'" + doc->input + "' has no end to its timeline (a glTF file without a clip): give frames=");
    for (int64_t f = r.first; f < r.first + r.count; ++f) out.frames.push_back(f);
  } else {
    for (const py::handle f : which) out.frames.push_back(f.cast<int64_t>());
  }
  for (int64_t f : out.frames) a.checkFrame(f, out.clock);  // before any work
  if (!doc->frameScene) {
    doc->frameScene = std::make_shared<PyScene>();
    doc->frameScene->description = std::shared_ptr<SceneDescription>(doc->animation, &a.current());
  }
  if (!accelKind.is_none()) {
    const auto policy = parseUpdatePolicy(update);
    if (!policy) fail("frames: update must be 'auto', 'refit' or 'rebuild', got '" + update + "'");
    const std::string name = accelKind.cast<std::string>();
    const auto kind = parseAccelKind(name);
    if (!kind) fail("frames: unknown accel kind '" + name + "'");
    out.build.kind = *kind;
    out.updater.emplace(*policy, rebuildFactor);
    out.accel = std::make_shared<PyAccel>();
    out.accel->scene = doc->frameScene;
  }
  return out;
}

}  // namespace

void bindAnimation(py::module_& m) {
  py::class_<Timeline>(m, "Timeline", "An input's timeline in seconds (end is inf for a glTF file without a clip).")
      .def_readonly("start", &Timeline::start)
      .def_readonly("end", &Timeline::end)
      .def_readonly("what", &Timeline::what, "e.g. \"clip 0 'Walk'\", \"29 keys at 24 fps\"")
      .def("__repr__", [](const Timeline& t) {
        return "<mbrt.Timeline " + t.what + ": " + std::to_string(t.start) + " to " + std::to_string(t.end) + " s>";
      });

  py::class_<PyFrame>(m, "Frame", "One frame of Document.frames().")
      .def_readonly("index", &PyFrame::index)
      .def_readonly("shutter", &PyFrame::shutter, "(open, close) in seconds of the timeline")
      .def_readonly("scene", &PyFrame::scene, "The frames' Scene (the same object every frame), over this shutter")
      .def_readonly("accel", &PyFrame::accel, "The Accel following the frames (the same object), or None")
      .def_readonly("update", &PyFrame::update,
                    "What the accel's update did: {'what', 'refitted', 'seconds', 'sah_cost'}, or None")
      .def_readonly("scene_seconds", &PyFrame::sceneSeconds, "The time to sample the scene")
      .def_readonly("change", &PyFrame::change,
                    "'vertices' (replaced in place: the accel refits) or 'layout' (geometries replaced)");

  py::class_<PyFrames>(m, "Frames", "The iterator of Document.frames().")
      .def("__iter__", [](PyFrames& self) -> PyFrames& { return self; }, py::return_value_policy::reference_internal)
      .def("__next__", &PyFrames::step)
      .def("__len__", [](const PyFrames& self) { return self.frames.size() - self.next; });

  py::class_<PyDocument, PyScene, std::shared_ptr<PyDocument>>(m, "Document", R"doc(
What mbrt.load returns: a Scene (the input over one shutter) that also
knows the input's timeline and renders or traces it frame by frame. The
input is read (and its textures decoded) once.)doc")
      .def_property_readonly("timeline", [](const PyDocument& d) { return d.animated().timeline(); })
      .def("frame_range",
           [](PyDocument& d, double fps, double shutterAngle) { return frameRange(d, fps, shutterAngle); },
           py::kw_only(), "fps"_a = 24.0, "shutter_angle"_a = 180.0,
           "The frames whose shutters lie in the timeline, as a range (frame f opens at f / fps seconds).")
      .def("frames", &frames, py::kw_only(), "fps"_a = 24.0, "shutter_angle"_a = 180.0, "frames"_a = py::none(),
           "accel"_a = py::none(), "update"_a = "auto", "rebuild_factor"_a = 1.5,
           R"doc(The frames in order (frames: the frame numbers; default frame_range()), each
with the frames' Scene sampled over its shutter (frame f opens at f / fps s
for shutter_angle / 360 of a frame) and updated in place: vertices replaced
when the layout stays, geometries otherwise. accel: a kind name to keep an
Accel over the scene, refitted or rebuilt per frame by update ('auto',
'refit', 'rebuild'; rebuild_factor: auto's SAH growth limit). Frames
outside the timeline raise mbrt.Error before any work.)doc");

  m.def("load", &load, "path"_a, py::kw_only(), "shutter"_a = py::none(), "steps"_a = py::none(), "clip"_a = "",
        "fps"_a = 24.0, "motion"_a = "", "size"_a = 1.0, "seed"_a = 1, "stage"_a = false,
        R"doc(Loads an input: a built-in scene name, .obj, .ply, .gltf/.glb, a JSON scene file,
or an OBJ keyframe sequence (a folder or a glob), as `mbrt --scene` does
(docs/input.md), into a Document: a Scene over one shutter (shutter: (open,
close) in seconds of its timeline; default: a glTF clip's start, 1/(2 fps)
long, the whole timeline of the other inputs) with its timeline and frames. steps: time steps
per moving glTF mesh (a number or 'auto'); clip: glTF animation; fps: the
default shutter's and an OBJ sequence's keys per second; motion: procedural
motion of a static mesh; stage: a loaded model on a ground plane. Raises
mbrt.Error naming the file for a missing or bad input.)doc");
}

}  // namespace mbrt::python
