// A glTF file read once (its nodes, primitives, skins, materials and decoded
// textures) and its scene over any shutter of its clip: which meshes deform,
// which move rigidly, which stand still, sampled over the shutter.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "io/animation_source.h"
#include "io/gltf_internal.h"

namespace tinygltf {
struct Primitive;
}

namespace mbrt::gltf {

class ClipSampler {
 public:
  // Reads the file and everything that does not depend on the shutter.
  // Throws Error naming the file (bad file, unknown clip, no triangle
  // meshes, bad accessors, missing or corrupt textures).
  ClipSampler(const std::string& path, const std::string& clip, const StepOptions& steps, LoadReport* report);
  ClipSampler(const ClipSampler&) = delete;  // materials_ refers to doc_
  ClipSampler& operator=(const ClipSampler&) = delete;

  int clip() const { return clip_; }  // -1: no animation
  // "0 'Walk'", or "none (static)".
  std::string clipName() const;
  double clipStart() const { return anim_->clipStart(); }
  double clipEnd() const { return anim_->clipEnd(); }
  // The shutter of `options` (its open and close, defaulting to the clip's
  // start, open shutterAngleDegrees / 360 of a frame at fps, clamped to the
  // clip's end). Throws Error for fps <= 0.
  std::pair<double, double> shutter(const GltfOptions& options) const;

  // The geometry and camera over [open, close] seconds of the clip. Throws
  // Error for open > close, a shutter that is not finite or lies outside the
  // clip.
  io::FrameGeometry sample(double open, double close, LoadReport* report);
  // Name, materials, texture coordinates and textures of the geometries of
  // every sample (one geometry per placed primitive, in the same order).
  const SceneDescription& surfaces() const { return surfaces_; }

 private:
  enum class Motion { Static, Rigid, Deforming };
  // One primitive placed by one node.
  struct Item {
    int node = -1, mesh = -1, primitive = -1;
    std::string name;
    std::vector<Triangle> triangles;
    const PrimitiveData* data = nullptr;
    bool skinned = false;
    Motion motion = Motion::Static;  // over a shutter that is not sharp
    int material = -1;
  };
  struct Pose {
    std::vector<NodeTRS> local;
    std::vector<Affine3f> world;
  };

  void setShutter(double open, double close);
  const Pose& poseAt(float u);
  const PrimitiveData& primitiveData(int mesh, int prim, bool wantSkin);
  std::vector<Triangle> triangles(const tinygltf::Primitive& p, size_t vertices, const std::string& what);
  void collectNodes(LoadReport* report);
  void addItem(const Item& it, Scene& scene, LoadReport* report);
  void describeSurfaces();
  const std::vector<Affine3f>& skinMatrices(int skinIndex);
  void evalWorld(const Item& it, float u, std::vector<Vec3f>& out);
  Camera camera(const Scene& scene, LoadReport* report);

  Document doc_;
  Materials materials_{doc_};
  StepOptions steps_;
  int clip_ = -1;
  std::unique_ptr<Animator> anim_;
  double open_ = 0, close_ = 0;
  bool sharp_ = true;
  float tolerance_ = 0;
  int cameraNode_ = -1;
  std::vector<Item> items_;
  SceneDescription surfaces_;
  std::map<std::pair<int, int>, PrimitiveData> prims_;
  std::map<int, std::vector<Affine3f>> ibm_;
  std::map<float, Pose> poses_;
  std::vector<Affine3f> joints_;
  std::vector<Vec3f> scratch_;
};

}  // namespace mbrt::gltf
