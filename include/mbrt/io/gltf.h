// glTF 2.0 (.gltf / .glb) scenes with animation: node hierarchies, TRS
// animation (LINEAR, STEP, CUBICSPLINE), skins, morph targets, several
// meshes, primitives and clips. See docs/input.md.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "mbrt/io/scene_description.h"

namespace mbrt {

// How many time steps a moving mesh (vertex steps) or instance (SRT keys)
// gets over the shutter.
struct StepOptions {
  uint32_t steps = 0;       // S for every moving geometry; 0: automatic
  uint32_t maxSteps = 33;   // the most the automatic mode gives
  // Automatic mode: the fewest steps whose interpolation stays within
  // tolerance * (the scene's bounding-box diagonal) of the true motion,
  // checked at 3 times inside each segment.
  float tolerance = 1e-3f;
};

struct GltfOptions {
  std::string clip;  // animation name or index; empty: the first one
  // The shutter in seconds of the clip. Default: opening at the clip's
  // start, closing shutterAngleDegrees / 360 / fps later (clamped to the
  // clip's end). open == close gives a sharp frame (S = 1 everywhere).
  std::optional<double> shutterOpen, shutterClose;
  double fps = 24.0;
  double shutterAngleDegrees = 180.0;
  StepOptions steps;
};

// What the loader chose, for messages: one line per geometry
// ("geometry 3 'Cesium_Man' skinned: 5 steps") and the clip and shutter.
struct LoadReport {
  std::vector<std::string> lines;
};

// Deforming meshes (skins, animated morph weights) become triangle meshes
// with vertex steps; meshes under rigidly animated nodes become instances
// with SRT keys; static ones static meshes in world space. Materials come
// from baseColorFactor and baseColorTexture (with TEXCOORD_n in
// SceneDescription::surfaces); the camera from the first camera node (else the
// scene is framed automatically). Throws Error naming the file and the
// problem (bad or truncated file, bad accessors, NaN data, unknown clip,
// shutter outside the clip).
SceneDescription loadGltf(const std::string& path, const GltfOptions& options = {}, LoadReport* report = nullptr);

}  // namespace mbrt

namespace mbrt {

// What a glTF file holds, for `mbrt info`: its clips with their time spans,
// meshes, cameras, without sampling any animation.
struct GltfClipInfo {
  std::string name;
  double start = 0.0, end = 0.0;  // seconds
  size_t channels = 0;
};
struct GltfMeshInfo {
  std::string name;
  size_t primitives = 0, triangles = 0, vertices = 0, morphTargets = 0;
  bool skinned = false;  // placed by a node with a skin
};
struct GltfCameraInfo {
  std::string name, type;  // "perspective" or "orthographic"
  double yfovDegrees = 0.0;  // perspective cameras
};
struct GltfFileInfo {
  std::vector<GltfClipInfo> clips;
  std::vector<GltfMeshInfo> meshes;
  std::vector<GltfCameraInfo> cameras;
  size_t nodes = 0, skins = 0;
};

// Throws Error naming the file for a missing or bad file.
GltfFileInfo inspectGltf(const std::string& path);

}  // namespace mbrt
