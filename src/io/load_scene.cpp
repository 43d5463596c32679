// Dispatch on what --scene names: built-in scene, file by extension, OBJ
// keyframe sequence.
#include <algorithm>
#include <filesystem>

#include "mbrt/io/loaders.h"
#include "mbrt/scenes.h"

namespace mbrt {
namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return ext;
}

SceneDescription staticMesh(const std::string& path, ObjMesh mesh, const LoadOptions& options) {
  SceneDescription out;
  out.name = path;
  ObjSurface surface = loadObjSurface(path, mesh);  // OBJ usemtl; none for PLY
  if (!surface.surface.faceMaterials.empty()) {
    out.surfaces = {std::move(surface.surface)};
    out.textures = std::move(surface.textures);
  }
  out.scene = options.motion.empty() ? makeMovingMeshScene(std::move(mesh), {})
                                     : makeMovingMeshScene(std::move(mesh), parseProceduralMotion(options.motion));
  out.camera.keys = {frameScene(*out.scene)};
  return out;
}

}  // namespace

SceneDescription loadSceneSpec(const std::string& spec, const LoadOptions& options, LoadReport* report) {
  const auto names = proceduralSceneNames();
  std::error_code ec;
  // A procedural motion moves a static mesh; anything else would ignore it.
  const std::string ext = lowerExtension(spec);
  if (!options.motion.empty() && ((ext != ".obj" && ext != ".ply") || isObjSequenceSpec(spec)))
    throw Error("'" + spec + "': a procedural motion ('" + options.motion +
                "') applies to a static .obj or .ply mesh only");
  if (std::find(names.begin(), names.end(), spec) != names.end() && !std::filesystem::exists(spec, ec)) {
    ProceduralScene p = makeProceduralScene(spec, options.size, options.seed);
    SceneDescription out;
    out.name = p.name;
    out.scene = std::move(p.scene);
    out.camera.keys = {p.camera};
    out.bringsEnvironment = true;
    return out;
  }
  if (isObjSequenceSpec(spec)) {
    const std::vector<std::string> files = listObjSequence(spec);
    SceneDescription out;
    out.name = spec;
    out.scene = loadObjSequence(files);
    out.camera.keys = {frameScene(*out.scene)};
    if (report)
      report->lines.push_back("OBJ sequence: " + std::to_string(files.size()) + " keys, " + files.front() + " ... " +
                              files.back());
    return out;
  }
  if (ext == ".obj") return staticMesh(spec, readObj(spec), options);
  if (ext == ".ply") return staticMesh(spec, readPly(spec), options);
  if (ext == ".gltf" || ext == ".glb") return loadGltf(spec, options.gltf, report);
  if (ext == ".json") return loadSceneFile(spec, options, report);
  if (!std::filesystem::exists(spec, ec))
    throw Error("'" + spec + "' is not a built-in scene and no such file exists");
  throw Error("'" + spec + "': unknown file type '" + ext + "' (.obj, .ply, .gltf, .glb, .json, a folder or a glob of OBJ keys)");
}

}  // namespace mbrt
