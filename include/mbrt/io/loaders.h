// One entry point for every input mbrt reads: built-in scene names, OBJ,
// PLY, glTF, JSON scene files, and OBJ keyframe sequences (a folder or a
// glob). See docs/input.md.
#pragma once

#include <string>

#include "mbrt/io/gltf.h"
#include "mbrt/io/mesh_files.h"
#include "mbrt/io/scene_description.h"

namespace mbrt {

struct LoadOptions {
  GltfOptions gltf;    // clip, shutter (seconds), fps, steps
  std::string motion;  // procedural motion of static .obj/.ply meshes (parseProceduralMotion), empty: none
  double size = 1.0;   // built-in scenes
  uint64_t seed = 1;
};

// What `spec` names, by its form: a built-in scene name; a folder or a
// pattern with * ? [ (OBJ keyframe sequence); a file by extension (.obj,
// .ply, .gltf, .glb, .json). Throws Error for unknown names, missing or bad
// files; the message names the file.
SceneDescription loadSceneSpec(const std::string& spec, const LoadOptions& options = {}, LoadReport* report = nullptr);

// A JSON scene file (docs/input.md): objects from files, sequences and
// built-in scenes with transforms and diffuse colours; camera, shutter,
// lights, sky. Relative paths are relative to the file's folder.
SceneDescription loadSceneFile(const std::string& path, const LoadOptions& options = {}, LoadReport* report = nullptr);

// The camera used when an input has none: frames the scene's bounds over
// all steps from the front (frameBox), or, when the scene is a closed room
// around its centre (probe rays from there meet inward-facing walls on
// every side, far from the centre, and a floor below), looks along the
// room's longer horizontal axis from inside (docs/renderer.md). Scenes of more than 8M
// triangles are framed from the front without probing.
CameraSpec frameScene(const Scene& scene);

// Puts a loaded model that brings no environment (!bringsEnvironment) on a
// stage: a ground plane (y up, a grey checker texture) just below its
// lowest point over the shutter, reaching 25 times its size each way, under
// the description's sky and a sun from the upper left in front (replacing
// `lights`), so that it casts a shadow beside it. Adds
// one geometry to d.scene (call before building an Accel) and returns true;
// returns false and changes nothing for descriptions that bring their own
// environment or have empty bounds. `over`, when given, places the stage
// from that box instead of the scene's bounds: a frame sequence passes one box
// for every frame, so the ground stays put while the model moves.
bool addStage(SceneDescription& d, const Box3f* over = nullptr);

}  // namespace mbrt
