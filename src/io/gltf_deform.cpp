// Deforming one primitive: morph targets, then linear blend skinning.
#include "io/gltf_internal.h"

namespace mbrt::gltf {

void morph(const PrimitiveData& p, const std::vector<float>& weights, std::vector<Vec3f>& out) {
  out = p.positions;
  const std::vector<float>& w = weights.empty() ? p.defaultWeights : weights;
  for (size_t t = 0; t < p.targets.size() && t < w.size(); ++t) {
    if (w[t] == 0.0f) continue;
    const std::vector<Vec3f>& d = p.targets[t];
    for (size_t i = 0; i < out.size(); ++i) out[i] += d[i] * w[t];
  }
}

void skin(const PrimitiveData& p, const std::vector<Affine3f>& joints, const Affine3f& fallback,
          std::vector<Vec3f>& positions) {
  const uint32_t n = p.influences;
  for (size_t i = 0; i < positions.size(); ++i) {
    const uint32_t* j = &p.joints[i * n];
    const float* w = &p.weights[i * n];
    float sum = 0.0f;
    for (uint32_t k = 0; k < n; ++k) sum += w[k];
    const Vec3f x = positions[i];
    if (!(sum > 0.0f)) {
      positions[i] = fallback.xfmPoint(x);
      continue;
    }
    Vec3f r{0.0f};
    for (uint32_t k = 0; k < n; ++k)
      if (w[k] != 0.0f) r += joints[j[k]].xfmPoint(x) * w[k];
    positions[i] = r * (1.0f / sum);  // weights are meant to sum to 1; normalize when they do not
  }
}

}  // namespace mbrt::gltf
