// Disagreements of `auto` with brute that its fit tolerance allows (the
// issue's one exception): rays that pass within the tolerance of an edge of
// the hit triangle, or meet it at a t that differs by about as much.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "oracle.h"

namespace mbrt::test {

inline float distanceToSegment(Vec3f p, Vec3f a, Vec3f b) {
  const Vec3f ab = b - a;
  const float l2 = dot(ab, ab);
  const float s = l2 > 0.0f ? std::clamp(dot(p - a, ab) / l2, 0.0f, 1.0f) : 0.0f;
  return length(p - (a + ab * s));
}

struct Explained {
  size_t nearEdge = 0;   // the ray passes within the slack of a hit triangle's edge
  size_t offset = 0;     // same triangle, t differs by less than the slack
  size_t unexplained = 0;
};

// Whether hit h (a top-level triangle of the original scene) lies within
// `slack` (widened at grazing angles) of an edge of its triangle.
inline bool nearAnEdge(const Scene& scene, const Ray& ray, const Hit& h, float slack) {
  if (!h.valid() || h.instID != kInvalidId) return false;
  const Geometry& g = scene.geometry(h.geomID);
  if (g.type() != GeometryType::Triangles) return false;
  const Triangle& t = g.triangles()[h.primID];
  const Vec3f a = g.vertexAt(ray.time, t.v0), b = g.vertexAt(ray.time, t.v1), c = g.vertexAt(ray.time, t.v2);
  const Vec3f n = normalize(cross(b - a, c - a));
  const float cosine = std::fabs(dot(n, normalize(ray.dir)));
  const float s = slack / std::max(cosine, 0.05f);
  const Vec3f p = ray.org + ray.dir * h.t;
  return std::min({distanceToSegment(p, a, b), distanceToSegment(p, b, c), distanceToSegment(p, c, a)}) <= s;
}

inline Explained classifyNearEdge(const Scene& scene, const Accel& oracle, const Accel& tested, const std::vector<Ray>& rays,
                   float slack) {
  Explained e;
  for (const Ray& ray : rays) {
    Hit a, b;
    oracle.intersect(ray, a);
    tested.intersect(ray, b);
    test::OracleReport rep;
    test::recordAgreement(rep, ray, a, b, oracle.occluded(ray), tested.occluded(ray), 1e-5f);
    if (rep.wrong == 0 && rep.anyWrong == 0) continue;
    const float dirLength = length(ray.dir);
    if (a.valid() && b.valid() && a.geomID == b.geomID && a.primID == b.primID && a.instID == b.instID &&
        std::fabs(a.t - b.t) * dirLength <= 20.0f * slack)
      ++e.offset;
    else if (nearAnEdge(scene, ray, a, slack) || nearAnEdge(scene, ray, b, slack))
      ++e.nearEdge;
    else
      ++e.unexplained;
  }
  return e;
}

// The rays on which `tested` disagrees with the oracle's answers.
inline std::vector<Ray> disagreeing(const OracleAnswers& ref, const Accel& tested, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> occ(rays.size());
  tested.intersect(rays, hits);
  tested.occluded(rays, occ);
  std::vector<Ray> out;
  for (size_t i = 0; i < rays.size(); ++i) {
    OracleReport rep;
    recordAgreement(rep, rays[i], ref.hits[i], hits[i], bool(ref.occluded[i]), bool(occ[i]), 1e-5f);
    if (rep.wrong + rep.anyWrong > 0) out.push_back(rays[i]);
  }
  return out;
}

}  // namespace mbrt::test
