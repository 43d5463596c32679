// glTF scene assembly over one shutter: rigid items become SRT instances,
// deforming ones vertex steps, static ones meshes in world space; the
// camera of the first camera node; loadGltf (mbrt/io/gltf.h).
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>

#include "io/gltf_sampler.h"
#include "mbrt/io/loaders.h"

namespace mbrt::gltf {

void ClipSampler::addItem(const Item& it, Scene& scene, LoadReport* report) {
  Motion motion = sharp_ ? Motion::Static : it.motion;
  std::vector<SRTKey> srt;
  if (motion == Motion::Rigid) {
    // SRT keys need a world matrix without shear at every time looked at; a
    // shear anywhere (a parent's non-uniform scale) makes the item deform.
    bool sheared = false;
    auto keyAt = [&](float u) {
      SRTKey k;
      if (!decomposeSRT(poseAt(u).world[size_t(it.node)], k)) sheared = true;
      return k;
    };
    Box3f local;
    std::vector<Vec3f> rest;
    morph(*it.data, poseAt(0.0f).local[size_t(it.node)].weights, rest);
    for (const Vec3f& p : rest) local.extend(p);
    std::vector<Vec3f> corners;
    for (int c = 0; c < 8; ++c)
      corners.push_back({c & 1 ? local.upper.x : local.lower.x, c & 2 ? local.upper.y : local.lower.y,
                         c & 4 ? local.upper.z : local.lower.z});
    const uint32_t s = chooseSRTSteps(
        keyAt, [&](float u) { return poseAt(u).world[size_t(it.node)]; }, corners, steps_, tolerance_);
    for (uint32_t k = 0; k < s && !sheared; ++k) srt.push_back(keyAt(s == 1 ? 0.0f : float(k) / float(s - 1)));
    if (sheared) {
      motion = Motion::Deforming;  // bake the vertices
    } else {
      auto child = std::make_shared<Scene>();
      child->addTriangleMesh(it.triangles, std::vector<std::vector<Vec3f>>{std::move(rest)});
      scene.addInstance(std::move(child), std::move(srt));
    }
  }
  if (motion != Motion::Rigid) {
    uint32_t s = 1;
    if (motion == Motion::Deforming)
      s = chooseVertexSteps([&](float u, std::vector<Vec3f>& o) { evalWorld(it, u, o); }, steps_, tolerance_);
    std::vector<std::vector<Vec3f>> steps(s);
    for (uint32_t k = 0; k < s; ++k) evalWorld(it, s == 1 ? 0.0f : float(k) / float(s - 1), steps[k]);
    scene.addTriangleMesh(it.triangles, std::move(steps));
  }
  const uint32_t id = scene.numGeometries() - 1;
  static const char* kinds[] = {"static", "rigid (SRT instance)", "deforming"};
  if (report)
    report->lines.push_back("geometry " + std::to_string(id) + " '" + it.name + "' primitive " +
                            std::to_string(it.primitive) + ": " + kinds[int(motion)] +
                            (it.skinned ? ", skinned" : "") + ", " + std::to_string(it.triangles.size()) +
                            " triangles, " + std::to_string(scene.geometry(id).numSteps()) + " steps");
}

// Per geometry (item) its material and the texture coordinates its texture
// reads; the textures decoded once, in the order of first use.
void ClipSampler::describeSurfaces() {
  surfaces_.name = doc_.path;
  for (size_t id = 0; id < items_.size(); ++id) {
    const Item& it = items_[id];
    surfaces_.materials.resize(id + 1);
    surfaces_.materials[id] = materials_.material(it.material, surfaces_);
    if (const int set = materials_.texCoordSet(it.material); set >= 0) {
      surfaces_.surfaces.resize(id + 1);
      surfaces_.surfaces[id].texcoords = readTexCoords(doc_, it.mesh, it.primitive, set, it.data->positions.size(),
                                                       "geometry " + std::to_string(id) + " '" + it.name + "'");
    }
  }
}

Camera ClipSampler::camera(const Scene& scene, LoadReport* report) {
  const tinygltf::Model& m = *doc_.model;
  Camera cam;
  if (cameraNode_ >= 0) {
    const tinygltf::Camera& c = m.cameras[size_t(m.nodes[size_t(cameraNode_)].camera)];
    if (c.type == "perspective") {
      cam.keys.clear();
      for (float u : {0.0f, 1.0f}) {
        const Affine3f w = poseAt(sharp_ ? 0.0f : u).world[size_t(cameraNode_)];
        CameraSpec s;
        s.eye = w.p;
        s.target = w.p - normalize(w.vz);
        s.up = normalize(w.vy);
        s.verticalFovDegrees = float(c.perspective.yfov * 180.0 / 3.14159265358979);
        if (cam.keys.empty() || !(cam.keys[0].eye == s.eye && cam.keys[0].target == s.target)) cam.keys.push_back(s);
      }
      return cam;
    }
    if (report)
      report->lines.push_back("camera " + std::to_string(m.nodes[size_t(cameraNode_)].camera) +
                              " is not perspective; framing automatically");
  }
  cam.keys = {frameScene(scene)};
  return cam;
}

}  // namespace mbrt::gltf

namespace mbrt {

SceneDescription loadGltf(const std::string& path, const GltfOptions& options, LoadReport* report) {
  gltf::ClipSampler sampler(path, options.clip, options.steps, report);
  const auto [open, close] = sampler.shutter(options);
  io::FrameGeometry geometry = sampler.sample(open, close, report);
  SceneDescription out = sampler.surfaces();
  out.scene = std::move(geometry.scene);
  out.camera = std::move(geometry.camera);
  out.shutterOpen = open;
  out.shutterClose = close;
  return out;
}

}  // namespace mbrt
