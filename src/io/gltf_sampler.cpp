// The glTF scene over a shutter (gltf_sampler.h): what the file holds is read
// once in the constructor; each sample poses the nodes over the shutter,
// deforms the skinned and morphed meshes and keys the rigid ones.
#include "io/gltf_sampler.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>

#include "mbrt/io/loaders.h"

namespace mbrt::gltf {
namespace {

int parseClip(const Document& doc, const std::string& clip) {
  const auto& anims = doc.model->animations;
  if (clip.empty()) return anims.empty() ? -1 : 0;
  std::string names;
  for (size_t i = 0; i < anims.size(); ++i) {
    if (anims[i].name == clip) return int(i);
    names += (names.empty() ? "" : ", ") + std::to_string(i) + (anims[i].name.empty() ? "" : " '" + anims[i].name + "'");
  }
  if (!clip.empty() && std::all_of(clip.begin(), clip.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    const size_t i = std::stoul(clip);
    if (i < anims.size()) return int(i);
  }
  doc.fail("no animation clip '" + clip + "' (the file has " +
           (anims.empty() ? std::string("no animations") : "clips " + names) + ")");
}

void note(LoadReport* report, const std::string& line) {
  if (report) report->lines.push_back(line);
}

}  // namespace

ClipSampler::ClipSampler(const std::string& path, const std::string& clip, const StepOptions& steps,
                         LoadReport* report)
    : doc_(readDocument(path)), steps_(steps) {
  clip_ = parseClip(doc_, clip);
  anim_ = std::make_unique<Animator>(doc_, clip_);
  collectNodes(report);
  if (items_.empty()) doc_.fail("no triangle meshes in the scene");
  describeSurfaces();
}

std::string ClipSampler::clipName() const {
  if (clip_ < 0) return "none (static)";
  const std::string& name = doc_.model->animations[size_t(clip_)].name;
  return std::to_string(clip_) + (name.empty() ? std::string() : " '" + name + "'");
}

std::pair<double, double> ClipSampler::shutter(const GltfOptions& options) const {
  if (options.fps <= 0 || !std::isfinite(options.fps)) doc_.fail("fps must be positive");
  const double length = options.shutterAngleDegrees / 360.0 / options.fps;
  const double open = options.shutterOpen.value_or(clipStart());
  return {open, options.shutterClose.value_or(std::min(open + length, std::max(clipEnd(), open)))};
}

void ClipSampler::setShutter(double open, double close) {
  if (!std::isfinite(open) || !std::isfinite(close) || close < open)
    doc_.fail("bad shutter [" + std::to_string(open) + ", " + std::to_string(close) + "] s (open <= close needed)");
  if (clip_ >= 0) {
    const double start = clipStart(), end = clipEnd();
    const double eps = 1e-6 * std::max(1.0, std::fabs(end));
    if (open < start - eps || close > end + eps) {
      const auto& a = doc_.model->animations[size_t(clip_)];
      doc_.fail("shutter [" + std::to_string(open) + ", " + std::to_string(close) + "] s is outside clip " +
                std::to_string(clip_) + (a.name.empty() ? "" : " '" + a.name + "'") + " (" + std::to_string(start) +
                " to " + std::to_string(end) + " s)");
    }
  }
  open_ = open;
  close_ = close;
  sharp_ = close_ == open_ || clip_ < 0;
  poses_.clear();
}

io::FrameGeometry ClipSampler::sample(double open, double close, LoadReport* report) {
  setShutter(open, close);
  // Tolerance of the automatic mode: relative to the scene's size at the
  // shutter's ends.
  Box3f bounds;
  for (const Item& it : items_)
    for (float u : {0.0f, 1.0f}) {
      evalWorld(it, u, scratch_);
      for (const Vec3f& p : scratch_) bounds.extend(p);
    }
  tolerance_ = steps_.tolerance * std::max(length(bounds.size()), 1e-6f);

  io::FrameGeometry out;
  out.scene = std::make_shared<Scene>();
  for (const Item& it : items_) addItem(it, *out.scene, report);
  out.camera = camera(*out.scene, report);
  if (report)
    report->lines.insert(report->lines.begin(),
                         "clip " + clipName() + " [" + std::to_string(clipStart()) + ", " + std::to_string(clipEnd()) +
                             "] s, shutter [" + std::to_string(open_) + ", " + std::to_string(close_) + "] s");
  return out;
}

const ClipSampler::Pose& ClipSampler::poseAt(float u) {
  auto it = poses_.find(u);
  if (it != poses_.end()) return it->second;
  if (poses_.size() > 4096) poses_.clear();
  Pose p;
  p.local = anim_->localAt(open_ + double(u) * (close_ - open_));
  p.world = anim_->worldFrom(p.local);
  return poses_.emplace(u, std::move(p)).first->second;
}

const PrimitiveData& ClipSampler::primitiveData(int mesh, int prim, bool wantSkin) {
  const auto key = std::make_pair(mesh, prim);
  auto found = prims_.find(key);
  if (found != prims_.end()) return found->second;
  const tinygltf::Model& m = *doc_.model;
  const tinygltf::Mesh& me = m.meshes[size_t(mesh)];
  const tinygltf::Primitive& p = me.primitives[size_t(prim)];
  const std::string what = "mesh " + std::to_string(mesh) + (me.name.empty() ? "" : " '" + me.name + "'") +
                           " primitive " + std::to_string(prim);
  PrimitiveData d;
  const auto pos = p.attributes.find("POSITION");
  if (pos == p.attributes.end()) doc_.fail(what + " has no POSITION");
  const std::vector<float> f = readFloats(doc_, pos->second, 3, what + " POSITION");
  d.positions.resize(f.size() / 3);
  for (size_t i = 0; i < d.positions.size(); ++i) d.positions[i] = {f[3 * i], f[3 * i + 1], f[3 * i + 2]};
  for (size_t t = 0; t < p.targets.size(); ++t) {
    std::vector<Vec3f> delta(d.positions.size(), Vec3f(0.0f));
    const auto tp = p.targets[t].find("POSITION");
    if (tp != p.targets[t].end()) {
      const std::vector<float> g = readFloats(doc_, tp->second, 3, what + " morph target " + std::to_string(t));
      if (g.size() != f.size()) doc_.fail(what + " morph target " + std::to_string(t) + " has another vertex count");
      for (size_t i = 0; i < delta.size(); ++i) delta[i] = {g[3 * i], g[3 * i + 1], g[3 * i + 2]};
    }
    d.targets.push_back(std::move(delta));
  }
  for (double w : me.weights) d.defaultWeights.push_back(float(w));
  d.defaultWeights.resize(d.targets.size(), 0.0f);
  if (wantSkin && p.attributes.count("JOINTS_0") && p.attributes.count("WEIGHTS_0")) {
    std::vector<std::vector<uint32_t>> js;
    std::vector<std::vector<float>> ws;
    for (int set = 0;; ++set) {
      const auto j = p.attributes.find("JOINTS_" + std::to_string(set));
      const auto w = p.attributes.find("WEIGHTS_" + std::to_string(set));
      if (j == p.attributes.end() || w == p.attributes.end()) break;
      js.push_back(readUints(doc_, j->second, 4, what + " JOINTS_" + std::to_string(set)));
      ws.push_back(readFloats(doc_, w->second, 4, what + " WEIGHTS_" + std::to_string(set)));
      if (js.back().size() != f.size() / 3 * 4 || ws.back().size() != f.size() / 3 * 4)
        doc_.fail(what + " JOINTS_/WEIGHTS_" + std::to_string(set) + " do not match the vertex count");
    }
    const size_t sets = js.size(), n = d.positions.size();
    d.influences = uint32_t(4 * sets);
    d.joints.resize(n * d.influences);
    d.weights.resize(n * d.influences);
    for (size_t i = 0; i < n; ++i)
      for (size_t s = 0; s < sets; ++s)
        for (size_t k = 0; k < 4; ++k) {
          d.joints[i * d.influences + 4 * s + k] = js[s][4 * i + k];
          d.weights[i * d.influences + 4 * s + k] = ws[s][4 * i + k];
        }
  }
  return prims_.emplace(key, std::move(d)).first->second;
}

std::vector<Triangle> ClipSampler::triangles(const tinygltf::Primitive& p, size_t vertices, const std::string& what) {
  std::vector<uint32_t> idx;
  if (p.indices >= 0) {
    idx = readUints(doc_, p.indices, 1, what + " indices");
  } else {
    idx.resize(vertices);
    for (size_t i = 0; i < vertices; ++i) idx[i] = uint32_t(i);
  }
  for (size_t i = 0; i < idx.size(); ++i)
    if (idx[i] >= vertices)
      doc_.fail(what + ": index " + std::to_string(i) + " is " + std::to_string(idx[i]) + ", but there are " +
                std::to_string(vertices) + " vertices");
  std::vector<Triangle> t;
  const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < idx.size(); i += 3) t.push_back({idx[i], idx[i + 1], idx[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < idx.size(); ++i)
      t.push_back(i % 2 == 0 ? Triangle{idx[i], idx[i + 1], idx[i + 2]} : Triangle{idx[i + 1], idx[i], idx[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 1; i + 1 < idx.size(); ++i) t.push_back({idx[0], idx[i], idx[i + 1]});
  }
  return t;
}

void ClipSampler::collectNodes(LoadReport* report) {
  const tinygltf::Model& m = *doc_.model;
  std::vector<int> roots;
  const int sceneIndex = m.defaultScene >= 0 ? m.defaultScene : (m.scenes.empty() ? -1 : 0);
  if (sceneIndex >= 0) {
    if (size_t(sceneIndex) >= m.scenes.size()) doc_.fail("default scene " + std::to_string(sceneIndex) + " does not exist");
    roots = m.scenes[size_t(sceneIndex)].nodes;
  } else {
    for (size_t i = 0; i < m.nodes.size(); ++i)
      if (anim_->parent(int(i)) < 0) roots.push_back(int(i));
  }
  std::vector<int> stack(roots.rbegin(), roots.rend());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (n < 0 || size_t(n) >= m.nodes.size()) doc_.fail("scene uses node " + std::to_string(n) + " that does not exist");
    const tinygltf::Node& node = m.nodes[size_t(n)];
    for (auto c = node.children.rbegin(); c != node.children.rend(); ++c) stack.push_back(*c);
    if (node.camera >= 0 && size_t(node.camera) >= m.cameras.size())
      doc_.fail("node " + std::to_string(n) + " uses camera " + std::to_string(node.camera) + " that does not exist");
    if (node.camera >= 0 && cameraNode_ < 0) cameraNode_ = n;
    if (node.mesh < 0) continue;
    if (size_t(node.mesh) >= m.meshes.size()) doc_.fail("node " + std::to_string(n) + " uses mesh " + std::to_string(node.mesh) + " that does not exist");
    if (node.skin >= 0 && size_t(node.skin) >= m.skins.size())
      doc_.fail("node " + std::to_string(n) + " uses skin " + std::to_string(node.skin) + " that does not exist");
    const tinygltf::Mesh& mesh = m.meshes[size_t(node.mesh)];
    for (size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const tinygltf::Primitive& p = mesh.primitives[pi];
      const int mode = p.mode < 0 ? TINYGLTF_MODE_TRIANGLES : p.mode;
      const std::string what = "mesh " + std::to_string(node.mesh) + (mesh.name.empty() ? "" : " '" + mesh.name + "'") +
                               " primitive " + std::to_string(pi);
      if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
        note(report, what + ": points or lines, skipped");
        continue;
      }
      Item it;
      it.node = n;
      it.mesh = node.mesh;
      it.primitive = int(pi);
      it.name = !node.name.empty() ? node.name : (!mesh.name.empty() ? mesh.name : "node " + std::to_string(n));
      it.data = &primitiveData(node.mesh, int(pi), node.skin >= 0);
      it.triangles = triangles(p, it.data->positions.size(), what);
      if (it.triangles.empty()) continue;
      it.skinned = node.skin >= 0 && it.data->influences > 0;
      if (it.skinned) {
        const tinygltf::Skin& skin = m.skins[size_t(node.skin)];
        for (uint32_t j : it.data->joints)
          if (j >= skin.joints.size())
            doc_.fail(what + " uses joint " + std::to_string(j) + " but skin " + std::to_string(node.skin) + " has " +
                      std::to_string(skin.joints.size()));
        skinMatrices(node.skin);  // checks the skin
      }
      it.material = p.material;
      if (it.skinned || (anim_->weightsAnimated(n) && !it.data->targets.empty())) it.motion = Motion::Deforming;
      else if (anim_->movesInWorld(n)) it.motion = Motion::Rigid;
      else it.motion = Motion::Static;
      items_.push_back(std::move(it));
    }
  }
}

// Inverse bind matrices of a skin (identity when absent).
const std::vector<Affine3f>& ClipSampler::skinMatrices(int skinIndex) {
  auto found = ibm_.find(skinIndex);
  if (found != ibm_.end()) return found->second;
  const tinygltf::Skin& skin = doc_.model->skins[size_t(skinIndex)];
  std::vector<Affine3f> out(skin.joints.size());
  for (int j : skin.joints)
    if (j < 0 || size_t(j) >= doc_.model->nodes.size())
      doc_.fail("skin " + std::to_string(skinIndex) + " uses joint node " + std::to_string(j) + " that does not exist");
  if (skin.inverseBindMatrices >= 0) {
    const std::vector<float> f =
        readFloats(doc_, skin.inverseBindMatrices, 16, "skin " + std::to_string(skinIndex) + " inverseBindMatrices");
    if (f.size() / 16 < out.size())
      doc_.fail("skin " + std::to_string(skinIndex) + " has fewer inverse bind matrices than joints");
    for (size_t j = 0; j < out.size(); ++j) {
      const float* c = &f[16 * j];  // column-major
      out[j].vx = {c[0], c[1], c[2]};
      out[j].vy = {c[4], c[5], c[6]};
      out[j].vz = {c[8], c[9], c[10]};
      out[j].p = {c[12], c[13], c[14]};
    }
  }
  return ibm_.emplace(skinIndex, std::move(out)).first->second;
}

// World-space positions of an item at normalized time u.
void ClipSampler::evalWorld(const Item& it, float u, std::vector<Vec3f>& out) {
  const Pose& pose = poseAt(sharp_ ? 0.0f : u);
  morph(*it.data, pose.local[size_t(it.node)].weights, out);
  const Affine3f& world = pose.world[size_t(it.node)];
  if (it.skinned) {
    const int skinIndex = doc_.model->nodes[size_t(it.node)].skin;
    const tinygltf::Skin& skin = doc_.model->skins[size_t(skinIndex)];
    const std::vector<Affine3f>& ibm = skinMatrices(skinIndex);
    joints_.resize(skin.joints.size());
    for (size_t j = 0; j < joints_.size(); ++j) joints_[j] = pose.world[size_t(skin.joints[j])] * ibm[j];
    gltf::skin(*it.data, joints_, world, out);
  } else {
    for (Vec3f& p : out) p = world.xfmPoint(p);
  }
}

}  // namespace mbrt::gltf
