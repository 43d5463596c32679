// Rotations as unit quaternions and SRT (scale, rotation, translation) keys
// for instance motion: between two keys, scale and translation are
// interpolated linearly and the rotation by slerp along the shorter arc, and
// the matrix is composed as T * R * S (scale first). This is the motion model
// of Embree's RTCQuaternionDecomposition and OptiX's SRT motion transforms
// (without their shear and pivot terms): a spinning object keeps its shape
// between keys, where element-wise matrix interpolation would shrink it.
#pragma once

#include <cmath>

#include "mbrt/math.h"

namespace mbrt {

// q = w + x i + y j + z k. Rotations use unit quaternions.
struct Quaternion {
  float w = 1, x = 0, y = 0, z = 0;

  static constexpr Quaternion identity() { return {}; }
  // Rotation by `radians` about `axis` (any length but zero), right-handed.
  static Quaternion fromAxisAngle(Vec3f axis, float radians) {
    const Vec3f u = normalize(axis);
    const float s = std::sin(0.5f * radians);
    return {std::cos(0.5f * radians), u.x * s, u.y * s, u.z * s};
  }
  // The rotation of an orthonormal, right-handed matrix's linear part.
  static Quaternion fromRotationMatrix(Vec3f cx, Vec3f cy, Vec3f cz);

  float norm() const { return std::sqrt(w * w + x * x + y * y + z * z); }
  bool isFinite() const { return std::isfinite(w) && std::isfinite(x) && std::isfinite(y) && std::isfinite(z); }
  Quaternion normalized() const {
    const float n = norm();
    return {w / n, x / n, y / n, z / n};
  }
  Quaternion operator-() const { return {-w, -x, -y, -z}; }

  // Rotates a vector (the quaternion must be unit).
  Vec3f rotate(Vec3f v) const {
    const Vec3f u{x, y, z};
    const Vec3f t = 2.0f * cross(u, v);
    return v + w * t + cross(u, t);
  }
  // Columns of the rotation matrix (the quaternion must be unit).
  void toMatrix(Vec3f& cx, Vec3f& cy, Vec3f& cz) const {
    cx = {1 - 2 * (y * y + z * z), 2 * (x * y + w * z), 2 * (x * z - w * y)};
    cy = {2 * (x * y - w * z), 1 - 2 * (x * x + z * z), 2 * (y * z + w * x)};
    cz = {2 * (x * z + w * y), 2 * (y * z - w * x), 1 - 2 * (x * x + y * y)};
  }
};

constexpr float dot(const Quaternion& a, const Quaternion& b) {
  return a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Quaternion operator*(const Quaternion& a, const Quaternion& b) {
  return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
          a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}

// Angle (radians, in [0, pi]) of the rotation taking unit a to unit b along
// the shorter arc.
inline float rotationAngle(const Quaternion& a, const Quaternion& b) {
  // 2*atan2(|a - b|, |a + b|) is accurate for small angles, unlike acos.
  const Quaternion bb = dot(a, b) < 0 ? -b : b;
  const float dw = a.w - bb.w, dx = a.x - bb.x, dy = a.y - bb.y, dz = a.z - bb.z;
  const float sw = a.w + bb.w, sx = a.x + bb.x, sy = a.y + bb.y, sz = a.z + bb.z;
  return 4.0f * std::atan2(std::sqrt(dw * dw + dx * dx + dy * dy + dz * dz),
                           std::sqrt(sw * sw + sx * sx + sy * sy + sz * sz));
}

// Spherical linear interpolation of unit quaternions along the shorter arc:
// constant angular velocity about a fixed axis. Keys closer than 1e-4 rad
// are interpolated linearly and renormalized (the difference is below float
// precision there).
inline Quaternion slerp(const Quaternion& a, Quaternion b, float t) {
  if (dot(a, b) < 0) b = -b;
  const float theta = 0.5f * rotationAngle(a, b);  // angle between a and b on the 4D sphere
  float wa, wb;
  if (theta < 1e-4f) {
    wa = 1.0f - t;
    wb = t;
  } else {
    const float s = std::sin(theta);
    wa = std::sin((1.0f - t) * theta) / s;
    wb = std::sin(t * theta) / s;
  }
  Quaternion q{wa * a.w + wb * b.w, wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z};
  return q.normalized();
}

inline Quaternion Quaternion::fromRotationMatrix(Vec3f cx, Vec3f cy, Vec3f cz) {
  // m[row][col]: column c is (cx, cy, cz)[c].
  const float m00 = cx.x, m10 = cx.y, m20 = cx.z;
  const float m01 = cy.x, m11 = cy.y, m21 = cy.z;
  const float m02 = cz.x, m12 = cz.y, m22 = cz.z;
  const float trace = m00 + m11 + m22;
  Quaternion q;
  if (trace > 0) {
    const float s = 0.5f / std::sqrt(trace + 1.0f);
    q = {0.25f / s, (m21 - m12) * s, (m02 - m20) * s, (m10 - m01) * s};
  } else if (m00 > m11 && m00 > m22) {
    const float s = 2.0f * std::sqrt(1.0f + m00 - m11 - m22);
    q = {(m21 - m12) / s, 0.25f * s, (m01 + m10) / s, (m02 + m20) / s};
  } else if (m11 > m22) {
    const float s = 2.0f * std::sqrt(1.0f + m11 - m00 - m22);
    q = {(m02 - m20) / s, (m01 + m10) / s, 0.25f * s, (m12 + m21) / s};
  } else {
    const float s = 2.0f * std::sqrt(1.0f + m22 - m00 - m11);
    q = {(m10 - m01) / s, (m02 + m20) / s, (m12 + m21) / s, 0.25f * s};
  }
  return q.normalized();
}

// One SRT key: p' = translation + rotation * (scale * p).
struct SRTKey {
  Vec3f scale{1, 1, 1};
  Quaternion rotation;
  Vec3f translation{0, 0, 0};

  Affine3f toAffine() const {
    Affine3f a;
    rotation.toMatrix(a.vx, a.vy, a.vz);
    a.vx *= scale.x;
    a.vy *= scale.y;
    a.vz *= scale.z;
    a.p = translation;
    return a;
  }
};

inline SRTKey lerp(const SRTKey& a, const SRTKey& b, float t) {
  return {lerp(a.scale, b.scale, t), slerp(a.rotation, b.rotation, t), lerp(a.translation, b.translation, t)};
}

// Splits a matrix into scale, rotation and translation when it has no shear
// (its columns are orthogonal within `tolerance`, relative). A negative
// determinant goes into the sign of scale.x. Returns false for shear or a
// singular matrix.
inline bool decomposeSRT(const Affine3f& m, SRTKey& out, float tolerance = 1e-4f) {
  const float sx = length(m.vx), sy = length(m.vy), sz = length(m.vz);
  if (!(sx > 0 && sy > 0 && sz > 0) || !std::isfinite(sx * sy * sz)) return false;
  Vec3f cx = m.vx / sx, cy = m.vy / sy, cz = m.vz / sz;
  if (std::fabs(dot(cx, cy)) > tolerance || std::fabs(dot(cx, cz)) > tolerance ||
      std::fabs(dot(cy, cz)) > tolerance)
    return false;
  float signX = 1.0f;
  if (dot(cx, cross(cy, cz)) < 0) {
    signX = -1.0f;
    cx = -cx;
  }
  out.scale = {signX * sx, sy, sz};
  out.rotation = Quaternion::fromRotationMatrix(cx, cy, cz);
  out.translation = m.p;
  return true;
}

}  // namespace mbrt
