// What mbrt's Embree API adds to a ray: an rtcIntersect1 loop through
// libembree3.so.3 against the same rays through mbrt's own C API
// (mbrtIntersect1, libmbrt.so), on the same kind and scene, one thread.
// Prints the time of each side and their ratio per round and the median of
// the rounds' ratios (docs/embree-api.md, docs/performance.md).
//
//   mbrt_embree_api_overhead [kind] [triangles] [rays] [rounds]
//
// The shim is loaded with dlopen from its build path (RTLD_LOCAL), beside
// libmbrt.so, which links the real libembree3 for its `embree` kind.
#include <dlfcn.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "mbrt/mbrt.h"

namespace {

struct Shim {
  decltype(&rtcNewDevice) newDevice;
  decltype(&rtcNewScene) newScene;
  decltype(&rtcNewGeometry) newGeometry;
  decltype(&rtcSetGeometryTimeStepCount) setTimeStepCount;
  decltype(&rtcSetSharedGeometryBuffer) setSharedBuffer;
  decltype(&rtcCommitGeometry) commitGeometry;
  decltype(&rtcAttachGeometry) attach;
  decltype(&rtcReleaseGeometry) releaseGeometry;
  decltype(&rtcCommitScene) commitScene;
  decltype(&rtcIntersect1) intersect1;
  decltype(&rtcGetDeviceError) getError;
};

template <class F>
void load(void* lib, const char* name, F& f) {
  f = reinterpret_cast<F>(dlsym(lib, name));
  if (!f) {
    std::fprintf(stderr, "overhead: %s missing from the shim\n", name);
    std::exit(1);
  }
}

double seconds(std::chrono::steady_clock::time_point a) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string kind = argc > 1 ? argv[1] : "auto";
  const size_t triangles = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 200000;
  const size_t rayCount = argc > 3 ? std::strtoul(argv[3], nullptr, 10) : 400000;
  const int rounds = argc > 4 ? std::atoi(argv[4]) : 3;

  void* lib = dlopen(MBRT_EMBREE_API_LIBRARY, RTLD_NOW | RTLD_LOCAL);
  if (!lib) return std::fprintf(stderr, "overhead: %s\n", dlerror()), 1;
  Shim s;
  load(lib, "rtcNewDevice", s.newDevice);
  load(lib, "rtcNewScene", s.newScene);
  load(lib, "rtcNewGeometry", s.newGeometry);
  load(lib, "rtcSetGeometryTimeStepCount", s.setTimeStepCount);
  load(lib, "rtcSetSharedGeometryBuffer", s.setSharedBuffer);
  load(lib, "rtcCommitGeometry", s.commitGeometry);
  load(lib, "rtcAttachGeometry", s.attach);
  load(lib, "rtcReleaseGeometry", s.releaseGeometry);
  load(lib, "rtcCommitScene", s.commitScene);
  load(lib, "rtcIntersect1", s.intersect1);
  load(lib, "rtcGetDeviceError", s.getError);

  // Small moving triangles in a unit cube, two steps (padded for Embree).
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<uint32_t> indices(3 * triangles);
  std::vector<float> steps[2];
  for (auto& st : steps) st.resize(9 * triangles + 4);
  for (size_t t = 0; t < triangles; ++t) {
    const float c[3] = {u(rng), u(rng), u(rng)}, m[3] = {0.05f * u(rng), 0.05f * u(rng), 0.05f * u(rng)};
    for (int k = 0; k < 3; ++k) {
      indices[3 * t + k] = uint32_t(3 * t + k);
      for (int a = 0; a < 3; ++a) {
        const float p = c[a] + 0.02f * u(rng);
        steps[0][9 * t + 3 * k + a] = p;
        steps[1][9 * t + 3 * k + a] = p + m[a];
      }
    }
  }
  std::vector<RTCRayHit> rays(rayCount);
  std::vector<MBRTRay> mrays(rayCount);
  std::uniform_real_distribution<float> t01(0.0f, 1.0f);
  for (size_t i = 0; i < rayCount; ++i) {
    const float o[3] = {0.3f * u(rng), 0.3f * u(rng), -3.0f}, d[3] = {0.3f * u(rng), 0.3f * u(rng), 1.0f};
    const float time = t01(rng);
    rays[i] = {};
    rays[i].ray = {o[0], o[1], o[2], 0.0f, d[0], d[1], d[2], time, INFINITY, ~0u, 0, 0};
    mrays[i] = {{o[0], o[1], o[2]}, 0.0f, {d[0], d[1], d[2]}, INFINITY, time, ~0u};
  }

  const std::string config = "mbrt.kind=" + kind;
  RTCDevice device = s.newDevice(config.c_str());
  if (!device) return std::fprintf(stderr, "overhead: the shim refused %s\n", config.c_str()), 1;
  RTCScene scene = s.newScene(device);
  RTCGeometry g = s.newGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  s.setTimeStepCount(g, 2);
  s.setSharedBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, indices.data(), 0, 12, triangles);
  for (unsigned k = 0; k < 2; ++k)
    s.setSharedBuffer(g, RTC_BUFFER_TYPE_VERTEX, k, RTC_FORMAT_FLOAT3, steps[k].data(), 0, 12, 3 * triangles);
  s.commitGeometry(g);
  s.attach(scene, g);
  s.releaseGeometry(g);
  s.commitScene(scene);
  if (s.getError(device) != RTC_ERROR_NONE) return std::fprintf(stderr, "overhead: the shim's build failed\n"), 1;

  MBRTDevice md = mbrtNewDevice();
  MBRTScene ms = mbrtNewScene(md);
  MBRTVertexBuffer vb[2] = {{steps[0].data(), 12, 3 * triangles}, {steps[1].data(), 12, 3 * triangles}};
  mbrtNewTriangleMesh(ms, indices.data(), triangles, vb, 2, 0.0f, 1.0f);
  MBRTAccel accel = mbrtNewAccel(ms, kind.c_str(), nullptr);
  if (!accel) return std::fprintf(stderr, "overhead: mbrtNewAccel failed\n"), 1;

  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  std::vector<double> ratios;
  size_t hitsShim = 0, hitsC = 0, differ = 0;
  std::vector<RTCRayHit> work(rays.size());
  std::vector<MBRTHit> mhits(rays.size());
  std::printf("kind %s, %zu moving triangles, %zu rays, one thread\n", kind.c_str(), triangles, rayCount);
  for (int r = 0; r < rounds; ++r) {
    work = rays;
    for (auto& w : work) w.hit.geomID = w.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    auto t0 = std::chrono::steady_clock::now();
    for (RTCRayHit& w : work) s.intersect1(scene, &ctx, &w);
    const double shim = seconds(t0);
    t0 = std::chrono::steady_clock::now();
    for (size_t i = 0; i < mrays.size(); ++i) mbrtIntersect1(accel, &mrays[i], &mhits[i]);
    const double capi = seconds(t0);
    hitsShim = hitsC = differ = 0;
    for (size_t i = 0; i < rays.size(); ++i) {
      const bool a = work[i].hit.geomID != RTC_INVALID_GEOMETRY_ID, b = mhits[i].geomID != MBRT_INVALID_ID;
      hitsShim += a, hitsC += b;
      differ += a != b || (a && work[i].ray.tfar != mhits[i].t);
    }
    ratios.push_back(shim / capi);
    std::printf("round %d: rtcIntersect1 %.3f s, mbrtIntersect1 %.3f s, ratio %.3f\n", r + 1, shim, capi, shim / capi);
  }
  std::sort(ratios.begin(), ratios.end());
  std::printf("hits %zu / %zu, answers differing %zu\n", hitsShim, hitsC, differ);
  std::printf("median ratio (shim / C API): %.3f\n", ratios[ratios.size() / 2]);
  mbrtReleaseAccel(accel);
  mbrtReleaseScene(ms);
  mbrtReleaseDevice(md);
  return differ == 0 ? 0 : 1;
}
