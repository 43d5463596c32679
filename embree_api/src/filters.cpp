// Filter functions with Embree's arguments (filters.h).
#include "filters.h"

#include <bit>
#include <algorithm>
#include <cmath>
#include <vector>

#include "geometry.h"

namespace mbrt::embree_api {
namespace {

thread_local TraceCall* tCall = nullptr;

// The ray in the space of the instanced scene a bound copy belongs to.
void toInstanceSpace(const InstancePath& path, float time, Vec3f& org, Vec3f& dir) {
  for (const mbrt::Geometry* g : {path.outer, path.inner}) {
    if (!g) continue;
    const Affine3f inv = g->transformAt(time).inverse();
    org = inv.xfmPoint(org);
    dir = inv.xfmVector(dir);
  }
}

}  // namespace

ScopedCall::ScopedCall(TraceCall& call) : previous_(tCall) { tCall = &call; }
ScopedCall::~ScopedCall() { tCall = previous_; }

double directionScale(Vec3f dir) {
  const float m = std::max(std::fabs(dir.x), std::max(std::fabs(dir.y), std::fabs(dir.z)));
  int e;
  std::frexp(double(m), &e);  // m = f * 2^e, f in [0.5, 1)
  return std::ldexp(1.0, 1 - e);
}

Vec3f objectNormal(const mbrt::Geometry& mesh, uint32_t prim, float time) {
  const Triangle& t = mesh.triangles()[prim];
  const Vec3f v0 = mesh.vertexAt(time, t.v0), v1 = mesh.vertexAt(time, t.v1), v2 = mesh.vertexAt(time, t.v2);
  return cross(v1 - v0, v2 - v0);
}

bool runFilters(const FilterBinding& b, const FilterArgs& a) {
  TraceCall* call = tCall;
  if (!call) return true;
  const bool occlusion = call->hit == nullptr;
  const RTCFilterFunctionN own = occlusion ? b.geometry->occludedFilter : b.geometry->intersectFilter;
  const RTCFilterFunctionN shared = call->contextFilter ? call->context->filter : nullptr;
  if (!own && !shared) return true;

  const unsigned N = call->N, lane = call->lane;
  // valid[] and the hit packet of N lanes (on the stack up to 16).
  alignas(64) int validStorage[16];
  alignas(64) RTCHit16 hitStorage;
  thread_local std::vector<int> validHeap;
  thread_local std::vector<float> hitHeap;
  int* valid = validStorage;
  RTCHitN* hit = reinterpret_cast<RTCHitN*>(&hitStorage);
  if (N > 16) {
    validHeap.assign(N, 0);
    hitHeap.assign(size_t(N) * sizeof(RTCHit) / sizeof(float), 0.0f);
    valid = validHeap.data();
    hit = reinterpret_cast<RTCHitN*>(hitHeap.data());
  }
  std::fill(valid, valid + N, 0);
  valid[lane] = -1;
  bool secondHalf;
  const uint32_t prim = b.prims.embreePrim(a.candidate.primID, secondHalf);
  const Vec3f ng = objectNormal(*b.mesh, a.candidate.primID, call->time);
  RTCHitN_Ng_x(hit, N, lane) = ng.x;
  RTCHitN_Ng_y(hit, N, lane) = ng.y;
  RTCHitN_Ng_z(hit, N, lane) = ng.z;
  RTCHitN_u(hit, N, lane) = secondHalf ? 1.0f - a.candidate.u : a.candidate.u;
  RTCHitN_v(hit, N, lane) = secondHalf ? 1.0f - a.candidate.v : a.candidate.v;
  RTCHitN_primID(hit, N, lane) = prim;
  RTCHitN_geomID(hit, N, lane) = b.geomID;
  RTCHitN_instID(hit, N, lane, 0) = b.instID;

  // The caller's ray as Embree shows it to a filter.
  RTCRayN* ray = call->ray;
  float& tfar = RTCRayN_tfar(ray, N, lane);
  const float oldTfar = tfar;
  const float t = float(double(a.candidate.t) * call->scale);
  tfar = t;
  if (b.path) {
    Vec3f org = call->org, dir = call->dir;
    toInstanceSpace(*b.path, call->time, org, dir);
    RTCRayN_org_x(ray, N, lane) = org.x;
    RTCRayN_org_y(ray, N, lane) = org.y;
    RTCRayN_org_z(ray, N, lane) = org.z;
    RTCRayN_dir_x(ray, N, lane) = dir.x;
    RTCRayN_dir_y(ray, N, lane) = dir.y;
    RTCRayN_dir_z(ray, N, lane) = dir.z;
  }
  const unsigned oldInst = call->context->instID[0];
  call->context->instID[0] = b.instID;

  RTCFilterFunctionNArguments args{valid, b.geometry->userData, call->context, ray, hit, N};
  if (own) own(&args);
  if (valid[lane] != 0 && shared) shared(&args);

  call->context->instID[0] = oldInst;
  if (b.path) {
    RTCRayN_org_x(ray, N, lane) = call->org.x;
    RTCRayN_org_y(ray, N, lane) = call->org.y;
    RTCRayN_org_z(ray, N, lane) = call->org.z;
    RTCRayN_dir_x(ray, N, lane) = call->dir.x;
    RTCRayN_dir_y(ray, N, lane) = call->dir.y;
    RTCRayN_dir_z(ray, N, lane) = call->dir.z;
  }
  if (valid[lane] == 0) {
    tfar = oldTfar;
    return false;
  }
  if (!occlusion) {
    // Embree copies the accepted hit, with the filter's changes, to the ray.
    const RTCHit accepted = rtcGetHitFromHitN(hit, N, lane);
    rtcCopyHitToHitN(call->hit, &accepted, N, lane);
    call->accepted = true;
    call->acceptedGeom = a.candidate.geomID;
    call->acceptedPrim = a.candidate.primID;
    call->acceptedInst = b.instID;
    call->acceptedT = t;
  }
  return true;
}

}  // namespace mbrt::embree_api
