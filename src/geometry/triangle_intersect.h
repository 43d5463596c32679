// Watertight ray/triangle intersection (Woop, Benthin, Wald, JCGT 2013):
// shear the triangle into ray space, evaluate the 2-D edge functions, redo
// them in double when one is exactly zero. No ray slips through a shared
// edge or vertex of a closed mesh.
//
// The edge functions are products of two coordinates (relative to the ray's
// origin) and T of three, which overflows float beyond ~5e12. When T or the
// determinant is not finite, they are redone in double from the same float
// edge operands (whose products are exact in double, so the edge signs, and
// watertightness, stay the same), which covers every coordinate up to the
// limit (kMaxCoordinate, 1e18) and ray origins far beyond it.
#pragma once

#include "core/ray_query.h"

namespace mbrt::detail {

struct TriangleHit {
  float t, u, v;  // u, v: barycentrics of v1 and v2
};

// The end of the test in double, for edge functions or T beyond float.
inline bool intersectTriangleWide(const RayQuery& ray, float Ax, float Ay, float Bx, float By, float Cx, float Cy,
                                  float Az, float Bz, float Cz, TriangleHit& out) {
  const double U = double(Cx) * double(By) - double(Cy) * double(Bx);
  const double V = double(Ax) * double(Cy) - double(Ay) * double(Cx);
  const double W = double(Bx) * double(Ay) - double(By) * double(Ax);
  if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
  const double det = U + V + W;
  if (det == 0.0) return false;
  const double t = (U * Az + V * Bz + W * Cz) / det;
  if (!(t >= ray.tnear && t <= ray.tfar)) return false;
  out.t = float(t);
  if (!(out.t >= ray.tnear && out.t <= ray.tfar)) return false;  // rounding to float
  out.u = float(V / det);
  out.v = float(W / det);
  return true;
}

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
  // One test catches an infinite or NaN T or det (and, harmlessly, their
  // sum overflowing).
  if (!std::isfinite(T + det)) [[unlikely]]
    return intersectTriangleWide(ray, Ax, Ay, Bx, By, Cx, Cy, Az, Bz, Cz, out);
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
