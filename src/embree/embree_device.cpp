// The Embree device: memory monitor, error handler and the shared filter.
#include "embree/embree_device.h"

#include "mbrt/ray.h"

namespace mbrt::detail {
namespace {

// Keeps the current and peak bytes; fails allocations over the build's limit.
bool memoryMonitor(void* user, ssize_t bytes, bool /*post*/) {
  Device& d = *static_cast<Device*>(user);
  const long long now = d.current.fetch_add(bytes) + bytes;
  const long long limit = d.limit.load();
  if (bytes > 0 && limit > 0 && now - d.base.load() > limit) {
    d.current.fetch_sub(bytes);
    return false;  // Embree fails the operation with RTC_ERROR_OUT_OF_MEMORY
  }
  long long peak = d.peak.load();
  while (now > peak && !d.peak.compare_exchange_weak(peak, now)) {
  }
  return true;
}

void errorHandler(void* user, RTCError code, const char* message) {
  Device& d = *static_cast<Device*>(user);
  std::lock_guard<std::mutex> lock(d.errorMutex);
  d.lastError = "Embree error " + std::to_string(int(code)) + (message ? std::string(": ") + message : "");
}

}  // namespace

std::atomic<bool> gForceFilterMasks{false};

Device& device() {
  static Device* d = [] {
    auto* dev = new Device();  // never freed: Embree may be used until exit
    dev->device = rtcNewDevice(nullptr);
    if (!dev->device) throw Error("could not create the Embree device");
    rtcSetDeviceErrorFunction(dev->device, errorHandler, dev);
    rtcSetDeviceMemoryMonitorFunction(dev->device, memoryMonitor, dev);
    dev->rayMask = rtcGetDeviceProperty(dev->device, RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED) != 0;
    return dev;
  }();
  return *d;
}

void filterFunction(const RTCFilterFunctionNArguments* args) {
  const auto* g = static_cast<const Geometry*>(args->geometryUserPtr);
  const auto* ctx = reinterpret_cast<const TraceContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    RTCRayN* r = args->ray;
    RTCHitN* h = args->hit;
    const unsigned N = args->N;
    if (ctx->filterMasks) {
      bool visible = (g->mask() & ctx->mask) != 0;
      const unsigned inst = RTCHitN_instID(h, N, i, 0);
      if (visible && inst != RTC_INVALID_GEOMETRY_ID) visible = (ctx->root->geometry(inst).mask() & ctx->mask) != 0;
      if (!visible) {
        args->valid[i] = 0;
        continue;
      }
    }
    if (!g->hasFilter()) continue;
    Ray ray;
    ray.org = {RTCRayN_org_x(r, N, i), RTCRayN_org_y(r, N, i), RTCRayN_org_z(r, N, i)};
    ray.dir = {RTCRayN_dir_x(r, N, i), RTCRayN_dir_y(r, N, i), RTCRayN_dir_z(r, N, i)};
    ray.tnear = RTCRayN_tnear(r, N, i);
    ray.tfar = RTCRayN_tfar(r, N, i);
    ray.time = RTCRayN_time(r, N, i);
    ray.mask = ctx->mask;
    if (ctx->shift != 0.0f) {  // the filter sees the ray as given, not as moved for Embree
      ray.org = ray.org - ray.dir * ctx->shift;
      ray.tnear += ctx->shift;
      ray.tfar += ctx->shift;
    }
    Hit hit;
    hit.t = ray.tfar;
    hit.u = RTCHitN_u(h, N, i);
    hit.v = RTCHitN_v(h, N, i);
    hit.Ng = {RTCHitN_Ng_x(h, N, i), RTCHitN_Ng_y(h, N, i), RTCHitN_Ng_z(h, N, i)};
    hit.geomID = RTCHitN_geomID(h, N, i);
    hit.primID = RTCHitN_primID(h, N, i);
    hit.instID = kInvalidId;
    if (!g->filter()(FilterArgs{ray, hit, g->userData()})) args->valid[i] = 0;
  }
}

}  // namespace mbrt::detail
