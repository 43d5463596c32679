// The ray in an instance's space (or a fuzzy kd-tree cluster's frame) at the ray's time, without forming the
// inverse matrix. For the interpolated key M = [L | p] with the columns
// c0, c1, c2 of L, the rows of L^-1 are the cofactor rows c1×c2, c2×c0 and
// c0×c1 divided by det L (Cramer's rule), so the local ray is
// (L^-1 (org - p), L^-1 dir) from three cross products, six dot products and
// one division, in double: the origin's offset from p is taken before any
// rounding, which keeps a far ray's origin as accurate as a near one's.
#pragma once

#include <cmath>

#include "core/ray_query.h"
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

// Sets `local` to the ray in the space that m maps to world space (and
// frame to what its hits need); false when m is singular (a flat instance:
// no hit).
inline bool toLocalSpace(const Affine3f& m, const RayQuery& ray, RayQuery& local, InstanceFrame& frame) {
  struct D3 {
    double x, y, z;
  };
  const auto d3 = [](Vec3f v) { return D3{v.x, v.y, v.z}; };
  const auto cross = [](D3 a, D3 b) { return D3{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
  const auto dot = [](D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; };
  const D3 c0 = d3(m.vx), c1 = d3(m.vy), c2 = d3(m.vz);
  const D3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
  const double det = dot(c0, r0);
  if (!(std::fabs(det) > 1e-30)) return false;
  const double inv = 1.0 / det;
  const D3 o{double(ray.org.x) - m.p.x, double(ray.org.y) - m.p.y, double(ray.org.z) - m.p.z};
  const D3 d = d3(ray.dir);
  local.setup({float(dot(r0, o) * inv), float(dot(r1, o) * inv), float(dot(r2, o) * inv)},
              {float(dot(r0, d) * inv), float(dot(r1, d) * inv), float(dot(r2, d) * inv)}, ray.tnear, ray.tfar,
              ray.time, ray.mask);
  frame.cofactor[0] = {float(r0.x), float(r0.y), float(r0.z)};
  frame.cofactor[1] = {float(r1.x), float(r1.y), float(r1.z)};
  frame.cofactor[2] = {float(r2.x), float(r2.y), float(r2.z)};
  frame.invDet = float(inv);
  return true;
}

// The ray in instance g's space at the ray's time (its keys interpolated).
inline bool toInstanceSpace(const Geometry& g, const RayQuery& ray, RayQuery& local, InstanceFrame& frame) {
  return toLocalSpace(g.transformAt(ray.time), ray, local, frame);
}

}  // namespace mbrt::detail
