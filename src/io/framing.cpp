// The camera for inputs without one: outside the scene's bounds looking
// along -z (frameBox), or, when the scene is a closed room seen from its
// centre (walls all around facing inwards, a floor below), from inside it:
// from outside such a scene shows only its outer wall.
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>

#include "mbrt/io/loaders.h"
#include "mbrt/scenes.h"

namespace mbrt {
namespace {

constexpr int kAround = 16;                   // horizontal probe rays from the centre
constexpr size_t kMaxProbeTriangles = 8u << 20;  // beyond: framed from outside, unprobed

struct Probe {
  Vec3f org, dir;
  float t = kInf;
  bool frontFacing = false;  // the nearest hit's winding faces the ray's origin
};

// Every triangle at its first step, in world space (instances at their first key).
void forEachTriangle(const Scene& scene, const Affine3f& xf, int depth,
                     const std::function<void(Vec3f, Vec3f, Vec3f)>& fn) {
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Triangles) {
      const VertexBuffer& vb = g.vertices(0);
      for (const Triangle& t : g.triangles()) fn(xf.xfmPoint(vb[t.v0]), xf.xfmPoint(vb[t.v1]), xf.xfmPoint(vb[t.v2]));
    } else if (g.type() == GeometryType::Instance && depth < 8 && g.instancedScene() && !g.transforms().empty()) {
      forEachTriangle(*g.instancedScene(), xf * g.transforms()[0], depth + 1, fn);
    }
  }
}

size_t countTriangles(const Scene& scene, int depth) {
  size_t n = 0;
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Triangles) n += g.numPrimitives();
    else if (g.type() == GeometryType::Instance && depth < 8 && g.instancedScene())
      n += countTriangles(*g.instancedScene(), depth + 1);
  }
  return n;
}

// Nearest hits of the probes, double-sided (Moller-Trumbore), in one pass
// over the triangles.
void trace(const Scene& scene, std::vector<Probe>& probes) {
  Affine3f identity;
  forEachTriangle(scene, identity, 0, [&](Vec3f a, Vec3f b, Vec3f c) {
    const Vec3f e1 = b - a, e2 = c - a, ng = cross(e1, e2);
    for (Probe& p : probes) {
      const Vec3f pv = cross(p.dir, e2);
      const float det = dot(e1, pv);
      if (!(std::fabs(det) > 0.0f)) continue;
      const float inv = 1.0f / det;
      const Vec3f tv = p.org - a;
      const float u = dot(tv, pv) * inv;
      if (u < 0.0f || u > 1.0f) continue;
      const Vec3f qv = cross(tv, e1);
      const float v = dot(p.dir, qv) * inv;
      if (v < 0.0f || u + v > 1.0f) continue;
      const float t = dot(e2, qv) * inv;
      if (t > 0.0f && t < p.t) {
        p.t = t;
        p.frontFacing = dot(ng, p.dir) < 0.0f;
      }
    }
  });
}

// How far the ray from inside the box travels to its boundary.
float toBoundary(const Box3f& box, Vec3f org, Vec3f dir) {
  float t = kInf;
  for (int k = 0; k < 3; ++k) {
    if (dir[k] > 0.0f) t = std::min(t, (box.upper[k] - org[k]) / dir[k]);
    if (dir[k] < 0.0f) t = std::min(t, (box.lower[k] - org[k]) / dir[k]);
  }
  return t;
}

// A view from inside when the scene is a room around its centre (y up).
std::optional<CameraSpec> viewFromInside(const Scene& scene, const Box3f& box) {
  if (countTriangles(scene, 0) > kMaxProbeTriangles) return std::nullopt;
  const Vec3f c = box.center();
  std::vector<Probe> probes;
  for (int i = 0; i < kAround; ++i) {
    const float a = 2.0f * 3.14159265f * (float(i) + 0.5f) / float(kAround);
    probes.push_back({c, {std::cos(a), 0.0f, std::sin(a)}});
  }
  probes.push_back({c, {0.0f, -1.0f, 0.0f}});
  trace(scene, probes);
  const Probe& down = probes.back();
  if (!(down.t < kInf) || !down.frontFacing) return std::nullopt;  // no floor seen from above
  int facing = 0;
  std::vector<float> hitFraction;
  for (int i = 0; i < kAround; ++i) {
    const Probe& p = probes[size_t(i)];
    if (!(p.t < kInf)) return std::nullopt;  // open to a side
    facing += p.frontFacing;
    hitFraction.push_back(p.t / toBoundary(box, p.org, p.dir));
  }
  std::nth_element(hitFraction.begin(), hitFraction.begin() + kAround / 2, hitFraction.end());
  // Walls facing inwards, and mostly far from the centre: a room, not the inside of a solid.
  if (facing < kAround * 3 / 4 || hitFraction[kAround / 2] < 0.3f) return std::nullopt;

  // On the longer horizontal axis, a quarter of the way up from the floor,
  // looking along the axis, a little more than halfway from the centre to
  // the wall behind (nearer to it, the arches of a room's end fill the view).
  const Vec3f size = box.size();
  const Vec3f axis = size.x >= size.z ? Vec3f{1, 0, 0} : Vec3f{0, 0, 1};
  const float floorY = c.y - down.t;
  const Vec3f start{c.x, floorY + 0.25f * (box.upper.y - floorY), c.z};
  std::vector<Probe> back{{start, -axis}};
  trace(scene, back);
  const float room = back[0].t < kInf ? back[0].t : toBoundary(box, start, -axis);
  CameraSpec cam;
  cam.eye = start - axis * (0.55f * room);
  cam.target = start + axis * room + Vec3f{0.0f, 0.15f * room, 0.0f};
  cam.up = {0, 1, 0};
  cam.verticalFovDegrees = 60.0f;
  return cam;
}

}  // namespace

CameraSpec frameScene(const Scene& scene) {
  const Box3f box = sceneBounds(scene);
  if (box.empty() || !isFinite(box.lower) || !isFinite(box.upper)) return frameBox(box);
  if (const std::optional<CameraSpec> inside = viewFromInside(scene, box)) return *inside;
  return frameBox(box);
}

}  // namespace mbrt
