// The process-wide Embree device of the `embree` kind (memory monitor, error
// handler) and the filter function its geometries share.
#pragma once

#include <embree3/rtcore.h>

#include <atomic>
#include <mutex>
#include <string>

#include "mbrt/scene.h"

namespace mbrt::detail {

// The device and what its callbacks record (bytes, the last error).
struct Device {
  RTCDevice device = nullptr;
  bool rayMask = false;
  std::atomic<long long> current{0};
  std::atomic<long long> peak{0};
  std::atomic<long long> base{0};   // memory at the start of the current build
  std::atomic<long long> limit{0};  // growth allowed during the current build; 0 = unlimited
  std::mutex buildMutex;
  std::mutex errorMutex;
  std::string lastError;
};

// Tests: geometry masks in filter functions even with Embree's ray masks.
extern std::atomic<bool> gForceFilterMasks;

// The process-wide device, created on first use (thread-safe static).
Device& device();

// What we pass to rtcIntersect1/rtcOccluded1: Embree hands it to filters.
struct TraceContext {
  RTCIntersectContext embree;
  const Scene* root;
  uint32_t mask;
  bool filterMasks;
  float shift;  // embree_ray.h: Embree traces from org + shift * dir
};

// Masks (when applied in filters) and the geometry's IntersectFilter.
void filterFunction(const RTCFilterFunctionNArguments* args);

}  // namespace mbrt::detail
