// One record of a ray log (raylog.cpp): the call, the ray as given, and
// the ray and hit as the library returned them.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>

namespace mbrt::embree_test {

struct RayRecord {
  uint32_t call;  // 0: rtcIntersect1(M), 1: rtcOccluded1(M)
  RTCRay in;
  RTCRayHit out;
};

}  // namespace mbrt::embree_test
