// Ray streams: M rays of a stride (1M), M pointers (1Mp), M packets of N
// (NM, any N, as Embree) and N rays in pointer-SOA layout (Np). Each ray goes through the
// one-ray path in the caller's memory (trace.h); an Np ray is gathered
// into an RTCRayHit, traced and scattered back.
#include "errors.h"
#include "trace.h"

using namespace mbrt::embree_api;

namespace {

void checkN(unsigned N) {
  if (N == 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: packet size N is 0");
}

RTCRayHit gather(const RTCRayHitNp& s, unsigned i) {
  RTCRayHit r;
  r.ray = {s.ray.org_x[i], s.ray.org_y[i], s.ray.org_z[i], s.ray.tnear[i], s.ray.dir_x[i], s.ray.dir_y[i],
           s.ray.dir_z[i], s.ray.time[i],  s.ray.tfar[i],  s.ray.mask[i],  s.ray.id[i],    s.ray.flags[i]};
  r.hit = {s.hit.Ng_x[i], s.hit.Ng_y[i], s.hit.Ng_z[i], s.hit.u[i], s.hit.v[i], s.hit.primID[i], s.hit.geomID[i],
           {s.hit.instID[0][i]}};
  return r;
}

void scatter(const RTCRayHit& r, const RTCRayHitNp& s, unsigned i) {
  s.ray.tfar[i] = r.ray.tfar;
  s.hit.Ng_x[i] = r.hit.Ng_x;
  s.hit.Ng_y[i] = r.hit.Ng_y;
  s.hit.Ng_z[i] = r.hit.Ng_z;
  s.hit.u[i] = r.hit.u;
  s.hit.v[i] = r.hit.v;
  s.hit.primID[i] = r.hit.primID;
  s.hit.geomID[i] = r.hit.geomID;
  s.hit.instID[0][i] = r.hit.instID[0];
}

RTCRayN* rayOf(RTCRayHit* r) { return reinterpret_cast<RTCRayN*>(&r->ray); }
RTCHitN* hitOf(RTCRayHit* r) { return reinterpret_cast<RTCHitN*>(&r->hit); }

}  // namespace

RTC_API void rtcIntersect1M(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit, unsigned int M,
                            size_t byteStride) {
  guarded("rtcIntersect1M", scene, [&] {
    const Committed& c = committedOf(scene);
    for (unsigned m = 0; m < M; ++m) {
      auto* r = reinterpret_cast<RTCRayHit*>(reinterpret_cast<char*>(rayhit) + m * byteStride);
      intersectLane(c, context, rayOf(r), hitOf(r), 1, 0);
    }
  });
}

RTC_API void rtcIntersect1Mp(RTCScene scene, RTCIntersectContext* context, RTCRayHit** rayhit, unsigned int M) {
  guarded("rtcIntersect1Mp", scene, [&] {
    const Committed& c = committedOf(scene);
    for (unsigned m = 0; m < M; ++m) intersectLane(c, context, rayOf(rayhit[m]), hitOf(rayhit[m]), 1, 0);
  });
}

RTC_API void rtcIntersectNM(RTCScene scene, RTCIntersectContext* context, RTCRayHitN* rayhit, unsigned int N,
                            unsigned int M, size_t byteStride) {
  guarded("rtcIntersectNM", scene, [&] {
    const Committed& c = committedOf(scene);
    checkN(N);
    for (unsigned m = 0; m < M; ++m) {
      auto* p = reinterpret_cast<RTCRayHitN*>(reinterpret_cast<char*>(rayhit) + m * byteStride);
      for (unsigned i = 0; i < N; ++i) intersectLane(c, context, RTCRayHitN_RayN(p, N), RTCRayHitN_HitN(p, N), N, i);
    }
  });
}

RTC_API void rtcIntersectNp(RTCScene scene, RTCIntersectContext* context, const RTCRayHitNp* rayhit, unsigned int N) {
  guarded("rtcIntersectNp", scene, [&] {
    const Committed& c = committedOf(scene);
    for (unsigned i = 0; i < N; ++i) {
      RTCRayHit r = gather(*rayhit, i);
      intersectLane(c, context, rayOf(&r), hitOf(&r), 1, 0);
      scatter(r, *rayhit, i);
    }
  });
}

RTC_API void rtcOccluded1M(RTCScene scene, RTCIntersectContext* context, RTCRay* ray, unsigned int M,
                           size_t byteStride) {
  guarded("rtcOccluded1M", scene, [&] {
    const Committed& c = committedOf(scene);
    for (unsigned m = 0; m < M; ++m)
      occludedLane(c, context, reinterpret_cast<RTCRayN*>(reinterpret_cast<char*>(ray) + m * byteStride), 1, 0);
  });
}

RTC_API void rtcOccluded1Mp(RTCScene scene, RTCIntersectContext* context, RTCRay** ray, unsigned int M) {
  guarded("rtcOccluded1Mp", scene, [&] {
    const Committed& c = committedOf(scene);
    for (unsigned m = 0; m < M; ++m) occludedLane(c, context, reinterpret_cast<RTCRayN*>(ray[m]), 1, 0);
  });
}

RTC_API void rtcOccludedNM(RTCScene scene, RTCIntersectContext* context, RTCRayN* ray, unsigned int N, unsigned int M,
                           size_t byteStride) {
  guarded("rtcOccludedNM", scene, [&] {
    const Committed& c = committedOf(scene);
    checkN(N);
    for (unsigned m = 0; m < M; ++m) {
      auto* p = reinterpret_cast<RTCRayN*>(reinterpret_cast<char*>(ray) + m * byteStride);
      for (unsigned i = 0; i < N; ++i) occludedLane(c, context, p, N, i);
    }
  });
}

RTC_API void rtcOccludedNp(RTCScene scene, RTCIntersectContext* context, const RTCRayNp* ray, unsigned int N) {
  guarded("rtcOccludedNp", scene, [&] {
    const Committed& c = committedOf(scene);
    for (unsigned i = 0; i < N; ++i) {
      RTCRay r{ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->tnear[i], ray->dir_x[i], ray->dir_y[i],
               ray->dir_z[i], ray->time[i],  ray->tfar[i],  ray->mask[i],  ray->id[i],    ray->flags[i]};
      occludedLane(c, context, reinterpret_cast<RTCRayN*>(&r), 1, 0);
      ray->tfar[i] = r.tfar;
    }
  });
}
