// RTCDevice: creation from the config string, reference counting,
// properties, the error code and callback, the memory monitor.
#include "device.h"

#include <atomic>
#include <cstdlib>

#include "errors.h"

namespace mbrt::embree_api {
namespace {

std::atomic<uint64_t> gNextSerial{1};

}  // namespace

Device::Device(const DeviceConfig& config)
    : Object(Tag::Device, this), verbose_(config.verbose), serial_(gNextSerial.fetch_add(1)) {
  options_.kind = config.kind;
  if (config.threads > 0) arena_ = std::make_unique<tbb::task_arena>(config.threads);
}

Device::~Device() = default;

void Device::setErrorFunction(RTCErrorFunction f, void* userPtr) {
  std::lock_guard<std::mutex> lock(mutex_);
  errorFunction_ = f;
  errorUserPtr_ = userPtr;
}

void Device::callErrorFunction(RTCError code, const char* message) {
  RTCErrorFunction f;
  void* user;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    f = errorFunction_;
    user = errorUserPtr_;
  }
  if (f) f(user, code, message);
}

void Device::setMemoryMonitor(RTCMemoryMonitorFunction f, void* userPtr) {
  std::lock_guard<std::mutex> lock(mutex_);
  memoryMonitor_ = f;
  memoryUserPtr_ = userPtr;
}

bool Device::monitorMemory(ssize_t bytes) {
  RTCMemoryMonitorFunction f;
  void* user;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    f = memoryMonitor_;
    user = memoryUserPtr_;
  }
  return !f || bytes == 0 || f(user, bytes, true);
}

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

RTC_API RTCDevice rtcNewDevice(const char* config) {
  return guarded("rtcNewDevice", nullptr, RTCDevice(nullptr), [&] {
    const DeviceConfig c = parseDeviceConfig(config, std::getenv("MBRT_EMBREE_KIND"));
    return reinterpret_cast<RTCDevice>(new Device(c));
  });
}

RTC_API void rtcRetainDevice(RTCDevice device) {
  guarded("rtcRetainDevice", device, [&] { require<Device>(device, "RTCDevice").retain(); });
}

RTC_API void rtcReleaseDevice(RTCDevice device) {
  guarded("rtcReleaseDevice", device, [&] { require<Device>(device, "RTCDevice").release(); });
}

RTC_API ssize_t rtcGetDeviceProperty(RTCDevice device, RTCDeviceProperty prop) {
  return guarded("rtcGetDeviceProperty", device, ssize_t(0), [&]() -> ssize_t {
    require<Device>(device, "RTCDevice");
    switch (prop) {
      case RTC_DEVICE_PROPERTY_VERSION: return RTC_VERSION;
      case RTC_DEVICE_PROPERTY_VERSION_MAJOR: return RTC_VERSION_MAJOR;
      case RTC_DEVICE_PROPERTY_VERSION_MINOR: return RTC_VERSION_MINOR;
      case RTC_DEVICE_PROPERTY_VERSION_PATCH: return RTC_VERSION_PATCH;
      // Packets and streams are traced ray by ray (docs/embree-api.md).
      case RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED:
      case RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED:
      case RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED:
      case RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED: return 1;
      case RTC_DEVICE_PROPERTY_BACKFACE_CULLING_CURVES_ENABLED: return 0;
      case RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED: return 1;
      case RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED: return 0;
      case RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED: return 1;
      case RTC_DEVICE_PROPERTY_IGNORE_INVALID_RAYS_ENABLED: return 0;
      case RTC_DEVICE_PROPERTY_COMPACT_POLYS_ENABLED: return 0;
      case RTC_DEVICE_PROPERTY_TRIANGLE_GEOMETRY_SUPPORTED:
      case RTC_DEVICE_PROPERTY_QUAD_GEOMETRY_SUPPORTED: return 1;
      case RTC_DEVICE_PROPERTY_SUBDIVISION_GEOMETRY_SUPPORTED:
      case RTC_DEVICE_PROPERTY_CURVE_GEOMETRY_SUPPORTED:
      case RTC_DEVICE_PROPERTY_USER_GEOMETRY_SUPPORTED:
      case RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED: return 0;
      case RTC_DEVICE_PROPERTY_TASKING_SYSTEM: return 1;  // TBB
      case RTC_DEVICE_PROPERTY_JOIN_COMMIT_SUPPORTED:
      case RTC_DEVICE_PROPERTY_PARALLEL_COMMIT_SUPPORTED: return 1;
    }
    fail(RTC_ERROR_INVALID_ARGUMENT, "unknown readable property " + std::to_string(int(prop)));
  });
}

RTC_API void rtcSetDeviceProperty(RTCDevice device, const RTCDeviceProperty prop, ssize_t) {
  guarded("rtcSetDeviceProperty", device, [&] {
    // Embree's internal debugging properties (1000000 to 1000003) need no
    // device and change nothing here; there are no other writable ones.
    if (size_t(prop) >= 1000000 && size_t(prop) < 1000004) return;
    require<Device>(device, "RTCDevice");
    fail(RTC_ERROR_INVALID_ARGUMENT, "unknown writable property " + std::to_string(int(prop)));
  });
}

RTC_API RTCError rtcGetDeviceError(RTCDevice device) {
  Device* d = objectOf<Device>(device);
  return takeError(d);
}

RTC_API void rtcSetDeviceErrorFunction(RTCDevice device, RTCErrorFunction error, void* userPtr) {
  guarded("rtcSetDeviceErrorFunction", device,
          [&] { require<Device>(device, "RTCDevice").setErrorFunction(error, userPtr); });
}

RTC_API void rtcSetDeviceMemoryMonitorFunction(RTCDevice device, RTCMemoryMonitorFunction monitor, void* userPtr) {
  guarded("rtcSetDeviceMemoryMonitorFunction", device,
          [&] { require<Device>(device, "RTCDevice").setMemoryMonitor(monitor, userPtr); });
}
