// Thread safety as Embree promises it: any number of threads trace one
// committed scene at once (rtcIntersect1, rtcOccluded1, packets, streams),
// with a filter function running on the tracing threads that looks the hit
// geometry and its user data up as Cycles' filters do (rtcGetGeometry,
// rtcGetGeometryUserData), and every answer equals one thread's. Linked against the shared libembree3.so.3 itself;
// run under ThreadSanitizer by scripts/test-tsan.sh.
#include <embree3/rtcore.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <random>
#include <thread>
#include <vector>

namespace {

constexpr int kThreads = 8;
std::atomic<uint64_t> gFilterCalls{0};
std::atomic<uint64_t> gLookupMisses{0};
RTCScene gScene = nullptr;  // set before tracing starts
int gFilteredTag = 0;       // the filtered mesh's user data points here

void oddPrimitivesOnly(const RTCFilterFunctionNArguments* a) {
  gFilterCalls.fetch_add(1, std::memory_order_relaxed);
  for (unsigned i = 0; i < a->N; ++i) {
    if (!a->valid[i]) continue;
    RTCGeometry g = rtcGetGeometry(gScene, RTCHitN_geomID(a->hit, a->N, i));
    if (a->geometryUserPtr != &gFilteredTag || rtcGetGeometryUserData(g) != &gFilteredTag)
      gLookupMisses.fetch_add(1, std::memory_order_relaxed);
    if (RTCHitN_primID(a->hit, a->N, i) % 2 == 0) a->valid[i] = 0;
  }
}

RTCGeometry randomMesh(RTCDevice d, std::mt19937& rng, bool quads, unsigned prims, unsigned steps) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  RTCGeometry g = rtcNewGeometry(d, quads ? RTC_GEOMETRY_TYPE_QUAD : RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryTimeStepCount(g, steps);
  const unsigned corners = quads ? 4 : 3;
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                                             quads ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3,
                                                             corners * 4, prims));
  for (unsigned i = 0; i < corners * prims; ++i) idx[i] = i;
  std::vector<float> base(3 * corners * prims);
  for (unsigned p = 0; p < prims; ++p) {
    const float c[3] = {u(rng), u(rng), u(rng)};
    for (unsigned k = 0; k < corners; ++k)
      for (int a = 0; a < 3; ++a) base[3 * (corners * p + k) + a] = c[a] + 0.2f * u(rng);
  }
  for (unsigned s = 0; s < steps; ++s) {
    auto* v = static_cast<float*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, s, RTC_FORMAT_FLOAT3, 12, corners * prims));
    for (size_t i = 0; i < base.size(); ++i) v[i] = base[i] + 0.1f * float(s) * float(i % 3 == 0);
  }
  rtcCommitGeometry(g);
  return g;
}

struct Answer {
  unsigned geomID, primID, instID;
  float t;
  bool occluded;
  bool operator==(const Answer&) const = default;
};

TEST(EmbreeApiThreads, ConcurrentTracingOfOneScene) {
  RTCDevice d = rtcNewDevice("threads=1");  // builds on the caller (TSan cannot see inside TBB)
  ASSERT_EQ(rtcNewDevice("mbrt.kind=nope"), nullptr) << "not mbrt's libembree3.so.3";
  std::mt19937 rng(3);
  RTCScene child = rtcNewScene(d);
  RTCGeometry c = randomMesh(d, rng, false, 40, 2);
  rtcAttachGeometry(child, c);
  rtcReleaseGeometry(c);
  rtcCommitScene(child);
  RTCScene s = rtcNewScene(d);
  for (int k = 0; k < 3; ++k) {
    RTCGeometry g = randomMesh(d, rng, k == 1, 80, k + 1);
    if (k == 2) {
      rtcSetGeometryIntersectFilterFunction(g, oddPrimitivesOnly);
      rtcSetGeometryUserData(g, &gFilteredTag);
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
  }
  RTCGeometry inst = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(inst, child);
  rtcSetGeometryTimeStepCount(inst, 2);
  const float m0[12] = {0.5f, 0, 0, 0, 0.5f, 0, 0, 0, 0.5f, 0.3f, 0, 0}, m1[12] = {0, 0.5f, 0, -0.5f, 0, 0, 0, 0, 0.5f, 0, 0.3f, 0};
  rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m0);
  rtcSetGeometryTransform(inst, 1, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, m1);
  rtcCommitGeometry(inst);
  rtcAttachGeometry(s, inst);
  rtcReleaseGeometry(inst);
  rtcCommitScene(s);
  ASSERT_EQ(rtcGetDeviceError(d), RTC_ERROR_NONE);
  gScene = s;

  std::uniform_real_distribution<float> u(-1.0f, 1.0f), t01(0.0f, 1.0f);
  std::vector<RTCRayHit> rays(1600);
  for (RTCRayHit& rh : rays) {
    rh = {};
    rh.ray.org_x = 3 * u(rng), rh.ray.org_y = 3 * u(rng), rh.ray.org_z = 3;
    rh.ray.dir_x = 0.5f * u(rng) - 0.3f * rh.ray.org_x, rh.ray.dir_y = 0.5f * u(rng) - 0.3f * rh.ray.org_y, rh.ray.dir_z = -1;
    rh.ray.tfar = INFINITY, rh.ray.time = t01(rng), rh.ray.mask = ~0u;
    rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  }
  auto traceAll = [&](std::vector<Answer>& out, bool packets) {
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    out.resize(rays.size());
    for (size_t i = 0; i < rays.size(); i += 8) {
      RTCRayHit local[8];
      for (int k = 0; k < 8; ++k) local[k] = rays[i + k];
      if (packets) {
        alignas(32) RTCRayHit8 p;
        alignas(32) int valid[8];
        for (int k = 0; k < 8; ++k) {
          valid[k] = -1;
          const RTCRayHit& r = local[k];
          p.ray.org_x[k] = r.ray.org_x, p.ray.org_y[k] = r.ray.org_y, p.ray.org_z[k] = r.ray.org_z;
          p.ray.dir_x[k] = r.ray.dir_x, p.ray.dir_y[k] = r.ray.dir_y, p.ray.dir_z[k] = r.ray.dir_z;
          p.ray.tnear[k] = 0, p.ray.tfar[k] = INFINITY, p.ray.time[k] = r.ray.time, p.ray.mask[k] = ~0u;
          p.ray.id[k] = 0, p.ray.flags[k] = 0;
          p.hit.geomID[k] = p.hit.primID[k] = p.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
        }
        rtcIntersect8(valid, s, &ctx, &p);
        for (int k = 0; k < 8; ++k) {
          local[k].ray.tfar = p.ray.tfar[k], local[k].hit.geomID = p.hit.geomID[k];
          local[k].hit.primID = p.hit.primID[k], local[k].hit.instID[0] = p.hit.instID[0][k];
        }
      } else {
        rtcIntersect1M(s, &ctx, local, 8, sizeof(RTCRayHit));
      }
      for (int k = 0; k < 8; ++k) {
        RTCRay shadow = rays[i + k].ray;
        rtcOccluded1(s, &ctx, &shadow);
        out[i + k] = {local[k].hit.geomID, local[k].hit.primID, local[k].hit.instID[0], local[k].ray.tfar,
                      shadow.tfar < 0.0f};
      }
    }
  };
  std::vector<Answer> reference;
  traceAll(reference, false);
  size_t hits = 0;
  for (const Answer& a : reference) hits += a.geomID != RTC_INVALID_GEOMETRY_ID;
  EXPECT_GT(hits, rays.size() / 5);
  const uint64_t callsBefore = gFilterCalls.load();
  std::vector<std::vector<Answer>> answers(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) threads.emplace_back([&, t] { traceAll(answers[t], t % 2 == 1); });
  for (auto& th : threads) th.join();
  for (int t = 0; t < kThreads; ++t) EXPECT_TRUE(answers[t] == reference) << "thread " << t;
  EXPECT_GT(gFilterCalls.load(), callsBefore);
  EXPECT_EQ(gLookupMisses.load(), 0u);
  EXPECT_EQ(rtcGetDeviceError(d), RTC_ERROR_NONE);
  rtcReleaseScene(s);
  rtcReleaseScene(child);
  rtcReleaseDevice(d);
}

}  // namespace
