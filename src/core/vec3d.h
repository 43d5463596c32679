// A double-precision 3-vector for the few places that need the extra bits:
// the ray's transform into an instance (scene/instance_space.h), the
// segment test's retry (geometry/segment_intersect.h) and motion
// decomposition's fits (decompose/affine_fit.h).
#pragma once

#include <algorithm>
#include <cmath>

#include "mbrt/math.h"

namespace mbrt::detail {

struct Vec3d {
  double x = 0, y = 0, z = 0;
  double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  double& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};
inline Vec3d toD(Vec3f v) { return {v.x, v.y, v.z}; }
inline Vec3f toF(Vec3d v) { return {float(v.x), float(v.y), float(v.z)}; }
inline Vec3d operator-(Vec3d a, Vec3d b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3d operator+(Vec3d a, Vec3d b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3d operator-(Vec3d a) { return {-a.x, -a.y, -a.z}; }
inline Vec3d operator*(Vec3d a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3d cross(Vec3d a, Vec3d b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double norm2(Vec3d a) { return dot(a, a); }
inline double normInf(Vec3d a) { return std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}); }
inline Vec3d lerp(Vec3d a, Vec3d b, double f) { return a * (1.0 - f) + b * f; }

}  // namespace mbrt::detail
