// RTCGeometry: creation (triangle, quad and instance geometries only),
// reference counting, commit, enable/disable and the settings every type
// shares: time steps and range, mask, user data, build quality, filters.
#include "geometry.h"

#include <string>

#include "device.h"
#include "errors.h"
#include "scene.h"

namespace mbrt::embree_api {
namespace {

// The name Embree gives a geometry type mbrt does not trace; null for none.
const char* typeName(std::underlying_type_t<RTCGeometryType> type) {
  switch (type) {
    case RTC_GEOMETRY_TYPE_GRID: return "RTC_GEOMETRY_TYPE_GRID";
    case RTC_GEOMETRY_TYPE_SUBDIVISION: return "RTC_GEOMETRY_TYPE_SUBDIVISION";
    case RTC_GEOMETRY_TYPE_CONE_LINEAR_CURVE:
    case RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE:
    case RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE:
    case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BEZIER_CURVE:
    case RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE:
    case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_BSPLINE_CURVE:
    case RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE:
    case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_HERMITE_CURVE:
    case RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE:
    case RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE:
    case RTC_GEOMETRY_TYPE_NORMAL_ORIENTED_CATMULL_ROM_CURVE: return "RTC_GEOMETRY_TYPE_CURVE";
    case RTC_GEOMETRY_TYPE_SPHERE_POINT:
    case RTC_GEOMETRY_TYPE_DISC_POINT:
    case RTC_GEOMETRY_TYPE_ORIENTED_DISC_POINT: return "RTC_GEOMETRY_TYPE_POINT";
    case RTC_GEOMETRY_TYPE_USER: return "RTC_GEOMETRY_TYPE_USER";
    default: return nullptr;
  }
}

}  // namespace

Geometry::Geometry(Device* device, RTCGeometryType type) : Object(Tag::Geometry, device), type_(type) {
  vertices.resize(1);
  keys.resize(1);
}

Geometry::~Geometry() = default;

void Geometry::setTimeStepCount(uint32_t steps) {
  timeSteps_ = steps;
  if (!isInstance())
    vertices.resize(steps);
  else
    keys.resize(steps);
  changedTopology();
}

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

namespace {

Geometry& geometryOf(RTCGeometry g) { return require<Geometry>(g, "RTCGeometry"); }

}  // namespace

RTC_API RTCGeometry rtcNewGeometry(RTCDevice device, RTCGeometryType type) {
  const char* unsupported = nullptr;
  RTCGeometry made = guarded("rtcNewGeometry", device, RTCGeometry(nullptr), [&] {
    Device& d = require<Device>(device, "RTCDevice");
    const auto t = passedValue(type);
    if (t != RTC_GEOMETRY_TYPE_TRIANGLE && t != RTC_GEOMETRY_TYPE_QUAD && t != RTC_GEOMETRY_TYPE_INSTANCE) {
      unsupported = typeName(t);
      if (!unsupported) fail(RTC_ERROR_UNKNOWN, "invalid geometry type");
    }
    return reinterpret_cast<RTCGeometry>(new Geometry(&d, type));
  });
  if (unsupported) {
    // Reported as Embree reports a geometry type compiled out of it; a
    // program that goes on regardless gets an inert placeholder, not a null
    // handle to crash on (Geometry::isPlaceholder). Reported outside
    // `guarded`, so that an error callback that throws is called once.
    try {
      report(objectOf<Device>(device), RTC_ERROR_UNKNOWN,
             "rtcNewGeometry: " + std::string(unsupported) +
                 " is not supported (mbrt's Embree API has triangle, quad and instance geometries; this one is "
                 "left out of every scene)");
    } catch (...) {
      rtcReleaseGeometry(made);
      throw;
    }
  }
  return made;
}

RTC_API void rtcRetainGeometry(RTCGeometry geometry) {
  guarded("rtcRetainGeometry", geometry, [&] { geometryOf(geometry).retain(); });
}

RTC_API void rtcReleaseGeometry(RTCGeometry geometry) {
  guarded("rtcReleaseGeometry", geometry, [&] { geometryOf(geometry).release(); });
}

RTC_API void rtcCommitGeometry(RTCGeometry geometry) {
  guarded("rtcCommitGeometry", geometry, [&] {
    // The scene's next commit reads the geometry (commit.cpp); a changed
    // instance rebuilds, a changed mesh may refit.
    Geometry& g = geometryOf(geometry);
    if (g.isInstance())
      g.changedTopology();
    else
      g.changedVertices();
  });
}

RTC_API void rtcEnableGeometry(RTCGeometry geometry) {
  guarded("rtcEnableGeometry", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    g.enabled = true;
    g.changedTopology();
  });
}

RTC_API void rtcDisableGeometry(RTCGeometry geometry) {
  guarded("rtcDisableGeometry", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    g.enabled = false;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryTimeStepCount(RTCGeometry geometry, unsigned int timeStepCount) {
  guarded("rtcSetGeometryTimeStepCount", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    if (timeStepCount > RTC_MAX_TIME_STEP_COUNT) fail(RTC_ERROR_INVALID_ARGUMENT, "number of time steps is out of range");
    g.setTimeStepCount(timeStepCount);
  });
}

RTC_API void rtcSetGeometryTimeRange(RTCGeometry geometry, float startTime, float endTime) {
  guarded("rtcSetGeometryTimeRange", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    if (!(startTime <= endTime))
      fail(RTC_ERROR_INVALID_ARGUMENT, "startTime has to be smaller or equal to the endTime");
    // mbrt's geometries live inside the shutter (mbrt/scene.h: a time range
    // [lo, hi) with 0 <= lo < hi <= 1).
    if (!(startTime >= 0.0f && endTime <= 1.0f && startTime < endTime))
      fail(RTC_ERROR_INVALID_OPERATION, "time range [" + std::to_string(startTime) + ", " + std::to_string(endTime) +
                                            "] is not supported: mbrt takes non-empty time ranges inside [0, 1]");
    g.timeStart = startTime;
    g.timeEnd = endTime;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryVertexAttributeCount(RTCGeometry geometry, unsigned int count) {
  guarded("rtcSetGeometryVertexAttributeCount", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    if (g.isInstance()) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
    g.attributes.resize(count);
  });
}

RTC_API void rtcSetGeometryMask(RTCGeometry geometry, unsigned int mask) {
  guarded("rtcSetGeometryMask", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    g.mask = mask;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryBuildQuality(RTCGeometry geometry, RTCBuildQuality quality) {
  guarded("rtcSetGeometryBuildQuality", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    const auto q = passedValue(quality);
    if (q != RTC_BUILD_QUALITY_LOW && q != RTC_BUILD_QUALITY_MEDIUM && q != RTC_BUILD_QUALITY_HIGH &&
        q != RTC_BUILD_QUALITY_REFIT)
      fail(RTC_ERROR_UNKNOWN, "invalid build quality");  // Embree's code
    g.buildQuality = quality;  // mbrt's kind decides how it builds
  });
}

RTC_API void rtcSetGeometryIntersectFilterFunction(RTCGeometry geometry, RTCFilterFunctionN filter) {
  guarded("rtcSetGeometryIntersectFilterFunction", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    g.intersectFilter = filter;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryOccludedFilterFunction(RTCGeometry geometry, RTCFilterFunctionN filter) {
  guarded("rtcSetGeometryOccludedFilterFunction", geometry, [&] {
    Geometry& g = geometryOf(geometry);
    g.occludedFilter = filter;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryUserData(RTCGeometry geometry, void* ptr) {
  guarded("rtcSetGeometryUserData", geometry, [&] { geometryOf(geometry).userData = ptr; });
}

RTC_API void* rtcGetGeometryUserData(RTCGeometry geometry) {
  return guarded("rtcGetGeometryUserData", geometry, static_cast<void*>(nullptr),
                 [&] { return geometryOf(geometry).userData; });
}
