// A ray prepared for traversal: reciprocal direction for slab tests and the
// shear of the watertight triangle test (Woop, Benthin, Wald, JCGT 2013).
#pragma once

#include <cmath>

#include "mbrt/ray.h"

namespace mbrt::detail {

struct RayQuery {
  Vec3f org;
  Vec3f dir;
  Vec3f rdir;  // 1/dir, with +-inf for zero components
  float tnear = 0.0f;
  float tfar = kInf;  // shrinks as closer hits are found
  float time = 0.0f;
  uint32_t mask = ~0u;
  int kx = 0, ky = 1, kz = 2;  // watertight permutation
  float Sx = 0, Sy = 0, Sz = 1;  // watertight shear
  uint32_t instID = kInvalidId;  // outermost instance being traversed

  RayQuery() = default;
  explicit RayQuery(const Ray& ray) { setup(ray.org, ray.dir, ray.tnear, ray.tfar, ray.time, ray.mask); }

  void setup(Vec3f o, Vec3f d, float tn, float tf, float t, uint32_t m) {
    org = o;
    dir = d;
    tnear = tn;
    tfar = tf;
    time = t;
    mask = m;
    rdir = {1.0f / d.x, 1.0f / d.y, 1.0f / d.z};
    const Vec3f a{std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)};
    kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (d[kz] < 0.0f) std::swap(kx, ky);
    Sx = d[kx] / d[kz];
    Sy = d[ky] / d[kz];
    Sz = rdir[kz];  // the same 1 / d[kz], not divided twice
  }

  Ray toRay() const { return Ray{org, tnear, dir, tfar, time, mask}; }
};

}  // namespace mbrt::detail
