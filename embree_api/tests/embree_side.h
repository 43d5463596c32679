// One build of the Embree API seen by the tests: the real libembree3 or
// mbrt's (its renamed static build, src/renames.h), behind the same
// functions, so that one process can run the same calls on both
// (embree_side.inl is compiled once for each).
#pragma once

#include <string>
#include <vector>

#include "test_world.h"

namespace mbrt::embree_test {

enum class TraceMode { Single, Packet4, Packet8, Packet16, Stream1M, Stream1Mp, StreamNM, StreamNp };
inline const char* modeName(TraceMode m) {
  const char* names[] = {"rtcIntersect1", "rtcIntersect4", "rtcIntersect8", "rtcIntersect16",
                         "rtcIntersect1M", "rtcIntersect1Mp", "rtcIntersectNM", "rtcIntersectNp"};
  return names[int(m)];
}

// What one filter call saw (the audit of filterAudit).
struct FilterCall {
  bool context = false;  // the context's filter (else the geometry's)
  uint32_t geomID = 0, primID = 0, instID = 0, contextInstID = 0;
  float tfar = 0, u = 0, v = 0;
  Vec3f Ng, org, dir;
  unsigned N = 1;
};

// One wrong call and what it reported (mistakes.inl).
struct Mistake {
  std::string what;
  RTCError deviceCode = RTC_ERROR_NONE;  // rtcGetDeviceError(device)
  RTCError threadCode = RTC_ERROR_NONE;  // rtcGetDeviceError(NULL)
  int callbacks = 0;                     // error callback calls
  std::string message;                   // the callback's last message
};

struct Side {
  const char* name;
  // A device (config string) and the world's scenes, committed; flags are
  // added to the top scene's (RTC_SCENE_FLAG_ROBUST for comparisons).
  void* (*build)(const TestWorld& world, const char* config, unsigned flags);
  void (*trace)(void* built, const std::vector<TestRay>& rays, std::vector<TestAnswer>& out, TraceMode mode);
  void (*release)(void* built);
  // Every filter call for each ray, closest hit then occlusion, in a world
  // where every mesh has a geometry filter that records and accepts and
  // the context filter records and rejects (so that every candidate along
  // the ray is seen).
  std::vector<std::vector<FilterCall>> (*filterAudit)(const TestWorld& world, const std::vector<TestRay>& rays,
                                                      TraceMode mode);
  // Wrong calls that both builds must report alike (mistakes.inl).
  std::vector<Mistake> (*mistakes)();
  // What scenarios.inl observes.
  std::vector<float> (*scenarios)();
};

const Side& realEmbree();
const Side& mbrtEmbree();

}  // namespace mbrt::embree_test
