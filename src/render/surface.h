// The shading frame at a hit: position, normal facing the incoming ray,
// albedo, and directions sampled around the normal.
#pragma once

#include <cmath>
#include <numbers>

#include "mbrt/ray.h"
#include "mbrt/render.h"

namespace mbrt::renderer {

struct Surface {
  Vec3f p;       // hit point
  Vec3f n;       // unit geometric normal, on the side the ray came from
  Vec3f albedo;

  // A ray leaving the surface (offset along the normal) at the given time.
  Ray spawn(Vec3f dir, float time, float epsilon, float tfar = kInf) const {
    Ray r;
    r.org = p + n * epsilon;
    r.dir = dir;
    r.tnear = 0.0f;
    r.tfar = tfar;
    r.time = time;
    return r;
  }
};

inline Surface surfaceAt(const SceneDescription& scene, const Ray& ray, const Hit& hit) {
  Surface s;
  s.p = ray.org + ray.dir * hit.t;
  const float len2 = dot(hit.Ng, hit.Ng);
  s.n = len2 > 0.0f && std::isfinite(len2) ? hit.Ng * (1.0f / std::sqrt(len2)) : -normalize(ray.dir);
  if (dot(s.n, ray.dir) > 0.0f) s.n = -s.n;
  s.albedo = albedoAt(scene, hit);
  return s;
}

// Orthonormal basis around n (Duff et al. 2017).
inline void basis(Vec3f n, Vec3f& t, Vec3f& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

// Cosine-weighted direction around n (pdf cos/pi).
inline Vec3f cosineDirection(Vec3f n, float u1, float u2) {
  const float r = std::sqrt(u1);
  const float phi = 2.0f * std::numbers::pi_v<float> * u2;
  Vec3f t, b;
  basis(n, t, b);
  const Vec3f d = t * (r * std::cos(phi)) + b * (r * std::sin(phi)) + n * std::sqrt(std::max(0.0f, 1.0f - u1));
  return normalize(d);
}

}  // namespace mbrt::renderer
