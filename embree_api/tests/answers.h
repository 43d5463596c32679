// Comparing Embree API answers: the same hit up to rounding (same ids, t,
// u/v, Ng in sign and scale), and the float64 reference's verdict on an
// answer where two sides differ.
#pragma once

#include <cmath>
#include <string>

#include "reference64.h"
#include "test_world.h"

namespace mbrt::embree_test {

inline Ray toMbrtRay(const TestRay& r) {
  Ray m;
  m.org = r.org;
  m.dir = r.dir;
  m.tnear = r.tnear;
  m.tfar = r.tfar;
  m.time = r.time;
  m.mask = r.mask;
  return m;
}

inline bool closeTo(Vec3f a, Vec3f b, float rel) {
  const float scale = std::max(length(a), length(b));
  return length(a - b) <= rel * scale;
}

// Same closest hit and occlusion up to float rounding; `why` says where not.
inline bool sameAnswer(const TestAnswer& a, const TestAnswer& b, std::string& why) {
  if (a.occluded != b.occluded) return why = "occlusion differs", false;
  if (a.hit != b.hit) return why = a.hit ? "second side misses" : "first side misses", false;
  if (!a.hit) return true;
  if (a.geomID != b.geomID || a.primID != b.primID || a.instID != b.instID)
    return why = "different primitive (geom " + std::to_string(a.geomID) + "/" + std::to_string(b.geomID) +
                 ", prim " + std::to_string(a.primID) + "/" + std::to_string(b.primID) + ", inst " +
                 std::to_string(a.instID) + "/" + std::to_string(b.instID) + ")",
           false;
  if (std::fabs(a.t - b.t) > 1e-4f * std::max(1.0f, std::fabs(a.t))) return why = "t differs", false;
  if (std::fabs(a.u - b.u) > 2e-3f || std::fabs(a.v - b.v) > 2e-3f) return why = "u/v differ", false;
  if (!closeTo(a.Ng, b.Ng, 1e-3f)) return why = "Ng differs", false;
  return true;
}

// The reference's verdict on one side's answer (closest hit and occlusion).
inline bool referenceAccepts(const ref::Reference& reference, const TestWorld& world, const TestRay& ray,
                             const TestAnswer& a, std::string& why) {
  const Ray r = toMbrtRay(ray);
  const Hit h = toMbrtHit(world, a);
  ref::Verdict closest, any;
  reference.judge(r, &h, &a.occluded, closest, any);
  if (!closest.ok) why = closest.why;
  if (!any.ok) why += " (occlusion) " + any.why;
  return closest.ok && any.ok;
}

}  // namespace mbrt::embree_test
