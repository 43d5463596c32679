// Small vector-math vocabulary shared by the public API and every structure:
// Vec3f, Box3f, LBounds (linear bounds over time), TimeRange, Affine3f.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace mbrt {

constexpr float kInf = std::numeric_limits<float>::infinity();

struct Vec3f {
  float x = 0, y = 0, z = 0;

  constexpr Vec3f() = default;
  constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit Vec3f(float s) : x(s), y(s), z(s) {}

  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

constexpr Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr Vec3f operator-(Vec3f a) { return {-a.x, -a.y, -a.z}; }
constexpr Vec3f operator*(Vec3f a, Vec3f b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr Vec3f operator*(float s, Vec3f a) { return a * s; }
constexpr Vec3f operator/(Vec3f a, float s) { return {a.x / s, a.y / s, a.z / s}; }
constexpr Vec3f& operator+=(Vec3f& a, Vec3f b) { return a = a + b; }
constexpr Vec3f& operator-=(Vec3f& a, Vec3f b) { return a = a - b; }
constexpr Vec3f& operator*=(Vec3f& a, float s) { return a = a * s; }
constexpr bool operator==(Vec3f a, Vec3f b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

constexpr float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3f a) { return std::sqrt(dot(a, a)); }
inline Vec3f normalize(Vec3f a) { return a * (1.0f / length(a)); }
constexpr Vec3f min(Vec3f a, Vec3f b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
constexpr Vec3f max(Vec3f a, Vec3f b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
constexpr Vec3f lerp(Vec3f a, Vec3f b, float t) { return a * (1.0f - t) + b * t; }
inline bool isFinite(Vec3f a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
constexpr float maxComponent(Vec3f a) { return std::max(a.x, std::max(a.y, a.z)); }

// Axis-aligned box. An empty box has lower > upper.
struct Box3f {
  Vec3f lower{kInf};
  Vec3f upper{-kInf};

  constexpr Box3f() = default;
  constexpr Box3f(Vec3f lo, Vec3f hi) : lower(lo), upper(hi) {}
  constexpr explicit Box3f(Vec3f p) : lower(p), upper(p) {}

  constexpr void extend(Vec3f p) { lower = min(lower, p); upper = max(upper, p); }
  constexpr void extend(const Box3f& b) { lower = min(lower, b.lower); upper = max(upper, b.upper); }
  constexpr bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  constexpr Vec3f size() const { return upper - lower; }
  constexpr Vec3f center() const { return (lower + upper) * 0.5f; }
  constexpr float halfArea() const {
    if (empty()) return 0.0f;
    Vec3f d = size();
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
  constexpr float area() const { return 2.0f * halfArea(); }
  constexpr bool contains(Vec3f p) const {
    return p.x >= lower.x && p.y >= lower.y && p.z >= lower.z && p.x <= upper.x &&
           p.y <= upper.y && p.z <= upper.z;
  }
  constexpr bool contains(const Box3f& b) const {
    return b.empty() || (contains(b.lower) && contains(b.upper));
  }
  constexpr int largestAxis() const {
    Vec3f d = size();
    return d.x >= d.y && d.x >= d.z ? 0 : (d.y >= d.z ? 1 : 2);
  }
};

constexpr Box3f merge(const Box3f& a, const Box3f& b) {
  return {min(a.lower, b.lower), max(a.upper, b.upper)};
}
constexpr Box3f intersect(const Box3f& a, const Box3f& b) {
  return {max(a.lower, b.lower), min(a.upper, b.upper)};
}
constexpr Box3f lerp(const Box3f& a, const Box3f& b, float t) {
  return {lerp(a.lower, b.lower, t), lerp(a.upper, b.upper, t)};
}

// Linear bounds (STBVH paper §3.3): the box at time t is lerp(b0, b1, t'),
// where t' is t mapped to the range the bounds were made for. Nodes store
// them "global", for t' = t over [0,1].
struct LBounds {
  Box3f b0, b1;

  constexpr LBounds() = default;
  constexpr LBounds(const Box3f& a, const Box3f& b) : b0(a), b1(b) {}
  constexpr explicit LBounds(const Box3f& b) : b0(b), b1(b) {}

  constexpr Box3f at(float t) const { return lerp(b0, b1, t); }
  constexpr Box3f hull() const { return merge(b0, b1); }  // union over [0,1]
  constexpr void extend(const LBounds& o) { b0.extend(o.b0); b1.extend(o.b1); }
  constexpr bool empty() const { return b0.empty() && b1.empty(); }
  // Mean half-area over [0,1], exact for linearly moving boxes (quadratic in t):
  // integral of a quadratic = Simpson's rule.
  constexpr float meanHalfArea() const {
    return (at(0.0f).halfArea() + 4.0f * at(0.5f).halfArea() + at(1.0f).halfArea()) / 6.0f;
  }
};

constexpr LBounds merge(const LBounds& a, const LBounds& b) {
  return {merge(a.b0, b.b0), merge(a.b1, b.b1)};
}

// Bounds a ray can hit: both boxes non-empty with finite planes. Primitives
// whose bounds are not usable (degenerate or overflowing) can never be hit
// and every structure leaves them out.
inline bool isUsable(const LBounds& b) {
  return !b.b0.empty() && !b.b1.empty() && isFinite(b.b0.lower) && isFinite(b.b0.upper) && isFinite(b.b1.lower) &&
         isFinite(b.b1.upper);
}

// Half-open time range [lo, hi), except that a range ending at 1 contains 1.
struct TimeRange {
  float lo = 0.0f, hi = 1.0f;

  constexpr bool contains(float t) const { return t >= lo && (t < hi || (hi >= 1.0f && t <= hi)); }
  constexpr float size() const { return hi - lo; }
  constexpr float center() const { return 0.5f * (lo + hi); }
  constexpr bool operator==(const TimeRange&) const = default;
};

// Affine transform: p' = L p + t, with L given by its columns.
struct Affine3f {
  Vec3f vx{1, 0, 0}, vy{0, 1, 0}, vz{0, 0, 1};
  Vec3f p{0, 0, 0};

  static constexpr Affine3f identity() { return {}; }
  static constexpr Affine3f translate(Vec3f t) {
    Affine3f a;
    a.p = t;
    return a;
  }
  static constexpr Affine3f scale(Vec3f s) {
    Affine3f a;
    a.vx = {s.x, 0, 0};
    a.vy = {0, s.y, 0};
    a.vz = {0, 0, s.z};
    return a;
  }
  static Affine3f rotate(Vec3f axis, float radians);
  // Row-major 4x4 (m[row][col]); the last row must be (0,0,0,1).
  static Affine3f fromRowMajor4x4(const float m[16]);

  constexpr Vec3f xfmVector(Vec3f v) const { return vx * v.x + vy * v.y + vz * v.z; }
  constexpr Vec3f xfmPoint(Vec3f v) const { return xfmVector(v) + p; }
  float determinant() const { return dot(vx, cross(vy, vz)); }
  Affine3f inverse() const;
  bool isFinite() const {
    return mbrt::isFinite(vx) && mbrt::isFinite(vy) && mbrt::isFinite(vz) && mbrt::isFinite(p);
  }
};

constexpr Affine3f operator*(const Affine3f& a, const Affine3f& b) {
  Affine3f r;
  r.vx = a.xfmVector(b.vx);
  r.vy = a.xfmVector(b.vy);
  r.vz = a.xfmVector(b.vz);
  r.p = a.xfmPoint(b.p);
  return r;
}

// Element-wise interpolation of matrix keys (MSBVH paper §3.3). Between
// two equal keys the result is that key exactly (a * (1 - t) + a * t may
// differ from a in the last bit): an instance that holds still, or one of
// identity keys, leaves the ray as it is.
constexpr Affine3f lerp(const Affine3f& a, const Affine3f& b, float t) {
  if (a.vx == b.vx && a.vy == b.vy && a.vz == b.vz && a.p == b.p) return a;
  Affine3f r;
  r.vx = lerp(a.vx, b.vx, t);
  r.vy = lerp(a.vy, b.vy, t);
  r.vz = lerp(a.vz, b.vz, t);
  r.p = lerp(a.p, b.p, t);
  return r;
}

inline Affine3f Affine3f::rotate(Vec3f axis, float radians) {
  Vec3f u = normalize(axis);
  float c = std::cos(radians), s = std::sin(radians), C = 1 - c;
  Affine3f a;
  a.vx = {u.x * u.x * C + c, u.y * u.x * C + u.z * s, u.z * u.x * C - u.y * s};
  a.vy = {u.x * u.y * C - u.z * s, u.y * u.y * C + c, u.z * u.y * C + u.x * s};
  a.vz = {u.x * u.z * C + u.y * s, u.y * u.z * C - u.x * s, u.z * u.z * C + c};
  return a;
}

inline Affine3f Affine3f::fromRowMajor4x4(const float m[16]) {
  Affine3f a;
  a.vx = {m[0], m[4], m[8]};
  a.vy = {m[1], m[5], m[9]};
  a.vz = {m[2], m[6], m[10]};
  a.p = {m[3], m[7], m[11]};
  return a;
}

inline Affine3f Affine3f::inverse() const {
  // Inverse of the linear part by the adjugate; all in double for accuracy.
  const double a00 = vx.x, a10 = vx.y, a20 = vx.z;
  const double a01 = vy.x, a11 = vy.y, a21 = vy.z;
  const double a02 = vz.x, a12 = vz.y, a22 = vz.z;
  const double c00 = a11 * a22 - a12 * a21, c01 = a02 * a21 - a01 * a22, c02 = a01 * a12 - a02 * a11;
  const double c10 = a12 * a20 - a10 * a22, c11 = a00 * a22 - a02 * a20, c12 = a02 * a10 - a00 * a12;
  const double c20 = a10 * a21 - a11 * a20, c21 = a01 * a20 - a00 * a21, c22 = a00 * a11 - a01 * a10;
  const double det = a00 * c00 + a01 * c10 + a02 * c20;
  const double inv = 1.0 / det;
  Affine3f r;
  r.vx = {float(c00 * inv), float(c10 * inv), float(c20 * inv)};
  r.vy = {float(c01 * inv), float(c11 * inv), float(c21 * inv)};
  r.vz = {float(c02 * inv), float(c12 * inv), float(c22 * inv)};
  const double px = p.x, py = p.y, pz = p.z;
  r.p = {float(-(c00 * px + c01 * py + c02 * pz) * inv), float(-(c10 * px + c11 * py + c12 * pz) * inv),
         float(-(c20 * px + c21 * py + c22 * pz) * inv)};
  return r;
}

}  // namespace mbrt
