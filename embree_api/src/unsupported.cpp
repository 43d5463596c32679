// What mbrt's Embree API does not implement, reported as Embree reports
// what is not compiled into it (docs/embree-api.md): the functions of
// geometry types that rtcNewGeometry refuses (user geometry, subdivision,
// curves, points, grids) fail on the geometries that exist, with Embree's
// RTC_ERROR_INVALID_OPERATION "operation not supported for this geometry";
// point queries, collision detection and the BVH builder fail with
// RTC_ERROR_INVALID_OPERATION, the function named.
#include <string>

#include "device.h"
#include "errors.h"
#include "geometry.h"

using namespace mbrt::embree_api;

namespace {

// A setter of a geometry type this library does not have.
// A placeholder (of the type it belongs to) takes it silently.
void notForThisGeometry(const char* function, RTCGeometry geometry) {
  guarded(function, geometry, [&] {
    if (require<Geometry>(geometry, "RTCGeometry").isPlaceholder()) return;
    fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  });
}

unsigned halfEdgeQuery(const char* function, RTCGeometry geometry) {
  notForThisGeometry(function, geometry);
  return unsigned(-1);
}

// A function of a feature this library does not have.
void notSupported(const char* function, const void* handle, const char* feature) {
  guarded(function, handle, [&] {
    fail(RTC_ERROR_INVALID_OPERATION, std::string(feature) + " is not supported by mbrt's Embree API");
  });
}

}  // namespace

RTC_API void rtcSetGeometryUserPrimitiveCount(RTCGeometry geometry, unsigned int) {
  guarded("rtcSetGeometryUserPrimitiveCount", geometry, [&] {
    if (require<Geometry>(geometry, "RTCGeometry").isPlaceholder()) return;
    fail(RTC_ERROR_INVALID_OPERATION, "operation only allowed for user geometries");
  });
}
RTC_API void rtcSetGeometryBoundsFunction(RTCGeometry geometry, RTCBoundsFunction, void*) {
  notForThisGeometry("rtcSetGeometryBoundsFunction", geometry);
}
RTC_API void rtcSetGeometryIntersectFunction(RTCGeometry geometry, RTCIntersectFunctionN) {
  notForThisGeometry("rtcSetGeometryIntersectFunction", geometry);
}
RTC_API void rtcSetGeometryOccludedFunction(RTCGeometry geometry, RTCOccludedFunctionN) {
  notForThisGeometry("rtcSetGeometryOccludedFunction", geometry);
}
RTC_API void rtcSetGeometryPointQueryFunction(RTCGeometry geometry, RTCPointQueryFunction) {
  notForThisGeometry("rtcSetGeometryPointQueryFunction", geometry);
}
RTC_API void rtcSetGeometryMaxRadiusScale(RTCGeometry geometry, float) {
  notForThisGeometry("rtcSetGeometryMaxRadiusScale", geometry);
}
RTC_API void rtcSetGeometryTessellationRate(RTCGeometry geometry, float) {
  notForThisGeometry("rtcSetGeometryTessellationRate", geometry);
}
RTC_API void rtcSetGeometryTopologyCount(RTCGeometry geometry, unsigned int) {
  notForThisGeometry("rtcSetGeometryTopologyCount", geometry);
}
RTC_API void rtcSetGeometrySubdivisionMode(RTCGeometry geometry, unsigned int, RTCSubdivisionMode) {
  notForThisGeometry("rtcSetGeometrySubdivisionMode", geometry);
}
RTC_API void rtcSetGeometryVertexAttributeTopology(RTCGeometry geometry, unsigned int, unsigned int) {
  notForThisGeometry("rtcSetGeometryVertexAttributeTopology", geometry);
}
RTC_API void rtcSetGeometryDisplacementFunction(RTCGeometry geometry, RTCDisplacementFunctionN) {
  notForThisGeometry("rtcSetGeometryDisplacementFunction", geometry);
}
RTC_API unsigned int rtcGetGeometryFirstHalfEdge(RTCGeometry geometry, unsigned int) {
  return halfEdgeQuery("rtcGetGeometryFirstHalfEdge", geometry);
}
RTC_API unsigned int rtcGetGeometryFace(RTCGeometry geometry, unsigned int) {
  return halfEdgeQuery("rtcGetGeometryFace", geometry);
}
RTC_API unsigned int rtcGetGeometryNextHalfEdge(RTCGeometry geometry, unsigned int) {
  return halfEdgeQuery("rtcGetGeometryNextHalfEdge", geometry);
}
RTC_API unsigned int rtcGetGeometryPreviousHalfEdge(RTCGeometry geometry, unsigned int) {
  return halfEdgeQuery("rtcGetGeometryPreviousHalfEdge", geometry);
}
RTC_API unsigned int rtcGetGeometryOppositeHalfEdge(RTCGeometry geometry, unsigned int, unsigned int) {
  return halfEdgeQuery("rtcGetGeometryOppositeHalfEdge", geometry);
}

// Called from user geometries' intersect functions, which never run here.
RTC_API void rtcFilterIntersection(const RTCIntersectFunctionNArguments*, const RTCFilterFunctionNArguments*) {
  notSupported("rtcFilterIntersection", nullptr, "user geometry");
}
RTC_API void rtcFilterOcclusion(const RTCOccludedFunctionNArguments*, const RTCFilterFunctionNArguments*) {
  notSupported("rtcFilterOcclusion", nullptr, "user geometry");
}

RTC_API bool rtcPointQuery(RTCScene scene, RTCPointQuery*, RTCPointQueryContext*, RTCPointQueryFunction, void*) {
  notSupported("rtcPointQuery", scene, "the point query");
  return false;
}
RTC_API bool rtcPointQuery4(const int*, RTCScene scene, RTCPointQuery4*, RTCPointQueryContext*, RTCPointQueryFunction,
                            void**) {
  notSupported("rtcPointQuery4", scene, "the point query");
  return false;
}
RTC_API bool rtcPointQuery8(const int*, RTCScene scene, RTCPointQuery8*, RTCPointQueryContext*, RTCPointQueryFunction,
                            void**) {
  notSupported("rtcPointQuery8", scene, "the point query");
  return false;
}
RTC_API bool rtcPointQuery16(const int*, RTCScene scene, RTCPointQuery16*, RTCPointQueryContext*,
                             RTCPointQueryFunction, void**) {
  notSupported("rtcPointQuery16", scene, "the point query");
  return false;
}
RTC_API void rtcCollide(RTCScene scene0, RTCScene, RTCCollideFunc, void*) {
  notSupported("rtcCollide", scene0, "collision detection");
}

RTC_API RTCBVH rtcNewBVH(RTCDevice device) {
  notSupported("rtcNewBVH", device, "the BVH builder (rtcNewBVH, rtcBuildBVH)");
  return nullptr;
}
RTC_API void* rtcBuildBVH(const RTCBuildArguments*) {
  notSupported("rtcBuildBVH", nullptr, "the BVH builder (rtcNewBVH, rtcBuildBVH)");
  return nullptr;
}
RTC_API void* rtcThreadLocalAlloc(RTCThreadLocalAllocator, size_t, size_t) {
  notSupported("rtcThreadLocalAlloc", nullptr, "the BVH builder (rtcNewBVH, rtcBuildBVH)");
  return nullptr;
}
RTC_API void rtcRetainBVH(RTCBVH) { notSupported("rtcRetainBVH", nullptr, "the BVH builder (rtcNewBVH, rtcBuildBVH)"); }
RTC_API void rtcReleaseBVH(RTCBVH) {
  notSupported("rtcReleaseBVH", nullptr, "the BVH builder (rtcNewBVH, rtcBuildBVH)");
}
// Exported by libembree3.so.3 without a declaration in its headers.
extern "C" RTC_API_EXPORT void rtcMakeStaticBVH(RTCBVH) {
  notSupported("rtcMakeStaticBVH", nullptr, "the BVH builder (rtcNewBVH, rtcBuildBVH)");
}
