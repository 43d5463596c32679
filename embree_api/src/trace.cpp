// One ray through mbrt and back into Embree's structures (trace.h), and
// rtcIntersect1 / rtcOccluded1.
#include "trace.h"

#include <algorithm>

#include "errors.h"
#include "filters.h"

namespace mbrt::embree_api {
namespace {

// The context of calls that pass none (Embree requires one; a null one is
// taken as rtcInitIntersectContext's).
RTCIntersectContext* contextOr(RTCIntersectContext* context) {
  if (context) return context;
  thread_local RTCIntersectContext fallback;
  rtcInitIntersectContext(&fallback);
  return &fallback;
}

// The lane as an mbrt ray; false when Embree would not trace it
// (tnear > tfar). Times outside [0, 1] are clamped into the shutter.
bool readRay(RTCRayN* r, unsigned N, unsigned i, Ray& out) {
  out.org = {RTCRayN_org_x(r, N, i), RTCRayN_org_y(r, N, i), RTCRayN_org_z(r, N, i)};
  out.dir = {RTCRayN_dir_x(r, N, i), RTCRayN_dir_y(r, N, i), RTCRayN_dir_z(r, N, i)};
  out.tnear = RTCRayN_tnear(r, N, i);
  out.tfar = RTCRayN_tfar(r, N, i);
  const float time = RTCRayN_time(r, N, i);
  out.time = time < 0.0f ? 0.0f : (time > 1.0f ? 1.0f : time);
  out.mask = RTCRayN_mask(r, N, i);
  return out.tnear <= out.tfar;
}

void startCall(TraceCall& call, const Committed& c, RTCIntersectContext* context, RTCRayN* ray, RTCHitN* hit,
               unsigned N, unsigned lane, const Ray& r) {
  call.context = context;
  call.ray = ray;
  call.hit = hit;
  call.N = N;
  call.lane = lane;
  call.contextFilter = c.contextFilter;
  call.scale = directionScale(r.dir);
  call.org = r.org;
  call.dir = r.dir;
  call.time = r.time;
}

}  // namespace

const Committed& committedOf(RTCScene scene) {
  const Scene& s = require<Scene>(scene, "RTCScene");
  const Committed* c = s.committed();
  if (!c) fail(RTC_ERROR_INVALID_OPERATION, "scene got not committed");
  return *c;
}

void intersectLane(const Committed& c, RTCIntersectContext* context, RTCRayN* ray, RTCHitN* hit, unsigned N,
                   unsigned lane) {
  Ray r;
  if (!c.accel || !readRay(ray, N, lane, r)) return;
  const Snapshot& s = *c.snapshot;
  Hit h;
  TraceCall call;
  bool found;
  if (s.hasFilters) {
    startCall(call, c, contextOr(context), ray, hit, N, lane, r);
    ScopedCall scope(call);
    found = c.accel->intersect(r, h);
  } else {
    found = c.accel->intersect(r, h);
  }
  if (!found) return;

  uint32_t instID = RTC_INVALID_GEOMETRY_ID;
  const GeomEntry* e;
  Vec3f ng = h.Ng;
  if (h.instID != kInvalidId) {
    // Embree reports an instanced hit in the instanced scene's space.
    const GeomEntry& inst = s.entries[h.instID];
    instID = inst.embreeID;
    e = &inst.child->entries[h.geomID];
    ng = objectNormal(inst.child->scene->geometry(h.geomID), h.primID, r.time);
  } else {
    e = &s.entries[h.geomID];
  }
  RTCRayN_tfar(ray, N, lane) = h.t;
  if (call.accepted && call.acceptedGeom == h.geomID && call.acceptedPrim == h.primID && call.acceptedInst == instID &&
      call.acceptedT == h.t)
    return;  // the filter's accepted hit is in the ray already (filters.cpp)
  bool secondHalf;
  const uint32_t prim = e->prims.embreePrim(h.primID, secondHalf);
  RTCHitN_Ng_x(hit, N, lane) = ng.x;
  RTCHitN_Ng_y(hit, N, lane) = ng.y;
  RTCHitN_Ng_z(hit, N, lane) = ng.z;
  RTCHitN_u(hit, N, lane) = secondHalf ? 1.0f - h.u : h.u;
  RTCHitN_v(hit, N, lane) = secondHalf ? 1.0f - h.v : h.v;
  RTCHitN_primID(hit, N, lane) = prim;
  RTCHitN_geomID(hit, N, lane) = e->embreeID;
  RTCHitN_instID(hit, N, lane, 0) = instID;
}

void occludedLane(const Committed& c, RTCIntersectContext* context, RTCRayN* ray, unsigned N, unsigned lane) {
  Ray r;
  if (!c.accel || !readRay(ray, N, lane, r)) return;
  bool blocked;
  if (c.snapshot->hasFilters) {
    TraceCall call;
    startCall(call, c, contextOr(context), ray, nullptr, N, lane, r);
    ScopedCall scope(call);
    blocked = c.accel->occluded(r);
  } else {
    blocked = c.accel->occluded(r);
  }
  if (blocked) RTCRayN_tfar(ray, N, lane) = -kInf;
}

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

RTC_API void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  guarded("rtcIntersect1", scene, [&] {
    const Committed& c = committedOf(scene);
    if (!rayhit) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null ray");
    intersectLane(c, context, reinterpret_cast<RTCRayN*>(&rayhit->ray), reinterpret_cast<RTCHitN*>(&rayhit->hit), 1, 0);
  });
}

RTC_API void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  guarded("rtcOccluded1", scene, [&] {
    const Committed& c = committedOf(scene);
    if (!ray) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null ray");
    occludedLane(c, context, reinterpret_cast<RTCRayN*>(ray), 1, 0);
  });
}
