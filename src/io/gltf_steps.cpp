// Automatic step counts: the fewest steps whose interpolation stays within a
// tolerance of the true motion.
#include <algorithm>
#include <cmath>

#include "io/gltf_internal.h"

namespace mbrt::gltf {
namespace {

constexpr float kProbes[] = {0.25f, 0.5f, 0.75f};

// A step count given by the caller: each step is a copy of the geometry, so
// it is capped (as `--steps` and a scene file's "steps" are).
constexpr uint32_t kMaxExplicitSteps = 1024;

uint32_t explicitSteps(const StepOptions& opt) {
  if (opt.steps > kMaxExplicitSteps)
    throw Error("glTF: " + std::to_string(opt.steps) + " time steps asked for, more than the limit of " +
                std::to_string(kMaxExplicitSteps));
  return opt.steps;
}

}  // namespace

uint32_t chooseVertexSteps(const PointsAt& eval, const StepOptions& opt, float tolerance) {
  if (opt.steps > 0) return explicitSteps(opt);
  const uint32_t most = std::max<uint32_t>(1, opt.maxSteps);
  std::vector<std::vector<Vec3f>> keys;
  std::vector<Vec3f> truth;
  for (uint32_t s = 1; s < most; ++s) {
    keys.resize(s);
    for (uint32_t k = 0; k < s; ++k) eval(s == 1 ? 0.0f : float(k) / float(s - 1), keys[k]);
    bool ok = true;
    if (s == 1) {
      for (float u : {0.25f, 0.5f, 0.75f, 1.0f}) {
        eval(u, truth);
        for (size_t i = 0; i < truth.size() && ok; ++i) ok = length(truth[i] - keys[0][i]) <= tolerance;
        if (!ok) break;
      }
    } else {
      for (uint32_t seg = 0; seg + 1 < s && ok; ++seg)
        for (float f : kProbes) {
          eval((float(seg) + f) / float(s - 1), truth);
          for (size_t i = 0; i < truth.size() && ok; ++i)
            ok = length(truth[i] - lerp(keys[seg][i], keys[seg + 1][i], f)) <= tolerance;
          if (!ok) break;
        }
    }
    if (ok) return s;
  }
  return most;
}

uint32_t chooseSRTSteps(const std::function<SRTKey(float)>& keyAt, const std::function<Affine3f(float)>& worldAt,
                        const std::vector<Vec3f>& points, const StepOptions& opt, float tolerance) {
  if (opt.steps > 0) return explicitSteps(opt);
  const uint32_t most = std::max<uint32_t>(1, opt.maxSteps);
  std::vector<SRTKey> keys;
  for (uint32_t s = 1; s < most; ++s) {
    keys.resize(s);
    for (uint32_t k = 0; k < s; ++k) keys[k] = keyAt(s == 1 ? 0.0f : float(k) / float(s - 1));
    auto within = [&](float u, const Affine3f& approx) {
      const Affine3f truth = worldAt(u);
      for (const Vec3f& p : points)
        if (length(truth.xfmPoint(p) - approx.xfmPoint(p)) > tolerance) return false;
      return true;
    };
    bool ok = true;
    if (s == 1) {
      const Affine3f m = keys[0].toAffine();
      for (float u : {0.25f, 0.5f, 0.75f, 1.0f}) ok = ok && within(u, m);
    } else {
      for (uint32_t seg = 0; seg + 1 < s && ok; ++seg)
        for (float f : kProbes)
          if (!(ok = within((float(seg) + f) / float(s - 1), lerp(keys[seg], keys[seg + 1], f).toAffine()))) break;
    }
    if (ok) return s;
  }
  return most;
}

}  // namespace mbrt::gltf
