#include "scenes/mesh_builders.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mbrt::scenes {
namespace {
constexpr float kPi = std::numbers::pi_v<float>;
}

void MeshData::append(const MeshData& other) {
  const uint32_t base = uint32_t(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  triangles.reserve(triangles.size() + other.triangles.size());
  for (const Triangle& t : other.triangles) triangles.push_back({t.v0 + base, t.v1 + base, t.v2 + base});
}

MeshData makeSphere(int around, int rings, const RadiusFn& radius, Vec3f center) {
  around = std::max(around, 3);
  rings = std::max(rings, 2);
  MeshData m;
  m.vertices.reserve(size_t(around) * (rings - 1) + 2);
  auto put = [&](Vec3f dir) { m.vertices.push_back(center + dir * radius(dir)); };
  put({0, 1, 0});  // north pole: vertex 0
  for (int r = 1; r < rings; ++r) {
    const float theta = kPi * float(r) / float(rings);
    const float st = std::sin(theta), ct = std::cos(theta);
    for (int a = 0; a < around; ++a) {
      const float phi = 2.0f * kPi * float(a) / float(around);
      put({st * std::cos(phi), ct, st * std::sin(phi)});
    }
  }
  put({0, -1, 0});  // south pole: last vertex
  const uint32_t south = uint32_t(m.vertices.size() - 1);
  auto ring = [&](int r, int a) { return uint32_t(1 + (r - 1) * around + (a % around)); };
  m.triangles.reserve(size_t(2) * around * (rings - 1));
  for (int a = 0; a < around; ++a) m.triangles.push_back({0, ring(1, a + 1), ring(1, a)});
  for (int r = 1; r + 1 < rings; ++r)
    for (int a = 0; a < around; ++a) {
      const uint32_t p = ring(r, a), q = ring(r, a + 1), s = ring(r + 1, a), t = ring(r + 1, a + 1);
      m.triangles.push_back({p, q, t});
      m.triangles.push_back({p, t, s});
    }
  for (int a = 0; a < around; ++a) m.triangles.push_back({south, ring(rings - 1, a), ring(rings - 1, a + 1)});
  return m;
}

void sphereResolution(size_t triangles, int& around, int& rings) {
  // around = 2*(rings-1) gives roughly square quads: 4*(rings-1)^2 triangles.
  const int m = std::max(2, int(std::lround(std::sqrt(double(triangles) / 4.0))));
  rings = m + 1;
  around = std::max(3, int(std::lround(double(triangles) / (2.0 * m))));
}

MeshData makeSphere(size_t triangles, const RadiusFn& radius, Vec3f center) {
  int around, rings;
  sphereResolution(triangles, around, rings);
  return makeSphere(around, rings, radius, center);
}

MeshData makeGrid(int nx, int nz, float sx, float sz) {
  nx = std::max(nx, 1);
  nz = std::max(nz, 1);
  MeshData m;
  m.vertices.reserve(size_t(nx + 1) * (nz + 1));
  for (int j = 0; j <= nz; ++j)
    for (int i = 0; i <= nx; ++i)
      m.vertices.push_back({sx * (float(i) / float(nx) - 0.5f), 0.0f, sz * (float(j) / float(nz) - 0.5f)});
  m.triangles.reserve(size_t(2) * nx * nz);
  const uint32_t row = uint32_t(nx + 1);
  for (int j = 0; j < nz; ++j)
    for (int i = 0; i < nx; ++i) {
      const uint32_t p = uint32_t(j) * row + uint32_t(i);
      m.triangles.push_back({p, p + row, p + 1});
      m.triangles.push_back({p + 1, p + row, p + row + 1});
    }
  return m;
}

Vec3f anyPerpendicular(Vec3f n) {
  const Vec3f h = std::fabs(n.x) < 0.6f ? Vec3f{1, 0, 0} : Vec3f{0, 1, 0};
  return normalize(cross(n, h));
}

MeshData makeCylinder(int around, int along, Vec3f a, Vec3f b, float ra, float rb) {
  around = std::max(around, 3);
  along = std::max(along, 1);
  const Vec3f axis = normalize(b - a);
  const Vec3f u = anyPerpendicular(axis), v = cross(axis, u);
  MeshData m;
  m.vertices.reserve(size_t(around) * (along + 1) + 2);
  for (int k = 0; k <= along; ++k) {
    const float s = float(k) / float(along);
    const Vec3f c = lerp(a, b, s);
    const float r = ra + (rb - ra) * s;
    for (int i = 0; i < around; ++i) {
      const float phi = 2.0f * kPi * float(i) / float(around);
      m.vertices.push_back(c + (u * std::cos(phi) + v * std::sin(phi)) * r);
    }
  }
  const uint32_t ca = uint32_t(m.vertices.size());
  m.vertices.push_back(a);
  m.vertices.push_back(b);
  auto idx = [&](int k, int i) { return uint32_t(k * around + (i % around)); };
  m.triangles.reserve(size_t(2) * around * along + 2 * size_t(around));
  for (int k = 0; k < along; ++k)
    for (int i = 0; i < around; ++i) {
      const uint32_t p = idx(k, i), q = idx(k, i + 1), s = idx(k + 1, i), t = idx(k + 1, i + 1);
      m.triangles.push_back({p, q, t});
      m.triangles.push_back({p, t, s});
    }
  for (int i = 0; i < around; ++i) {
    m.triangles.push_back({ca, idx(0, i + 1), idx(0, i)});
    m.triangles.push_back({ca + 1, idx(along, i), idx(along, i + 1)});
  }
  return m;
}

MeshData makeCylinder(size_t triangles, Vec3f a, Vec3f b, float ra, float rb) {
  // around ~ 2*along*(mean circumference / length) would be "square"; keep it
  // simple: choose along so that 2*around*(along+1) ~ triangles with around ~ 2*along.
  const int along = std::max(1, int(std::lround(std::sqrt(double(triangles) / 4.0))) - 1);
  const int around = std::max(3, int(std::lround(double(triangles) / (2.0 * (along + 1)))));
  return makeCylinder(around, along, a, b, ra, rb);
}

MeshData makeTorus(int around, int tube, float majorRadius, float minorRadius) {
  around = std::max(around, 3);
  tube = std::max(tube, 3);
  MeshData m;
  m.vertices.reserve(size_t(around) * tube);
  for (int i = 0; i < around; ++i) {
    const float phi = 2.0f * kPi * float(i) / float(around);
    const Vec3f radial{std::cos(phi), 0.0f, std::sin(phi)};
    for (int j = 0; j < tube; ++j) {
      const float psi = 2.0f * kPi * float(j) / float(tube);
      m.vertices.push_back(radial * (majorRadius + minorRadius * std::cos(psi)) +
                           Vec3f{0, minorRadius * std::sin(psi), 0});
    }
  }
  auto idx = [&](int i, int j) { return uint32_t((i % around) * tube + (j % tube)); };
  m.triangles.reserve(size_t(2) * around * tube);
  for (int i = 0; i < around; ++i)
    for (int j = 0; j < tube; ++j) {
      const uint32_t p = idx(i, j), q = idx(i + 1, j), s = idx(i, j + 1), t = idx(i + 1, j + 1);
      m.triangles.push_back({p, s, t});
      m.triangles.push_back({p, t, q});
    }
  return m;
}

MeshData makeTorus(size_t triangles, float majorRadius, float minorRadius) {
  const int tube = std::max(3, int(std::lround(std::sqrt(double(triangles) / 4.0))));
  const int around = std::max(3, int(std::lround(double(triangles) / (2.0 * tube))));
  return makeTorus(around, tube, majorRadius, minorRadius);
}

void appendRibbon(MeshData& mesh, std::span<const Vec3f> polyline, Vec3f normalHint, float width) {
  const size_t n = polyline.size();
  if (n < 2) return;
  const uint32_t base = uint32_t(mesh.vertices.size());
  Vec3f lastSide = anyPerpendicular(normalize(polyline[1] - polyline[0]));
  for (size_t i = 0; i < n; ++i) {
    const Vec3f t = polyline[std::min(i + 1, n - 1)] - polyline[i == 0 ? 0 : i - 1];
    Vec3f side = cross(t, normalHint);
    const float len = length(side);
    side = len > 1e-12f ? side * (1.0f / len) : lastSide;
    if (dot(side, lastSide) < 0.0f) side = -side;  // no twist flips
    lastSide = side;
    mesh.vertices.push_back(polyline[i] - side * (0.5f * width));
    mesh.vertices.push_back(polyline[i] + side * (0.5f * width));
  }
  for (uint32_t i = 0; i + 1 < n; ++i) {
    const uint32_t p = base + 2 * i;
    mesh.triangles.push_back({p, p + 1, p + 2});
    mesh.triangles.push_back({p + 1, p + 3, p + 2});
  }
}

float BlobShape::operator()(Vec3f dir) const {
  float r = base;
  for (const Lobe& l : lobes) r += l.amplitude * std::exp(l.sharpness * (dot(dir, l.axis) - 1.0f));
  return r;
}

void BlobShape::addRandomLobes(Rng& rng, int count, float ampLo, float ampHi, float sharpLo, float sharpHi) {
  for (int i = 0; i < count; ++i) {
    Lobe l;
    l.axis = rng.unitVector();
    l.amplitude = rng.uniform(ampLo, ampHi);
    l.sharpness = rng.uniform(sharpLo, sharpHi);
    lobes.push_back(l);
  }
}

std::vector<Vec3f> transformed(std::span<const Vec3f> v, const Affine3f& m) {
  std::vector<Vec3f> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = m.xfmPoint(v[i]);
  return out;
}

void transformInPlace(std::span<Vec3f> v, const Affine3f& m) {
  for (Vec3f& p : v) p = m.xfmPoint(p);
}

Box3f boundsOf(std::span<const Vec3f> v) {
  Box3f b;
  for (const Vec3f& p : v) b.extend(p);
  return b;
}

Affine3f rotateAbout(Vec3f pivot, Vec3f axis, float radians) {
  return Affine3f::translate(pivot) * Affine3f::rotate(axis, radians) * Affine3f::translate(-pivot);
}

float smoothstep(float e0, float e1, float x) {
  const float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

size_t scaledCount(double size, double base, size_t minimum) {
  return std::max(minimum, size_t(std::llround(base * size)));
}

}  // namespace mbrt::scenes
