// `mbrt info FILE`: what an input holds, without rendering: a glTF file's
// clips (with their time spans and frame counts), meshes and cameras; an OBJ
// sequence's keys; for every input the loaded scene's geometries with their
// steps, its bounds and its camera.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include "commands.h"
#include "mbrt/io/gltf.h"
#include "mbrt/io/mesh_files.h"
#include "scene_loading.h"

namespace mbrt::tools {
namespace {

const char* typeName(GeometryType t) {
  switch (t) {
    case GeometryType::Triangles: return "triangles";
    case GeometryType::Segments: return "segments";
    case GeometryType::Instance: return "instance";
  }
  return "?";
}

void printVec(const char* label, const Vec3f& v) { std::printf("%s%g, %g, %g", label, v.x, v.y, v.z); }

void printGltf(const std::string& path, double fps) {
  const GltfFileInfo info = inspectGltf(path);
  std::printf("clips     %zu\n", info.clips.size());
  for (size_t i = 0; i < info.clips.size(); ++i) {
    const GltfClipInfo& c = info.clips[i];
    // The frames whose 180 degree shutter lies in the clip (as render --frames allows them).
    const double first = std::max(0.0, std::ceil(c.start * fps - 1e-6));
    const double last = std::floor((c.end - 0.5 / fps) * fps + 1e-6);
    std::printf("  clip %zu '%s': %g to %g s, %zu channels, frames %g to %g at %g fps\n", i, c.name.c_str(), c.start,
                c.end, c.channels, first, last, fps);
  }
  std::printf("meshes    %zu (%zu nodes, %zu skins)\n", info.meshes.size(), info.nodes, info.skins);
  for (size_t i = 0; i < info.meshes.size(); ++i) {
    const GltfMeshInfo& m = info.meshes[i];
    std::printf("  mesh %zu '%s': %zu primitives, %zu triangles, %zu vertices%s", i, m.name.c_str(), m.primitives,
                m.triangles, m.vertices, m.skinned ? ", skinned" : "");
    if (m.morphTargets) std::printf(", %zu morph targets", m.morphTargets);
    std::printf("\n");
  }
  std::printf("cameras   %zu\n", info.cameras.size());
  for (size_t i = 0; i < info.cameras.size(); ++i) {
    const GltfCameraInfo& c = info.cameras[i];
    std::printf("  camera %zu '%s': %s", i, c.name.c_str(), c.type.c_str());
    if (c.type == "perspective") std::printf(", vertical fov %.3g degrees", c.yfovDegrees);
    std::printf("\n");
  }
}

void printScene(const LoadedScene& loaded, const LoadReport& report) {
  const Scene& scene = *loaded.scene;
  std::printf("scene     %s\n", describeScene(loaded).c_str());
  for (const std::string& line : report.lines) std::printf("  %s\n", line.c_str());
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    std::printf("  geometry %u: %s, %u primitives, %u steps over [%g, %g]\n", id, typeName(g.type()),
                g.numPrimitives(), g.numSteps(), g.timeRange().lo, g.timeRange().hi);
  }
  const Box3f b = sceneBounds(scene);
  printVec("bounds    ", b.lower);
  printVec(" to ", b.upper);
  printVec(" (size ", b.upper - b.lower);
  std::printf(")\n");
  std::printf("camera    %zu key%s%s\n", loaded.camera.keys.size(), loaded.camera.keys.size() == 1 ? "" : "s",
              loaded.camera.apertureRadius > 0.0f ? ", thin lens" : ", pinhole");
  for (const CameraSpec& k : loaded.camera.keys) {
    printVec("  eye ", k.eye);
    printVec(", target ", k.target);
    printVec(", up ", k.up);
    std::printf(", fov %g\n", k.verticalFovDegrees);
  }
}

}  // namespace

void registerInfoCommand(CLI::App& app) {
  auto args = std::make_shared<SceneArgs>();
  auto* cmd = app.add_subcommand("info", "What an input holds: clips, meshes, steps, bounds, cameras");
  args->fpsForAnyInput = true;
  addSceneOptions(*cmd, *args);
  cmd->callback([args] {
    resolveScene(*args);
    std::printf("input     %s\n", args->scene.c_str());
    if (isGltfFile(args->scene)) printGltf(args->scene, args->fps);
    LoadReport report;
    const LoadedScene loaded = loadScene(*args, &report);
    if (isObjSequenceSpec(args->scene)) {
      const uint32_t keys = loaded.scene->maxSegments() + 1;
      std::printf("keys      %u, at %g fps: 0 to %g s\n", keys, args->fps, double(keys - 1) / args->fps);
    }
    printScene(loaded, report);
  });
}

}  // namespace mbrt::tools
