// Rays with a time and the hits they return.
#pragma once

#include <cstdint>

#include "mbrt/math.h"

namespace mbrt {

constexpr uint32_t kInvalidId = 0xFFFFFFFFu;

// A ray segment [tnear, tfar] along org + t*dir, at shutter time `time` in
// [0,1]. Only geometries whose mask shares a bit with `mask` are hit.
// Rays with NaN/inf components, zero direction, time outside [0,1] or NaN, or
// tnear > tfar are invalid: they miss and are counted in the statistics.
// The direction need not be normalized, and any finite scale works (1e-45
// to 3e38): every structure traces the ray as if its direction were scaled
// by a power of two, 2^k, so that its largest component is in [1, 2), with
// tnear, tfar scaled by 2^-k and the hit's t scaled back by 2^k. Powers of
// two keep this exact, except that tnear / tfar (or a hit's t) that become
// smaller than the smallest normal float round to denormals. A hit is
// reported only where its t is a finite float: with a very short direction
// (a denormal one, say) a hit farther than ~3.4e38 in t is a miss.
struct Ray {
  Vec3f org;
  float tnear = 0.0f;
  Vec3f dir;
  float tfar = kInf;
  float time = 0.0f;
  uint32_t mask = 0xFFFFFFFFu;
};

// Closest hit. geomID == kInvalidId on a miss. For a hit inside an instance,
// geomID/primID name the primitive in the instanced scene and instID is the
// geometry id of the (outermost) instance in the scene that was traced;
// instID == kInvalidId otherwise. Ng is the unnormalized geometric normal in
// world space (for triangles: (v1-v0) x (v2-v0) at the ray's time).
struct Hit {
  float t = kInf;
  float u = 0.0f, v = 0.0f;  // triangle barycentrics of v1, v2; segments: u along the segment
  Vec3f Ng;
  uint32_t geomID = kInvalidId;
  uint32_t primID = kInvalidId;
  uint32_t instID = kInvalidId;

  bool valid() const { return geomID != kInvalidId; }
};

// True when the ray is well formed (see Ray).
bool isValidRay(const Ray& ray);

}  // namespace mbrt
