// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013):
// shear the triangle into ray space, evaluate the 2-D edge functions, redo
// them in double when one is exactly zero. No ray slips through a shared
// edge or vertex of a closed mesh.
#pragma once

#include "core/ray_query.h"

namespace mbrt::detail {

struct TriangleHit {
  float t, u, v;  // u, v: barycentrics of v1 and v2
};

inline bool intersectTriangle(const RayQuery& ray, Vec3f v0, Vec3f v1, Vec3f v2, TriangleHit& out) {
  const Vec3f A = v0 - ray.org, B = v1 - ray.org, C = v2 - ray.org;
  const int kx = ray.kx, ky = ray.ky, kz = ray.kz;
  const float Ax = A[kx] - ray.Sx * A[kz], Ay = A[ky] - ray.Sy * A[kz];
  const float Bx = B[kx] - ray.Sx * B[kz], By = B[ky] - ray.Sy * B[kz];
  const float Cx = C[kx] - ray.Sx * C[kz], Cy = C[ky] - ray.Sy * C[kz];
  float U = Cx * By - Cy * Bx;
  float V = Ax * Cy - Ay * Cx;
  float W = Bx * Ay - By * Ax;
  if (U == 0.0f || V == 0.0f || W == 0.0f) {
    U = float(double(Cx) * double(By) - double(Cy) * double(Bx));
    V = float(double(Ax) * double(Cy) - double(Ay) * double(Cx));
    W = float(double(Bx) * double(Ay) - double(By) * double(Ax));
  }
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  const float det = U + V + W;
  if (det == 0.0f) return false;
  const float Az = ray.Sz * A[kz], Bz = ray.Sz * B[kz], Cz = ray.Sz * C[kz];
  const float T = U * Az + V * Bz + W * Cz;
  // Compare T/det against [tnear, tfar] without dividing.
  const float sign = det < 0.0f ? -1.0f : 1.0f;
  const float Ts = T * sign, absDet = det * sign;
  if (Ts < ray.tnear * absDet || Ts > ray.tfar * absDet) return false;
  const float rcpDet = 1.0f / det;
  out.t = T * rcpDet;
  if (!(out.t >= ray.tnear && out.t <= ray.tfar)) return false;  // rounding of the division
  out.u = V * rcpDet;
  out.v = W * rcpDet;
  return true;
}

}  // namespace mbrt::detail
