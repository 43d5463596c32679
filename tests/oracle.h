// The oracle check shared by all structure tests: a structure must give the
// same closest hit as `brute` (same primitive, or a tie: same t within a
// small relative tolerance) and the same any-hit answer. A missed hit is a
// failure, never a tie.
#pragma once

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/scenes.h"

namespace mbrt::test {

struct OracleReport {
  size_t rays = 0;
  size_t hits = 0;
  size_t ties = 0;
  size_t wrong = 0;     // different primitive at a different t, or hit/miss disagreement
  size_t anyWrong = 0;  // occluded() disagreements
  std::string firstFailure;
};

// Adds one ray's closest hits (oracle `a`, tested `b`) and any-hit answers to
// `rep`. Ties (another primitive at the same t, e.g. on a shared edge) agree.
inline void recordAgreement(OracleReport& rep, const Ray& ray, const Hit& a, const Hit& b, bool occludedA,
                            bool occludedB, float tolerance) {
  const bool ha = a.valid(), hb = b.valid();
  ++rep.rays;
  rep.hits += ha ? 1 : 0;
  bool ok = ha == hb;
  if (ok && ha && (a.geomID != b.geomID || a.primID != b.primID || a.instID != b.instID)) {
    const bool tie = std::fabs(a.t - b.t) <= std::max(1e-4f, tolerance) * std::max(1.0f, std::fabs(a.t));
    rep.ties += tie ? 1 : 0;
    ok = tie;
  } else if (ok && ha) {
    ok = std::fabs(a.t - b.t) <= tolerance * std::max(1.0f, std::fabs(a.t));
  }
  if (!ok) {
    if (rep.wrong == 0) {
      rep.firstFailure = "ray org (" + std::to_string(ray.org.x) + "," + std::to_string(ray.org.y) + "," +
                         std::to_string(ray.org.z) + ") dir (" + std::to_string(ray.dir.x) + "," +
                         std::to_string(ray.dir.y) + "," + std::to_string(ray.dir.z) + ") time " +
                         std::to_string(ray.time) + ": oracle " + (ha ? "hit" : "miss") + " g" +
                         std::to_string(a.geomID) + " p" + std::to_string(a.primID) + " t " + std::to_string(a.t) +
                         ", tested " + (hb ? "hit" : "miss") + " g" + std::to_string(b.geomID) + " p" +
                         std::to_string(b.primID) + " t " + std::to_string(b.t);
    }
    ++rep.wrong;
  }
  if (occludedA != occludedB) ++rep.anyWrong;
}

// The oracle: brute force over `scene`.
inline std::unique_ptr<Accel> buildBrute(const Scene& scene) {
  BuildOptions o;
  o.kind = AccelKind::Brute;
  return Accel::build(scene, o);
}

// `tolerance`: relative difference of t allowed for the same primitive and for
// ties. mbrt's structures share the oracle's leaf test, so only traversal
// order differs (1e-5); Embree evaluates vertices and triangles with its own
// arithmetic and needs more (2e-4).
inline OracleReport compareWithOracle(const Accel& oracle, const Accel& tested, const std::vector<Ray>& rays,
                                      float tolerance = 1e-5f) {
  OracleReport rep;
  for (const Ray& ray : rays) {
    Hit a, b;
    oracle.intersect(ray, a);
    tested.intersect(ray, b);
    recordAgreement(rep, ray, a, b, oracle.occluded(ray), tested.occluded(ray), tolerance);
  }
  return rep;
}

// compareWithOracle of `rays` with every ray's mask set to `mask`.
inline OracleReport compareMasked(const Accel& oracle, const Accel& tested, std::vector<Ray> rays, uint32_t mask) {
  for (Ray& r : rays) r.mask = mask;
  return compareWithOracle(oracle, tested, rays);
}

// Every time at which some geometry of the scene (or of an instanced scene)
// has a step or a range end, plus 0 and 1.
inline void collectStepTimes(const Scene& scene, std::vector<float>& times) {
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    for (uint32_t k = 0; k < g.numSteps(); ++k) times.push_back(g.stepTime(k));
    times.push_back(g.timeRange().lo);
    times.push_back(g.timeRange().hi);
    if (g.type() == GeometryType::Instance) collectStepTimes(*g.instancedScene(), times);
  }
}

inline std::vector<float> stepTimes(const Scene& scene) {
  std::vector<float> times = {0.0f, 1.0f};
  collectStepTimes(scene, times);
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

// A random point on a random triangle or segment of the scene's top level at
// `time` (false when it has none alive then).
inline bool randomSurfacePoint(const Scene& scene, float time, std::mt19937& rng, Vec3f& point) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int attempt = 0; attempt < 16; ++attempt) {
    const uint32_t id = std::min(scene.numGeometries() - 1, uint32_t(u(rng) * scene.numGeometries()));
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Instance || g.numPrimitives() == 0 || !g.timeRange().contains(time)) continue;
    const uint32_t p = std::min(g.numPrimitives() - 1, uint32_t(u(rng) * g.numPrimitives()));
    if (g.type() == GeometryType::Triangles) {
      const Triangle& t = g.triangles()[p];
      float a = u(rng), b = u(rng);
      if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
      const Vec3f v0 = g.vertexAt(time, t.v0), v1 = g.vertexAt(time, t.v1), v2 = g.vertexAt(time, t.v2);
      point = v0 + (v1 - v0) * a + (v2 - v0) * b;
    } else {
      const Segment& s = g.segments()[p];
      point = lerp(g.vertexAt(time, s.v0), g.vertexAt(time, s.v1), u(rng));
    }
    return true;
  }
  return false;
}

// Rays at random times and at every step time: half from the scene's camera
// through random pixels, half aimed at random points on primitives (a
// quarter of all start inside the scene).
// With fixedTime >= 0, all rays are at that time instead.
inline std::vector<Ray> oracleRays(const ProceduralScene& ps, size_t randomTimeRays, size_t raysPerStepTime,
                                   uint64_t seed, float fixedTime = -1.0f) {
  std::mt19937 rng(uint32_t(seed * 2654435761u + 1));
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  const CameraSpec& c = ps.camera;
  const Vec3f fwd = normalize(c.target - c.eye);
  const Vec3f right = normalize(cross(fwd, c.up));
  const Vec3f up = cross(right, fwd);
  const float h = std::tan(c.verticalFovDegrees * 3.14159265f / 360.0f);
  const float dist = length(c.target - c.eye);
  auto makeRay = [&](float time) {
    Ray r;
    r.org = c.eye;
    const float x = (2 * u(rng) - 1) * h * 1.2f, y = (2 * u(rng) - 1) * h;
    r.dir = fwd + right * x + up * y;
    Vec3f target;
    if (u(rng) < 0.5f && randomSurfacePoint(*ps.scene, time, rng, target)) {
      r.org = c.eye + Vec3f{u(rng) - 0.5f, u(rng) - 0.5f, u(rng) - 0.5f} * (0.3f * dist);
      r.dir = target - r.org;
    }
    if (u(rng) < 0.25f) r.org = r.org + r.dir * (0.8f * u(rng));  // start inside the scene
    r.time = time;
    return r;
  };
  std::vector<Ray> rays;
  for (size_t i = 0; i < randomTimeRays; ++i) rays.push_back(makeRay(fixedTime >= 0.0f ? fixedTime : u(rng)));
  if (fixedTime >= 0.0f) return rays;
  for (float t : stepTimes(*ps.scene))
    for (size_t i = 0; i < raysPerStepTime; ++i) rays.push_back(makeRay(t));
  return rays;
}

}  // namespace mbrt::test

namespace mbrt::test {

// The oracle's answers for a batch of rays, computed once (in parallel) and
// compared with several structures: compareWithOracleHits applies the same
// rules as compareWithOracle.
struct OracleAnswers {
  std::vector<Hit> hits;
  std::vector<uint8_t> occluded;
};

inline OracleAnswers oracleAnswers(const Accel& oracle, const std::vector<Ray>& rays) {
  OracleAnswers a;
  a.hits.resize(rays.size());
  a.occluded.resize(rays.size());
  oracle.intersect(rays, a.hits);
  oracle.occluded(rays, a.occluded);
  return a;
}

inline OracleReport compareWithOracleHits(const OracleAnswers& ref, const Accel& tested, const std::vector<Ray>& rays,
                                          float tolerance = 1e-5f) {
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> occ(rays.size());
  tested.intersect(rays, hits);
  tested.occluded(rays, occ);
  OracleReport rep;
  for (size_t i = 0; i < rays.size(); ++i)
    recordAgreement(rep, rays[i], ref.hits[i], hits[i], bool(ref.occluded[i]), bool(occ[i]), tolerance);
  return rep;
}

}  // namespace mbrt::test
