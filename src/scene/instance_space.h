// The ray in an instance's space (or a fuzzy kd-tree cluster's frame) at the
// ray's time, without forming the inverse matrix. For the interpolated key M
// = [L | p] with the columns c0, c1, c2 of L, the rows of L^-1 are the
// cofactor rows c1×c2, c2×c0 and c0×c1 divided by det L (Cramer's rule), so
// the local ray is (L^-1 (org - p), L^-1 dir) from three cross products, six
// dot products and one division, in double: the origin's offset from p is
// taken before any rounding, which keeps a far ray's origin as accurate as a
// near one's.
#pragma once

#include <cmath>

#include "core/ray_query.h"
#include "core/vec3d.h"
#include "mbrt/scene.h"

namespace mbrt::detail {

// What a hit in the instance needs to come back: M^-T n for its normal.
struct InstanceFrame {
  Vec3f cofactor[3];  // the rows of det(L) L^-1
  float invDet = 0.0f;

  Vec3f normalToWorld(Vec3f n) const {
    return (cofactor[0] * n.x + cofactor[1] * n.y + cofactor[2] * n.z) * invDet;
  }
};

// Sets `local` to the ray in the space that m maps to world space, and
// `frame` (when given: closest-hit queries) to what its hits need; false
// when m is singular (a flat instance: no hit).
inline bool toLocalSpace(const Affine3f& m, const RayQuery& ray, RayQuery& local, InstanceFrame* frame) {
  const Vec3d c0 = toD(m.vx), c1 = toD(m.vy), c2 = toD(m.vz);
  const Vec3d r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
  const double det = dot(c0, r0);
  if (!(std::fabs(det) > 1e-30)) return false;
  const double inv = 1.0 / det;
  const Vec3d o = toD(ray.org) - toD(m.p), d = toD(ray.dir);
  local.setup({float(dot(r0, o) * inv), float(dot(r1, o) * inv), float(dot(r2, o) * inv)},
              {float(dot(r0, d) * inv), float(dot(r1, d) * inv), float(dot(r2, d) * inv)}, ray.tnear, ray.tfar,
              ray.time, ray.mask);
  if (frame) *frame = {{toF(r0), toF(r1), toF(r2)}, float(inv)};
  return true;
}

// The ray in instance g's space at the ray's time (its keys interpolated).
inline bool toInstanceSpace(const Geometry& g, const RayQuery& ray, RayQuery& local, InstanceFrame* frame) {
  return toLocalSpace(g.transformAt(ray.time), ray, local, frame);
}

}  // namespace mbrt::detail
