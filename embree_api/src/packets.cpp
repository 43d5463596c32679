// Ray packets of 4, 8 and 16 (rtcIntersect4/8/16, rtcOccluded4/8/16): each
// valid lane (valid[i] != 0) is traced on its own through the one-ray path,
// in the packet's own memory (trace.h), so filters see the packet with N.
#include "errors.h"
#include "trace.h"

using namespace mbrt::embree_api;

namespace {

template <unsigned N, class RayHitN>
void intersectPacket(const char* function, const int* valid, RTCScene scene, RTCIntersectContext* context,
                     RayHitN* rayhit) {
  guarded(function, scene, [&] {
    const Committed& c = committedOf(scene);
    if (!valid || !rayhit) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null valid mask or ray packet");
    auto* rh = reinterpret_cast<RTCRayHitN*>(rayhit);
    for (unsigned i = 0; i < N; ++i)
      if (valid[i]) intersectLane(c, context, RTCRayHitN_RayN(rh, N), RTCRayHitN_HitN(rh, N), N, i);
  });
}

template <unsigned N, class RayN>
void occludedPacket(const char* function, const int* valid, RTCScene scene, RTCIntersectContext* context, RayN* ray) {
  guarded(function, scene, [&] {
    const Committed& c = committedOf(scene);
    if (!valid || !ray) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null valid mask or ray packet");
    for (unsigned i = 0; i < N; ++i)
      if (valid[i]) occludedLane(c, context, reinterpret_cast<RTCRayN*>(ray), N, i);
  });
}

}  // namespace

RTC_API void rtcIntersect4(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit4* rayhit) {
  intersectPacket<4>("rtcIntersect4", valid, scene, context, rayhit);
}

RTC_API void rtcIntersect8(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit8* rayhit) {
  intersectPacket<8>("rtcIntersect8", valid, scene, context, rayhit);
}

RTC_API void rtcIntersect16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit16* rayhit) {
  intersectPacket<16>("rtcIntersect16", valid, scene, context, rayhit);
}

RTC_API void rtcOccluded4(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay4* ray) {
  occludedPacket<4>("rtcOccluded4", valid, scene, context, ray);
}

RTC_API void rtcOccluded8(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay8* ray) {
  occludedPacket<8>("rtcOccluded8", valid, scene, context, ray);
}

RTC_API void rtcOccluded16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay16* ray) {
  occludedPacket<16>("rtcOccluded16", valid, scene, context, ray);
}
