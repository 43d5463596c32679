// An LD_PRELOAD library, for both the real libembree3 and mbrt's, that
// leaves out of a program's scenes the geometry types mbrt does not have
// (user geometry, subdivision surfaces, curves, points, grids), so that
// the rest of a tutorial drawing them all (motion_blur_geometry) can be
// compared: each such geometry becomes an empty triangle mesh (its id
// stays the same) and the calls that set it up do nothing.
#include <dlfcn.h>
#include <embree3/rtcore.h>

#include <cstdlib>
#include <mutex>
#include <set>

namespace {

std::mutex gMutex;
std::set<RTCGeometry> gDropped;

bool dropped(RTCGeometry g) {
  std::lock_guard<std::mutex> lock(gMutex);
  return gDropped.count(g) != 0;
}

template <class F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

RTCGeometry rtcNewGeometry(RTCDevice device, RTCGeometryType type) {
  static const auto real = next<decltype(&rtcNewGeometry)>("rtcNewGeometry");
  if (type == RTC_GEOMETRY_TYPE_TRIANGLE || type == RTC_GEOMETRY_TYPE_QUAD || type == RTC_GEOMETRY_TYPE_INSTANCE)
    return real(device, type);
  RTCGeometry g = real(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  std::lock_guard<std::mutex> lock(gMutex);
  gDropped.insert(g);
  return g;
}

void rtcReleaseGeometry(RTCGeometry g) {
  static const auto real = next<decltype(&rtcReleaseGeometry)>("rtcReleaseGeometry");
  real(g);  // the handle may be reused once freed; attached geometries stay alive meanwhile
}

void* rtcSetNewGeometryBuffer(RTCGeometry g, RTCBufferType type, unsigned slot, RTCFormat format, size_t stride,
                              size_t count) {
  static const auto real = next<decltype(&rtcSetNewGeometryBuffer)>("rtcSetNewGeometryBuffer");
  if (dropped(g)) return std::calloc(count + 1, stride + 16);  // written by the program, never read
  return real(g, type, slot, format, stride, count);
}

void rtcSetSharedGeometryBuffer(RTCGeometry g, RTCBufferType type, unsigned slot, RTCFormat format, const void* ptr,
                                size_t offset, size_t stride, size_t count) {
  static const auto real = next<decltype(&rtcSetSharedGeometryBuffer)>("rtcSetSharedGeometryBuffer");
  if (!dropped(g)) real(g, type, slot, format, ptr, offset, stride, count);
}

#define MBRT_DROPPED_NOOP(name, ...)                              \
  void name(RTCGeometry g, __VA_ARGS__) {                         \
    static const auto real = next<decltype(&name)>(#name);        \
    if (!dropped(g)) real(g, MBRT_DROPPED_ARGS);                  \
  }

#define MBRT_DROPPED_ARGS a
MBRT_DROPPED_NOOP(rtcSetGeometryTessellationRate, float a)
MBRT_DROPPED_NOOP(rtcSetGeometryUserPrimitiveCount, unsigned a)
MBRT_DROPPED_NOOP(rtcSetGeometryIntersectFunction, RTCIntersectFunctionN a)
MBRT_DROPPED_NOOP(rtcSetGeometryOccludedFunction, RTCOccludedFunctionN a)
MBRT_DROPPED_NOOP(rtcSetGeometryTopologyCount, unsigned a)
MBRT_DROPPED_NOOP(rtcSetGeometryDisplacementFunction, RTCDisplacementFunctionN a)
MBRT_DROPPED_NOOP(rtcSetGeometryVertexAttributeCount, unsigned a)
#undef MBRT_DROPPED_ARGS
#define MBRT_DROPPED_ARGS a, b
MBRT_DROPPED_NOOP(rtcSetGeometryBoundsFunction, RTCBoundsFunction a, void* b)
MBRT_DROPPED_NOOP(rtcSetGeometrySubdivisionMode, unsigned a, RTCSubdivisionMode b)
MBRT_DROPPED_NOOP(rtcSetGeometryVertexAttributeTopology, unsigned a, unsigned b)
#undef MBRT_DROPPED_ARGS

}  // extern "C"
