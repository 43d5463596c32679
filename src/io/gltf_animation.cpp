// Animation clips: sampler interpolation (LINEAR, STEP, CUBICSPLINE) and the
// node hierarchy's transforms at a time.
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>

#include "io/gltf_internal.h"

namespace mbrt::gltf {

Animator::Animator(const Document& doc, int clip) : doc_(&doc) {
  const tinygltf::Model& m = *doc.model;
  const size_t n = m.nodes.size();
  parent_.assign(n, -1);
  animated_.assign(n, false);
  weightsAnimated_.assign(n, false);
  for (size_t i = 0; i < n; ++i)
    for (int c : m.nodes[i].children) {
      if (c < 0 || size_t(c) >= n) doc.fail("node " + std::to_string(i) + " has a child " + std::to_string(c) + " that does not exist");
      if (parent_[size_t(c)] >= 0) doc.fail("node " + std::to_string(c) + " has two parents (the node hierarchy must be a tree)");
      parent_[size_t(c)] = int(i);
    }
  // Cycles: walk up from every node.
  for (size_t i = 0; i < n; ++i) {
    size_t steps = 0;
    for (int p = parent_[i]; p >= 0; p = parent_[size_t(p)])
      if (++steps > n) doc.fail("the node hierarchy has a cycle through node " + std::to_string(i));
  }
  if (clip < 0) return;
  const tinygltf::Animation& anim = m.animations[size_t(clip)];
  const std::string clipName = "animation " + std::to_string(clip) + (anim.name.empty() ? "" : " '" + anim.name + "'");
  bool any = false;
  start_ = 1e300;
  end_ = -1e300;
  for (size_t ci = 0; ci < anim.channels.size(); ++ci) {
    const tinygltf::AnimationChannel& ch = anim.channels[ci];
    const std::string what = clipName + " channel " + std::to_string(ci);
    if (ch.target_node < 0) continue;  // no target: ignored, as the spec allows
    if (size_t(ch.target_node) >= n) doc.fail(what + " targets node " + std::to_string(ch.target_node) + " that does not exist");
    if (ch.sampler < 0 || size_t(ch.sampler) >= anim.samplers.size())
      doc.fail(what + " uses sampler " + std::to_string(ch.sampler) + " that does not exist");
    const tinygltf::AnimationSampler& s = anim.samplers[size_t(ch.sampler)];
    Channel c;
    c.node = ch.target_node;
    if (ch.target_path == "translation") c.path = 0, c.width = 3;
    else if (ch.target_path == "rotation") c.path = 1, c.width = 4;
    else if (ch.target_path == "scale") c.path = 2, c.width = 3;
    else if (ch.target_path == "weights") {
      c.path = 3;
      const tinygltf::Node& node = m.nodes[size_t(c.node)];
      if (node.mesh < 0 || size_t(node.mesh) >= m.meshes.size()) doc.fail(what + " animates weights of a node without a mesh");
      const auto& prims = m.meshes[size_t(node.mesh)].primitives;
      c.width = prims.empty() ? 0 : int(prims[0].targets.size());
      if (c.width == 0) doc.fail(what + " animates weights of a mesh without morph targets");
    } else {
      continue;  // e.g. KHR_animation_pointer paths: not ours
    }
    if (s.interpolation == "LINEAR" || s.interpolation.empty()) c.interpolation = 0;
    else if (s.interpolation == "STEP") c.interpolation = 1;
    else if (s.interpolation == "CUBICSPLINE") c.interpolation = 2;
    else doc.fail(what + ": unknown interpolation '" + s.interpolation + "'");
    c.times = readFloats(doc, s.input, 1, what + " input (key times)");
    if (c.times.empty()) doc.fail(what + " has no keys");
    for (size_t k = 1; k < c.times.size(); ++k)
      if (!(c.times[k] > c.times[k - 1])) doc.fail(what + ": key times are not increasing at key " + std::to_string(k));
    const size_t perKey = size_t(c.width) * (c.interpolation == 2 ? 3 : 1);
    if (c.path == 3) {
      std::vector<float> v = readFloats(doc, s.output, 1, what + " output");
      c.values = std::move(v);
    } else {
      c.values = readFloats(doc, s.output, c.width, what + " output");
    }
    if (c.values.size() != perKey * c.times.size())
      doc.fail(what + ": " + std::to_string(c.values.size()) + " output values for " + std::to_string(c.times.size()) +
               " keys (expected " + std::to_string(perKey * c.times.size()) + ")");
    start_ = std::min(start_, double(c.times.front()));
    end_ = std::max(end_, double(c.times.back()));
    if (c.path == 3) weightsAnimated_[size_t(c.node)] = true;
    else animated_[size_t(c.node)] = true;
    any = true;
    channels_.push_back(std::move(c));
  }
  if (!any) start_ = end_ = 0.0;
}

bool Animator::movesInWorld(int node) const {
  for (int n = node; n >= 0; n = parent_[size_t(n)])
    if (animated_[size_t(n)]) return true;
  return false;
}

void Animator::sample(const Channel& c, double t, float* out) const {
  const int w = c.width;
  const size_t keys = c.times.size();
  const bool cubic = c.interpolation == 2;
  auto value = [&](size_t k) { return &c.values[(cubic ? 3 * k + 1 : k) * size_t(w)]; };
  if (t <= c.times.front() || keys == 1) {
    std::copy(value(0), value(0) + w, out);
  } else if (t >= c.times.back()) {
    std::copy(value(keys - 1), value(keys - 1) + w, out);
  } else {
    const size_t k = size_t(std::upper_bound(c.times.begin(), c.times.end(), float(t)) - c.times.begin()) - 1;
    const double t0 = c.times[k], t1 = c.times[k + 1], td = t1 - t0;
    const float s = float((t - t0) / td);
    if (c.interpolation == 1) {
      std::copy(value(k), value(k) + w, out);
    } else if (c.interpolation == 0) {
      if (c.path == 1) {
        const float* a = value(k);
        const float* b = value(k + 1);
        const Quaternion q = slerp(Quaternion{a[3], a[0], a[1], a[2]}.normalized(),
                                   Quaternion{b[3], b[0], b[1], b[2]}.normalized(), s);
        out[0] = q.x, out[1] = q.y, out[2] = q.z, out[3] = q.w;
      } else {
        for (int i = 0; i < w; ++i) out[i] = (1 - s) * value(k)[i] + s * value(k + 1)[i];
      }
    } else {
      // Hermite spline: value v, out-tangent b of key k; in-tangent a, value of k+1.
      const float* v0 = value(k);
      const float* b0 = v0 + w;
      const float* a1 = value(k + 1) - w;
      const float* v1 = value(k + 1);
      const float s2 = s * s, s3 = s2 * s;
      const float h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
      for (int i = 0; i < w; ++i)
        out[i] = h00 * v0[i] + float(td) * h10 * b0[i] + h01 * v1[i] + float(td) * h11 * a1[i];
      if (c.path == 1) {
        const float nrm = std::sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
        if (nrm > 0)
          for (int i = 0; i < 4; ++i) out[i] /= nrm;
      }
    }
  }
}

std::vector<NodeTRS> Animator::localAt(double seconds) const {
  const tinygltf::Model& m = *doc_->model;
  std::vector<NodeTRS> out(m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) {
    const tinygltf::Node& n = m.nodes[i];
    NodeTRS& r = out[i];
    if (n.matrix.size() == 16) {
      float f[16];
      for (int k = 0; k < 16; ++k) f[k] = float(n.matrix[size_t(k)]);
      // glTF matrices are column-major: element (row r, col c) at c*4+r.
      r.hasMatrix = true;
      r.matrix.vx = {f[0], f[1], f[2]};
      r.matrix.vy = {f[4], f[5], f[6]};
      r.matrix.vz = {f[8], f[9], f[10]};
      r.matrix.p = {f[12], f[13], f[14]};
    }
    if (n.translation.size() == 3) r.translation = {float(n.translation[0]), float(n.translation[1]), float(n.translation[2])};
    if (n.rotation.size() == 4)
      r.rotation = Quaternion{float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2])};
    if (n.scale.size() == 3) r.scale = {float(n.scale[0]), float(n.scale[1]), float(n.scale[2])};
    for (double w : n.weights) r.weights.push_back(float(w));
  }
  for (const Channel& c : channels_) {
    NodeTRS& r = out[size_t(c.node)];
    float v[64];
    std::vector<float> big;
    float* dst = v;
    if (c.width > 64) {
      big.resize(size_t(c.width));
      dst = big.data();
    }
    sample(c, seconds, dst);
    switch (c.path) {
      case 0: r.translation = {dst[0], dst[1], dst[2]}; break;
      case 1: r.rotation = Quaternion{dst[3], dst[0], dst[1], dst[2]}; break;
      case 2: r.scale = {dst[0], dst[1], dst[2]}; break;
      case 3: r.weights.assign(dst, dst + c.width); break;
    }
    if (c.path != 3) r.hasMatrix = false;  // animated nodes use TRS (the spec forbids matrix + animation)
  }
  for (NodeTRS& r : out) {
    const float nrm = r.rotation.norm();
    if (nrm > 0 && std::isfinite(nrm)) r.rotation = r.rotation.normalized();
    else r.rotation = Quaternion::identity();
  }
  return out;
}

std::vector<Affine3f> Animator::worldFrom(const std::vector<NodeTRS>& local) const {
  const size_t n = local.size();
  std::vector<Affine3f> world(n);
  std::vector<char> done(n, 0);
  std::vector<int> chain;
  for (size_t i = 0; i < n; ++i) {
    chain.clear();
    for (int k = int(i); k >= 0 && !done[size_t(k)]; k = parent_[size_t(k)]) chain.push_back(k);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      const size_t k = size_t(*it);
      const NodeTRS& r = local[k];
      const Affine3f m = r.hasMatrix ? r.matrix : SRTKey{r.scale, r.rotation, r.translation}.toAffine();
      world[k] = parent_[k] >= 0 ? world[size_t(parent_[k])] * m : m;
      done[k] = 1;
    }
  }
  return world;
}

}  // namespace mbrt::gltf
