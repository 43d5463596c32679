// Intersection and occlusion filter functions with Embree's semantics.
// mbrt calls a geometry's filter (mbrt::Scene::setFilter) on the tracing
// thread for every candidate hit; the call in progress (TraceCall, one per
// thread) says which ray of the caller's memory it is for. The filter then
// sees what Embree's would: valid[] with the ray's lane set, the caller's
// ray (or packet) with tfar set to the candidate's distance and, inside an
// instance, org and dir in the instance's space; the candidate in an
// RTCHitN (object-space Ng, Embree's primID and u/v, instID[0]); the
// geometry's filter first, then the context's (RTCIntersectContext::filter,
// when the traced scene has RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION).
// valid[lane] = 0 rejects the hit; an accepted closest hit is copied to the
// ray with the filter's changes, as Embree copies it.
#pragma once

#include "mbrt/scene.h"
#include "snapshot.h"

namespace mbrt::embree_api {

struct TraceCall {
  RTCIntersectContext* context = nullptr;
  RTCRayN* ray = nullptr;
  RTCHitN* hit = nullptr;  // null for occlusion queries
  unsigned N = 1, lane = 0;
  bool contextFilter = false;
  double scale = 1.0;  // 2^k by which mbrt scaled the direction (mbrt/ray.h)
  Vec3f org, dir;      // the ray as the caller gave it
  float time = 0.0f;
  // The last candidate a filter accepted (closest-hit queries).
  bool accepted = false;
  uint32_t acceptedGeom = 0, acceptedPrim = 0, acceptedInst = 0;
  float acceptedT = 0.0f;
};

// Makes `call` the calling thread's call in progress for its lifetime.
class ScopedCall {
 public:
  explicit ScopedCall(TraceCall& call);
  ~ScopedCall();
  ScopedCall(const ScopedCall&) = delete;
  ScopedCall& operator=(const ScopedCall&) = delete;

 private:
  TraceCall* previous_;
};

// The mbrt filter of a geometry with Embree filters (or of every geometry
// when the context filter may run).
bool runFilters(const FilterBinding& binding, const FilterArgs& args);

// The factor 2^k by which mbrt scales a ray's direction (largest component
// into [1, 2)), as mbrt/ray.h states.
double directionScale(Vec3f dir);

// Object-space Ng of mbrt triangle `prim` of `mesh` at `time`, as mbrt and
// Embree compute it: (v1 - v0) x (v2 - v0).
Vec3f objectNormal(const mbrt::Geometry& mesh, uint32_t prim, float time);

}  // namespace mbrt::embree_api
