// mbrt.scenes, mbrt.render and mbrt.bench.
#include <mutex>

#include "bindings.h"
#include "mbrt/bench.h"
#include "mbrt/io/loaders.h"
#include "mbrt/render.h"
#include "mbrt/scenes.h"

namespace mbrt::python {
namespace {

using namespace pybind11::literals;

std::shared_ptr<PyScene> wrap(SceneDescription description) {
  auto s = std::make_shared<PyScene>();
  s->description = std::make_shared<SceneDescription>(std::move(description));
  return s;
}

std::shared_ptr<PyScene> makeScene(const std::string& name, double size, uint64_t seed) {
  py::gil_scoped_release nogil;
  ProceduralScene p = makeProceduralScene(name, size, seed);
  SceneDescription d;
  d.name = p.name;
  d.scene = std::move(p.scene);
  d.camera.keys = {p.camera};
  return wrap(std::move(d));
}

Vec3f vec3(const py::object& o, const char* what) {
  auto a = py::array_t<float, py::array::forcecast>::ensure(o);
  if (!a || a.size() != 3) fail(std::string("render: ") + what + " must be 3 numbers");
  return {a.data()[0], a.data()[1], a.data()[2]};
}

struct RenderArgs {
  RenderOptions options;
  py::object eye, target, up, fov;
  bool tonemap = false;
  float exposure = 0.0f;
};

py::array_t<float> renderScene(const std::shared_ptr<PyScene>& scene, std::shared_ptr<PyAccel> accel,
                               const RenderArgs& args) {
  if (!scene) fail("render needs an mbrt.Scene");
  if (accel && accel->scene != scene) fail("render: the accel was built over another scene");
  SceneDescription description = *scene->description;  // shares the geometry; the camera may change
  if (!args.eye.is_none() || !args.target.is_none() || !args.up.is_none() || !args.fov.is_none()) {
    CameraSpec c = description.camera.keys.empty() ? frameScene(scene->scene()) : description.camera.keys.front();
    if (!args.eye.is_none()) c.eye = vec3(args.eye, "eye");
    if (!args.target.is_none()) c.target = vec3(args.target, "target");
    if (!args.up.is_none()) c.up = vec3(args.up, "up");
    if (!args.fov.is_none()) c.verticalFovDegrees = args.fov.cast<float>();
    description.camera.keys = {c};
  }
  Image image;
  {
    py::gil_scoped_release nogil;
    std::shared_lock lock(sceneLock());
    std::unique_ptr<Accel> own;
    if (!accel) {
      own = Accel::build(scene->scene(), BuildOptions{});  // auto, the default everywhere
    } else {
      accel->checkCurrent();
    }
    RenderResult r = render(description, own ? *own : accel->get(), args.options);
    image = args.tonemap ? tonemap(r.image, args.options.integrator, args.exposure) : std::move(r.image);
  }
  py::array_t<float> out({py::ssize_t(image.height()), py::ssize_t(image.width()), py::ssize_t(3)});
  std::memcpy(out.mutable_data(), image.pixels().data(), image.pixels().size() * sizeof(Rgb));
  return out;
}

py::object optional(const std::optional<double>& v) { return v ? py::object(py::float_(*v)) : py::none(); }

py::dict resultDict(const bench::Result& r) {
  py::dict d;
  d["scene"] = r.scene;
  d["accel"] = r.accel;
  d["frozen"] = r.frozen;
  d["peer"] = r.peer;
  d["primitives"] = r.primitives;
  d["build_s"] = r.buildS;
  d["build_mprims"] = r.buildMprims;
  d["bytes"] = r.bytes;
  d["peak_build_bytes"] = r.peakBuildBytes;
  d["sah"] = optional(r.sah);
  d["steps_mean"] = optional(r.stepsMean);
  d["steps_max"] = optional(r.stepsMax);
  d["box_tests_mean"] = optional(r.boxTestsMean);
  d["isects_mean"] = optional(r.isectsMean);
  d["isects_max"] = r.isectsMax ? py::object(py::int_(*r.isectsMax)) : py::none();
  d["mismatches"] = r.mismatches();
  for (bench::RaySet set : bench::kAllRaySets) {
    const bench::SetResult& s = r.set(set);
    const std::string p = std::string(bench::toString(set)) + "_";
    auto value = [&](auto v) { return s.traced ? py::cast(v) : py::none(); };
    d[(p + "rays").c_str()] = value(s.rays);
    d[(p + "timed_rays").c_str()] = value(s.timedRays);
    d[(p + "mrays_st").c_str()] = value(s.mraysSt);
    d[(p + "mrays_mt").c_str()] = value(s.mraysMt);
    d[(p + "mismatches_brute").c_str()] = value(s.mismatchesBrute);
    d[(p + "brute_checked").c_str()] = value(s.bruteChecked);
    d[(p + "mismatches_embree").c_str()] =
        s.traced && s.mismatchesEmbree ? py::object(py::int_(*s.mismatchesEmbree)) : py::none();
  }
  return d;
}

template <class T>
void setIfGiven(T& field, const py::object& value) {
  if (!value.is_none()) field = value.cast<T>();
}

py::list runBench(const py::list& scenes, const std::vector<std::string>& accels, bool quick, const py::dict& knobs,
                  bool progress) {
  bench::Options o;
  if (quick) o.makeQuick();
  setIfGiven(o.size, knobs["size"]);
  setIfGiven(o.width, knobs["width"]);
  setIfGiven(o.height, knobs["height"]);
  setIfGiven(o.repeats, knobs["repeats"]);
  setIfGiven(o.frozenTimes, knobs["frozen_times"]);
  setIfGiven(o.bruteSample, knobs["brute_sample"]);
  setIfGiven(o.seed, knobs["seed"]);
  o.accels = accels;
  o.progress = progress ? stderr : nullptr;
  std::vector<ProceduralScene> given;
  for (const py::handle item : scenes) {
    if (py::isinstance<py::str>(item)) {
      given.push_back({item.cast<std::string>(), nullptr, {}});
    } else {
      auto s = item.cast<std::shared_ptr<PyScene>>();
      const auto& keys = s->description->camera.keys;
      given.push_back({s->description->name, s->description->scene,
                       keys.empty() ? frameScene(s->scene()) : keys.front()});
    }
  }
  bench::Report report;
  {
    py::gil_scoped_release nogil;
    std::shared_lock lock(sceneLock());
    for (ProceduralScene& p : given)
      if (!p.scene) p = makeProceduralScene(p.name, o.size, o.seed);
    report = given.empty() ? bench::run(o) : bench::run(o, given);
  }
  py::list rows;
  for (const bench::Result& r : report.results) rows.append(resultDict(r));
  return rows;
}

}  // namespace

void bindLoaders(py::module_& m) {
  py::module_ scenes = m.def_submodule("scenes", "The built-in procedural scene suite.");
  scenes.def("make", &makeScene, "name"_a, "size"_a = 1.0, "seed"_a = 1,
             "Builds a built-in scene (names()): deterministic for a seed; size 1 gives the suite's defaults.");
  scenes.def("names", &proceduralSceneNames, "The built-in scenes, in suite order.");
}

void bindRender(py::module_& m) {
  m.def(
      "render",
      [](const std::shared_ptr<PyScene>& scene, std::shared_ptr<PyAccel> accel, int width, int height, int spp,
         const std::string& integrator, std::pair<float, float> shutter, uint64_t seed, int aoSamples,
         float aoDistance, int maxDepth, float heatMax, bool colorBar, bool tonemapped, float exposure,
         py::object eye, py::object target, py::object up, py::object fov) {
        RenderArgs a;
        const auto kind = parseIntegratorKind(integrator);
        if (!kind) fail("render: unknown integrator '" + integrator + "' (available: " + integratorKindList() + ")");
        a.options.integrator = *kind;
        a.options.width = width, a.options.height = height, a.options.spp = spp;
        a.options.shutterOpen = shutter.first, a.options.shutterClose = shutter.second;
        a.options.seed = seed, a.options.aoSamples = aoSamples, a.options.aoDistance = aoDistance;
        a.options.maxDepth = maxDepth, a.options.heatMax = heatMax, a.options.colorBar = colorBar;
        a.tonemap = tonemapped, a.exposure = exposure;
        a.eye = std::move(eye), a.target = std::move(target), a.up = std::move(up), a.fov = std::move(fov);
        return renderScene(scene, std::move(accel), a);
      },
      "scene"_a, "accel"_a = py::none(), py::kw_only(), "width"_a = 640, "height"_a = 360, "spp"_a = 16,
      "integrator"_a = "ao", "shutter"_a = std::pair<float, float>{0.0f, 1.0f}, "seed"_a = 1, "ao_samples"_a = 2,
      "ao_distance"_a = 0.0f, "max_depth"_a = 4, "heat_max"_a = 0.0f, "color_bar"_a = true, "tonemap"_a = false,
      "exposure"_a = 0.0f, "eye"_a = py::none(), "target"_a = py::none(), "up"_a = py::none(), "fov"_a = py::none(),
      R"doc(Renders the scene to an (H, W, 3) float32 linear RGB array (tonemap=True: the
display transform of `mbrt render`'s PNGs, still linear). integrator: normals,
ao, path, heat-steps, heat-isects, clusters. accel: an Accel over this scene
(default: an `auto` accel built for the call, as everywhere). The camera is the scene's (loaded and
built-in scenes) or frames the scene; eye/target/up/fov override it.
Deterministic for a seed whatever the thread count.)doc");
}

void bindBench(py::module_& m) {
  m.def(
      "bench",
      [](const py::object& scenes, const std::vector<std::string>& accels, bool quick, const py::object& size,
         const py::object& width, const py::object& height, const py::object& repeats, const py::object& frozenTimes,
         const py::object& bruteSample, const py::object& seed, bool progress) {
        py::dict knobs;
        knobs["size"] = size, knobs["width"] = width, knobs["height"] = height, knobs["repeats"] = repeats;
        knobs["frozen_times"] = frozenTimes, knobs["brute_sample"] = bruteSample, knobs["seed"] = seed;
        py::list list = scenes.is_none() ? py::list() : py::list(scenes);
        return runBench(list, accels, quick, knobs, progress);
      },
      "scenes"_a = py::none(), "accels"_a = std::vector<std::string>{}, py::kw_only(), "quick"_a = false,
      "size"_a = py::none(), "width"_a = py::none(), "height"_a = py::none(), "repeats"_a = py::none(),
      "frozen_times"_a = py::none(), "brute_sample"_a = py::none(), "seed"_a = py::none(), "progress"_a = false,
      R"doc(Runs the benchmark of `mbrt bench` and returns its table as a list of dicts, one
per (scene, structure): build_s, bytes, sah, traversal counters and, per ray
set (primary, secondary, shadow, frozen), <set>_mrays_st / <set>_mrays_mt
(Mrays/s on one / all threads), <set>_rays and mismatches against brute and
Embree (None where a set was not traced). scenes: built-in names or Scene
objects (default: the suite); accels: bench row names (default: every kind
and Embree's modes). quick=True: small scenes and ray sets.)doc");
}

}  // namespace mbrt::python
