// An LD_PRELOAD library that records every rtcIntersect1, rtcOccluded1,
// rtcIntersect1M and rtcOccluded1M call of a program, whichever
// libembree3.so.3 it runs on, to the file MBRT_RAYLOG: per ray the call
// (0 closest hit, 1 occlusion), the ray as given and the ray and hit as
// returned (raylog.h). tutorial_check compares two such logs.
#include <dlfcn.h>
#include <embree3/rtcore.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <vector>

#include "raylog.h"

namespace {

std::mutex gMutex;
std::FILE* gFile = nullptr;

std::FILE* logFile() {
  static std::once_flag once;
  std::call_once(once, [] {
    const char* path = std::getenv("MBRT_RAYLOG");
    if (path && *path) gFile = std::fopen(path, "wb");
  });
  return gFile;
}

void record(uint32_t call, const RTCRay& in, const RTCRayHit& out) {
  std::FILE* f = logFile();
  if (!f) return;
  mbrt::embree_test::RayRecord r{call, in, out};
  std::lock_guard<std::mutex> lock(gMutex);
  std::fwrite(&r, sizeof r, 1, f);
  std::fflush(f);
}

template <class F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" {

void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  static const auto real = next<decltype(&rtcIntersect1)>("rtcIntersect1");
  const RTCRay in = rayhit->ray;
  real(scene, context, rayhit);
  record(0, in, *rayhit);
}

void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  static const auto real = next<decltype(&rtcOccluded1)>("rtcOccluded1");
  const RTCRay in = *ray;
  real(scene, context, ray);
  RTCRayHit out{};
  out.ray = *ray;
  record(1, in, out);
}

void rtcIntersect1M(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit, unsigned int M, size_t stride) {
  static const auto real = next<decltype(&rtcIntersect1M)>("rtcIntersect1M");
  auto at = [&](unsigned i) { return reinterpret_cast<RTCRayHit*>(reinterpret_cast<char*>(rayhit) + i * stride); };
  std::vector<RTCRay> in(M);
  for (unsigned i = 0; i < M; ++i) in[i] = at(i)->ray;
  real(scene, context, rayhit, M, stride);
  for (unsigned i = 0; i < M; ++i) record(0, in[i], *at(i));
}

void rtcOccluded1M(RTCScene scene, RTCIntersectContext* context, RTCRay* ray, unsigned int M, size_t stride) {
  static const auto real = next<decltype(&rtcOccluded1M)>("rtcOccluded1M");
  auto at = [&](unsigned i) { return reinterpret_cast<RTCRay*>(reinterpret_cast<char*>(ray) + i * stride); };
  std::vector<RTCRay> in(M);
  for (unsigned i = 0; i < M; ++i) in[i] = *at(i);
  real(scene, context, ray, M, stride);
  for (unsigned i = 0; i < M; ++i) {
    RTCRayHit out{};
    out.ray = *at(i);
    record(1, in[i], out);
  }
}

}  // extern "C"
