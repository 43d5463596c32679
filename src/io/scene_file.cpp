// JSON scene files: objects (files, sequences, built-in scenes) with
// transforms and colours, camera, shutter, lights.
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <optional>

#include "mbrt/io/file_access.h"
#include "mbrt/io/loaders.h"

namespace mbrt {
namespace {

using json = nlohmann::json;

class SceneFile {
 public:
  SceneFile(const std::string& path, const LoadOptions& options, LoadReport* report)
      : path_(path), options_(options), report_(report) {}

  SceneDescription run() {
    const std::string text = io::readInputFile(path_);
    json doc;
    try {
      doc = json::parse(text, nullptr, true, /*ignore_comments=*/true);
    } catch (const json::exception& e) {
      fail(std::string("not valid JSON: ") + e.what());
    }
    if (!doc.is_object()) fail("the top level must be an object");
    for (auto it = doc.begin(); it != doc.end(); ++it)
      if (it.key() != "objects" && it.key() != "camera" && it.key() != "shutter" && it.key() != "fps" &&
          it.key() != "steps" && it.key() != "lights" && it.key() != "sky" && it.key() != "stage")
        fail("unknown key '" + it.key() + "'");
    LoadOptions opt = options_;
    if (doc.contains("shutter")) {
      const auto v = numbers(doc["shutter"], "shutter", 2);
      if (!options_.gltf.shutterOpen) opt.gltf.shutterOpen = v[0];
      if (!options_.gltf.shutterClose) opt.gltf.shutterClose = v[1];
    }
    if (doc.contains("fps")) opt.gltf.fps = number(doc["fps"], "fps");
    if (doc.contains("steps") && options_.gltf.steps.steps == 0) {
      const json& s = doc["steps"];
      if (s.is_string() && s.get<std::string>() == "auto") opt.gltf.steps.steps = 0;
      else {
        const long long n = positiveInt(s, "steps");
        if (n > 1024) fail("'steps' must be at most 1024 (each step is a copy of the meshes), got " + std::to_string(n));
        opt.gltf.steps.steps = uint32_t(n);
      }
    }
    SceneDescription out;
    out.name = path_;
    out.scene = std::make_shared<Scene>();
    if (!doc.contains("objects") || !doc["objects"].is_array() || doc["objects"].empty())
      fail("'objects' must be a non-empty array");
    size_t index = 0;
    for (const json& o : doc["objects"]) addObject(o, index++, opt, out);
    out.shutterOpen = opt.gltf.shutterOpen.value_or(0.0);
    out.shutterClose = opt.gltf.shutterClose.value_or(1.0);
    if (doc.contains("camera")) out.camera = camera(doc["camera"]);
    else out.camera.keys = {frameScene(*out.scene)};
    if (doc.contains("lights")) {
      if (!doc["lights"].is_array()) fail("'lights' must be an array");
      out.lights.clear();
      for (const json& l : doc["lights"]) {
        DirectionalLight light;
        if (l.contains("direction")) light.direction = vec3(l["direction"], "light direction");
        if (l.contains("radiance")) light.radiance = colour(l["radiance"], "light radiance", 1e6);
        if (length(light.direction) == 0) fail("a light direction is zero");
        out.lights.push_back(light);
      }
    }
    if (doc.contains("sky")) out.skyColor = colour(doc["sky"], "sky", 1e6);
    // "stage": true puts the objects on mbrt render's stage (addStage).
    if (doc.contains("stage") && !doc["stage"].is_boolean()) fail("'stage' must be true or false");
    out.bringsEnvironment = !doc.value("stage", false);
    return out;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(path_ + ": " + what); }

  double number(const json& j, const std::string& what) const {
    if (!j.is_number()) fail("'" + what + "' must be a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) fail("'" + what + "' is not finite");
    return v;
  }
  long long positiveInt(const json& j, const std::string& what) const {
    if (!j.is_number_integer() || j.get<long long>() < 1) fail("'" + what + "' must be a positive integer or \"auto\"");
    return j.get<long long>();
  }
  std::vector<double> numbers(const json& j, const std::string& what, size_t n) const {
    if (!j.is_array() || j.size() != n) fail("'" + what + "' must be an array of " + std::to_string(n) + " numbers");
    std::vector<double> v;
    for (const json& x : j) v.push_back(number(x, what));
    return v;
  }
  Vec3f vec3(const json& j, const std::string& what) const {
    const auto v = numbers(j, what, 3);
    return {float(v[0]), float(v[1]), float(v[2])};
  }

  // A colour: three numbers in [0, maxValue] (a negative radiance or an
  // albedo above 1 would make light from nothing).
  Vec3f colour(const json& j, const std::string& what, double maxValue) const {
    const auto v = numbers(j, what, 3);
    for (double x : v)
      if (!(x >= 0.0 && x <= maxValue))
        fail("'" + what + "' values must be in [0, " + (maxValue == 1.0 ? std::string("1") : std::string("1e6")) +
             "], got " + json(v).dump());
    return {float(v[0]), float(v[1]), float(v[2])};
  }

  std::string resolve(const std::string& p) const {
    std::filesystem::path fp(p);
    if (fp.is_absolute()) return p;
    return (std::filesystem::path(path_).parent_path() / fp).string();
  }

  // T * R * S from "translate", "rotate" [deg, ax, ay, az], "scale" (number or [x,y,z]).
  SRTKey transform(const json& o, const std::string& what) const {
    SRTKey k;
    if (o.contains("translate")) k.translation = vec3(o["translate"], what + " translate");
    if (o.contains("rotate")) {
      const auto r = numbers(o["rotate"], what + " rotate", 4);
      const Vec3f axis{float(r[1]), float(r[2]), float(r[3])};
      if (length(axis) == 0) fail(what + ": the rotation axis is zero");
      k.rotation = Quaternion::fromAxisAngle(axis, float(r[0] * 3.14159265358979 / 180.0));
    }
    if (o.contains("scale")) {
      if (o["scale"].is_number()) k.scale = Vec3f(float(number(o["scale"], what + " scale")));
      else k.scale = vec3(o["scale"], what + " scale");
      if (k.scale.x == 0 || k.scale.y == 0 || k.scale.z == 0) fail(what + ": a scale is zero");
    }
    return k;
  }

  void addObject(const json& o, size_t index, const LoadOptions& opt, SceneDescription& out) {
    const std::string what = "object " + std::to_string(index);
    if (!o.is_object()) fail(what + " must be an object");
    for (auto it = o.begin(); it != o.end(); ++it) {
      static const char* known[] = {"file", "scene", "sequence", "translate", "rotate", "scale", "diffuse",
                                    "motion", "clip", "size", "seed"};
      if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return it.key() == k; }) ==
          std::end(known))
        fail(what + ": unknown key '" + it.key() + "'");
    }
    const int sources = int(o.contains("file")) + int(o.contains("scene")) + int(o.contains("sequence"));
    if (sources != 1) fail(what + " needs exactly one of 'file', 'scene', 'sequence'");
    LoadOptions sub = opt;
    if (o.contains("motion")) {
      if (!o["motion"].is_string()) fail(what + ": 'motion' must be a string like \"rotate:90\"");
      sub.motion = o["motion"].get<std::string>();
    }
    if (o.contains("clip")) {
      if (o["clip"].is_string()) sub.gltf.clip = o["clip"].get<std::string>();
      else if (o["clip"].is_number_integer() && o["clip"].get<long long>() >= 0)
        sub.gltf.clip = std::to_string(o["clip"].get<long long>());
      else fail(what + ": 'clip' must be a name or an index");
    }
    if (o.contains("size")) sub.size = number(o["size"], what + " size");
    if (o.contains("seed")) sub.seed = uint64_t(positiveInt(o["seed"], what + " seed"));
    std::string spec;
    if (o.contains("file")) {
      if (!o["file"].is_string()) fail(what + ": 'file' must be a string");
      spec = resolve(o["file"].get<std::string>());
      const std::string ext = std::filesystem::path(spec).extension().string();
      if (ext == ".json") fail(what + ": scene files cannot include scene files");
      std::error_code ec;
      if (!std::filesystem::is_regular_file(spec, ec)) fail(what + ": no file '" + spec + "'");
    } else if (o.contains("sequence")) {
      if (!o["sequence"].is_string()) fail(what + ": 'sequence' must be a string");
      spec = resolve(o["sequence"].get<std::string>());
      if (!isObjSequenceSpec(spec)) fail(what + ": sequence '" + spec + "' is neither a folder nor a glob pattern");
    } else {
      if (!o["scene"].is_string()) fail(what + ": 'scene' must be a string");
      spec = o["scene"].get<std::string>();
      const auto names = proceduralSceneNames();
      if (std::find(names.begin(), names.end(), spec) == names.end()) fail(what + ": no built-in scene '" + spec + "'");
    }
    SceneDescription part = loadSceneSpec(spec, sub, report_);
    const SRTKey xf = transform(o, what);
    std::optional<Vec3f> diffuse;
    if (o.contains("diffuse")) diffuse = colour(o["diffuse"], what + " diffuse", 1.0);
    merge(part, xf, diffuse, what, out);
  }

  // Copies the part's geometries into `out`, transformed.
  void merge(const SceneDescription& part, const SRTKey& xf, const std::optional<Vec3f>& diffuse,
             const std::string& what, SceneDescription& out) {
    const Affine3f m = xf.toAffine();
    const bool uniform = xf.scale.x == xf.scale.y && xf.scale.y == xf.scale.z;
    const Scene& s = *part.scene;
    // The part's textures follow the ones already there.
    const int32_t textureBase = int32_t(out.textures.size());
    out.textures.insert(out.textures.end(), part.textures.begin(), part.textures.end());
    auto rebase = [&](Material m) {
      if (m.texture >= 0) m.texture += textureBase;
      return m;
    };
    for (uint32_t id = 0; id < s.numGeometries(); ++id) {
      const Geometry& g = s.geometry(id);
      uint32_t added = 0;
      switch (g.type()) {
        case GeometryType::Triangles:
        case GeometryType::Segments: {
          std::vector<std::vector<Vec3f>> steps(g.numSteps());
          for (uint32_t k = 0; k < g.numSteps(); ++k) {
            const VertexBuffer& vb = g.vertices(k);
            steps[k].resize(vb.count);
            for (size_t i = 0; i < vb.count; ++i) steps[k][i] = m.xfmPoint(vb[i]);
          }
          if (g.type() == GeometryType::Triangles) {
            added = out.scene->addTriangleMesh({g.triangles().begin(), g.triangles().end()}, std::move(steps), g.timeRange());
          } else {
            std::vector<float> radii(g.radii().begin(), g.radii().end());
            const float r = std::cbrt(std::fabs(m.determinant()));  // radii scale with a uniform scale
            for (float& x : radii) x *= r;
            added = out.scene->addSegments({g.segments().begin(), g.segments().end()}, std::move(steps), std::move(radii),
                                           g.timeRange());
          }
          break;
        }
        case GeometryType::Instance: {
          if (g.hasSRTKeys()) {
            if (!uniform) fail(what + ": a non-uniform scale cannot be applied to an object with SRT instances");
            std::vector<SRTKey> keys;
            for (const SRTKey& k : g.srtKeys())
              keys.push_back({k.scale * xf.scale.x, xf.rotation * k.rotation, m.xfmPoint(k.translation)});
            added = out.scene->addInstance(g.instancedSceneShared(), std::move(keys), g.timeRange());
          } else {
            std::vector<Affine3f> keys;
            for (const Affine3f& k : g.transforms()) keys.push_back(m * k);
            added = out.scene->addInstance(g.instancedSceneShared(), std::move(keys), g.timeRange());
          }
          break;
        }
      }
      out.materials.resize(added + 1);
      out.materials[added] = rebase(part.material(id));
      if (diffuse) out.materials[added].diffuse = *diffuse;
      if (id < part.surfaces.size()) {
        out.surfaces.resize(added + 1);
        out.surfaces[added] = part.surfaces[id];
        for (Material& m : out.surfaces[added].materials) m = rebase(m);
        if (diffuse) {  // the object's colour replaces its file's materials
          out.surfaces[added].faceMaterials.clear();
          out.surfaces[added].materials.clear();
        }
      }
    }
  }

  Camera camera(const json& j) const {
    if (!j.is_object()) fail("'camera' must be an object");
    Camera cam;
    auto spec = [&](const json& c) {
      CameraSpec s;
      if (!c.is_object()) fail("a camera key must be an object");
      if (c.contains("eye")) s.eye = vec3(c["eye"], "camera eye");
      if (c.contains("target")) s.target = vec3(c["target"], "camera target");
      if (c.contains("up")) s.up = vec3(c["up"], "camera up");
      if (c.contains("fov")) s.verticalFovDegrees = float(number(c["fov"], "camera fov"));
      if (!(s.verticalFovDegrees > 0 && s.verticalFovDegrees < 180)) fail("camera fov must be in (0, 180) degrees");
      if (length(s.target - s.eye) == 0) fail("camera eye and target are the same point");
      return s;
    };
    if (j.contains("keys")) {
      if (!j["keys"].is_array() || j["keys"].empty()) fail("camera 'keys' must be a non-empty array");
      cam.keys.clear();
      for (const json& k : j["keys"]) cam.keys.push_back(spec(k));
    } else {
      cam.keys = {spec(j)};
    }
    if (j.contains("aperture")) cam.apertureRadius = float(number(j["aperture"], "camera aperture"));
    if (j.contains("focus")) cam.focusDistance = float(number(j["focus"], "camera focus"));
    if (cam.apertureRadius < 0 || cam.focusDistance < 0) fail("camera aperture and focus must not be negative");
    return cam;
  }

  std::string path_;
  LoadOptions options_;
  LoadReport* report_;
};

}  // namespace

SceneDescription loadSceneFile(const std::string& path, const LoadOptions& options, LoadReport* report) {
  return SceneFile(path, options, report).run();
}

}  // namespace mbrt
