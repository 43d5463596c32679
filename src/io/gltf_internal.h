// Internals of the glTF loader, one idea per file:
//   gltf_document.cpp  reading the file (tinygltf) and accessors
//   gltf_animation.cpp clips, sampler interpolation, node transforms over time
//   gltf_deform.cpp    morph targets and skinning of one primitive
//   gltf_steps.cpp     choosing the number of steps (automatic mode)
//   gltf_materials.cpp base colours, base colour textures, texture coordinates
//   gltf_sampler.cpp   the file read once; nodes posed and meshes deformed over a shutter
//   gltf_loader.cpp    a shutter's geometry (instances, vertex steps) and camera; loadGltf
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "mbrt/io/gltf.h"
#include "mbrt/quaternion.h"

namespace tinygltf {
class Model;
}

namespace mbrt::gltf {

// The parsed file. `model` is tinygltf's.
struct Document {
  std::string path;
  std::shared_ptr<tinygltf::Model> model;

  [[noreturn]] void fail(const std::string& what) const;
};

Document readDocument(const std::string& path);

// An accessor's elements as floats (normalized integers mapped to [0,1] or
// [-1,1], other integers converted), `components` per element; sparse
// accessors applied. Throws when the accessor does not fit its buffer, has
// another number of components, or holds NaN / infinity. `what` names it in
// errors.
std::vector<float> readFloats(const Document& doc, int accessor, int components, const std::string& what);
// Integer elements (indices, joints), `components` per element.
std::vector<uint32_t> readUints(const Document& doc, int accessor, int components, const std::string& what);
size_t accessorCount(const Document& doc, int accessor);
// A buffer view's bytes (an embedded image's, an accessor's), after checking
// that the view and its buffer exist and the view fits the buffer.
std::span<const uint8_t> bufferViewBytes(const Document& doc, int viewIndex, const std::string& what);

// ---- animation ----

struct NodeTRS {
  Vec3f translation{0, 0, 0};
  Quaternion rotation;
  Vec3f scale{1, 1, 1};
  bool hasMatrix = false;  // a static node given by a matrix
  Affine3f matrix;
  std::vector<float> weights;  // morph weights (empty: the mesh's defaults)
};

class Animator {
 public:
  // clip < 0: no animation (the rest pose).
  Animator(const Document& doc, int clip);

  double clipStart() const { return start_; }
  double clipEnd() const { return end_; }
  // True when a channel of the clip moves the node (translation, rotation
  // or scale).
  bool animated(int node) const { return animated_[size_t(node)]; }
  bool weightsAnimated(int node) const { return weightsAnimated_[size_t(node)]; }
  // True when the node or one of its ancestors is animated.
  bool movesInWorld(int node) const;
  int parent(int node) const { return parent_[size_t(node)]; }

  // Local TRS of every node at `seconds`.
  std::vector<NodeTRS> localAt(double seconds) const;
  // World matrices of every node from local TRS.
  std::vector<Affine3f> worldFrom(const std::vector<NodeTRS>& local) const;

 private:
  struct Channel {
    int node;
    int path;  // 0 translation, 1 rotation, 2 scale, 3 weights
    int interpolation;  // 0 linear, 1 step, 2 cubic
    std::vector<float> times;
    std::vector<float> values;
    int width;  // floats per value
  };
  void sample(const Channel& c, double t, float* out) const;

  const Document* doc_;
  std::vector<Channel> channels_;
  std::vector<int> parent_;
  std::vector<bool> animated_, weightsAnimated_;
  double start_ = 0.0, end_ = 0.0;
};

// ---- deformation ----

// One primitive's data for deforming it.
struct PrimitiveData {
  std::vector<Vec3f> positions;
  std::vector<std::vector<Vec3f>> targets;  // morph target position deltas
  std::vector<float> defaultWeights;        // the mesh's weights
  // Skinning: per vertex, groups of 4 joints and weights (JOINTS_n, WEIGHTS_n).
  std::vector<uint32_t> joints;
  std::vector<float> weights;
  uint32_t influences = 0;  // joints per vertex (4 per set)
};

// Positions with the morph weights applied (weights may be empty: defaults).
void morph(const PrimitiveData& p, const std::vector<float>& weights, std::vector<Vec3f>& out);
// Skins morphed positions in place with joint matrices (world * inverse bind).
void skin(const PrimitiveData& p, const std::vector<Affine3f>& jointMatrices, const Affine3f& fallback,
          std::vector<Vec3f>& positions);

// ---- steps ----

// Evaluates points at a normalized time in [0,1].
using PointsAt = std::function<void(float u, std::vector<Vec3f>& out)>;
// Fewest vertex steps (1..opt.maxSteps) whose linear interpolation stays
// within `tolerance` of `eval` at 3 times inside each segment; opt.steps
// when not automatic.
uint32_t chooseVertexSteps(const PointsAt& eval, const StepOptions& opt, float tolerance);
// Same for SRT keys sampled from `keyAt`, checked on `points` (e.g. a box's
// corners) moved by the interpolated keys against `worldAt`.
uint32_t chooseSRTSteps(const std::function<SRTKey(float)>& keyAt, const std::function<Affine3f(float)>& worldAt,
                        const std::vector<Vec3f>& points, const StepOptions& opt, float tolerance);

// ---- materials ----

// The materials of a document: base colour factor and base colour texture
// (PNG or JPEG from a buffer view, a data URI or a file beside the glTF),
// each texture decoded once, when a material first uses it.
class Materials {
 public:
  explicit Materials(const Document& doc) : doc_(&doc) {}
  // glTF material `index` (-1: the default material); its texture is added
  // to out.textures on first use. Throws Error naming the file, the image
  // and the problem for a missing or corrupt texture.
  Material material(int index, SceneDescription& out);
  // The TEXCOORD_n set the material's base colour texture reads, -1 when it
  // has no texture.
  int texCoordSet(int index) const;

 private:
  int32_t texture(int index, SceneDescription& out);
  const Document* doc_;
  std::map<int, int32_t> added_;  // glTF texture -> index into out.textures
};

// TEXCOORD_<set> of a primitive, one per vertex. Throws Error when it is
// missing or its count is not `vertices`.
std::vector<TexCoord> readTexCoords(const Document& doc, int mesh, int primitive, int set, size_t vertices,
                                    const std::string& what);

}  // namespace mbrt::gltf
