// What Embree is allowed to see of a ray. Embree 3 asserts (ray.valid(),
// SIGABRT) on an origin or direction component beyond its FLT_LARGE,
// 1.844e18, although mbrt accepts any finite origin. Scene coordinates are
// within kMaxCoordinate (1e18), so a ray whose origin is farther out can only
// hit inside the cube |x| <= kEmbreeClipCube: such a ray is moved forward to
// where it enters that cube (t0), traced from there, and its hit distances
// are shifted back by t0. A ray that misses the cube misses everything.
#pragma once

#include <algorithm>
#include <cmath>

#include "mbrt/math.h"
#include "mbrt/scene.h"

namespace mbrt::detail {

// Origins up to this are handed to Embree as they are (below FLT_LARGE with
// room for rounding); farther ones are moved onto the clip cube.
constexpr float kEmbreeOriginLimit = 1.5e18f;
// The cube the far origins are moved onto: the coordinate limit with margin.
constexpr float kEmbreeClipCube = 1.25f * kMaxCoordinate;

struct EmbreeRayClip {
  bool miss = false;   // the ray cannot reach the scene: do not call Embree
  float shift = 0.0f;  // Embree's org = org + shift * dir; its t = ours - shift
  Vec3f org;
  float tnear = 0.0f, tfar = 0.0f;
};

// dir's components must be finite and at most FLT_LARGE (the structures see
// directions scaled to a largest component in [1, 2)).
inline EmbreeRayClip clipForEmbree(Vec3f org, Vec3f dir, float tnear, float tfar) {
  EmbreeRayClip c;
  c.org = org;
  c.tnear = std::max(tnear, 0.0f);  // Embree never traces behind the origin (it asserts tnear >= 0)
  c.tfar = tfar;
  const float reach = std::max({std::fabs(org.x), std::fabs(org.y), std::fabs(org.z)});
  if (reach <= kEmbreeOriginLimit) return c;
  // Slab test against the clip cube, in double: t values near 1e18 / |dir|.
  double t0 = c.tnear, t1 = c.tfar;
  const double o[3] = {org.x, org.y, org.z}, d[3] = {dir.x, dir.y, dir.z};
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0.0) {
      if (std::fabs(o[a]) > kEmbreeClipCube) c.miss = true;
      continue;
    }
    double lo = (-double(kEmbreeClipCube) - o[a]) / d[a], hi = (double(kEmbreeClipCube) - o[a]) / d[a];
    if (lo > hi) std::swap(lo, hi);
    t0 = std::max(t0, lo);
    t1 = std::min(t1, hi);
  }
  if (c.miss || !(t0 <= t1)) {
    c.miss = true;
    return c;
  }
  c.shift = float(t0);
  c.org = {float(o[0] + d[0] * t0), float(o[1] + d[1] * t0), float(o[2] + d[2] * t0)};
  c.tnear = 0.0f;
  c.tfar = tfar - c.shift;  // inf stays inf
  return c;
}

}  // namespace mbrt::detail
