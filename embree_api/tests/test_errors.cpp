// Errors: the wrong calls of mistakes.inl must be reported by mbrt's
// Embree API with the real libembree3's codes (rtcGetDeviceError of the
// device or, without a usable one, of NULL; the error callback), and what
// mbrt does not implement, or refuses where Embree would assert or crash,
// gets a clear error naming the function, never a crash.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "api.h"  // mbrt's build, renamed: rtcX is mbrtEmbree_rtcX here
#include "embree_side.h"

namespace mbrt::embree_test {
namespace {

TEST(EmbreeApiErrors, WrongCallsReportedWithEmbreesCodes) {
  const std::vector<Mistake> real = realEmbree().mistakes();
  const std::vector<Mistake> ours = mbrtEmbree().mistakes();
  ASSERT_EQ(real.size(), ours.size());
  for (size_t i = 0; i < real.size(); ++i) {
    SCOPED_TRACE(real[i].what);
    EXPECT_EQ(ours[i].deviceCode, real[i].deviceCode) << "Embree: " << real[i].message << "; mbrt: " << ours[i].message;
    EXPECT_EQ(ours[i].threadCode, real[i].threadCode);
    EXPECT_EQ(ours[i].callbacks, real[i].callbacks);
    if (ours[i].callbacks > 0) EXPECT_EQ(ours[i].message.rfind("rtc", 0), 0u) << ours[i].message;
  }
}

// A device with a callback recording the last error.
struct Checked {
  RTCDevice device;
  RTCError code = RTC_ERROR_NONE;
  std::string message;
  explicit Checked(const char* config = nullptr) : device(rtcNewDevice(config)) {
    rtcSetDeviceErrorFunction(
        device,
        [](void* self, RTCError code, const char* message) {
          static_cast<Checked*>(self)->code = code;
          static_cast<Checked*>(self)->message = message;
        },
        this);
  }
  ~Checked() { rtcReleaseDevice(device); }
  // The code reported since the last call, and that rtcGetDeviceError agrees.
  RTCError take() {
    const RTCError c = code;
    EXPECT_EQ(rtcGetDeviceError(device), c);
    code = RTC_ERROR_NONE;
    return c;
  }
};

RTCScene triangleScene(RTCDevice d) {
  RTCScene s = rtcNewScene(d);
  RTCGeometry g = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 6));
  const float p[18] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0, 3, 0, 0, 2, 1, NAN};
  for (int i = 0; i < 18; ++i) v[i] = p[i];
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, 2));
  const unsigned ind[6] = {0, 1, 2, 3, 4, 5};
  for (int i = 0; i < 6; ++i) idx[i] = ind[i];
  rtcCommitGeometry(g);
  rtcAttachGeometry(s, g);
  rtcReleaseGeometry(g);
  return s;
}

RTCRayHit rayAt(float x, float y) {
  RTCRayHit rh{};
  rh.ray.org_x = x;
  rh.ray.org_y = y;
  rh.ray.org_z = -1;
  rh.ray.dir_z = 1;
  rh.ray.tfar = INFINITY;
  rh.ray.mask = ~0u;
  rh.hit.geomID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

TEST(EmbreeApiErrors, UnsupportedGeometryTypes) {
  Checked c;
  RTCScene s = triangleScene(c.device);
  for (RTCGeometryType t : {RTC_GEOMETRY_TYPE_SUBDIVISION, RTC_GEOMETRY_TYPE_USER, RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE,
                            RTC_GEOMETRY_TYPE_ROUND_LINEAR_CURVE, RTC_GEOMETRY_TYPE_SPHERE_POINT, RTC_GEOMETRY_TYPE_GRID}) {
    RTCGeometry g = rtcNewGeometry(c.device, t);
    EXPECT_EQ(c.take(), RTC_ERROR_UNKNOWN);  // as Embree reports a type compiled out of it
    EXPECT_EQ(c.message.rfind("rtcNewGeometry: RTC_GEOMETRY_TYPE_", 0), 0u) << c.message;
    EXPECT_NE(c.message.find("is not supported"), std::string::npos) << c.message;
    // The placeholder handed out: a program that goes on does not crash,
    // and nothing more is reported.
    ASSERT_NE(g, nullptr);
    rtcSetGeometryTimeStepCount(g, 2);
    auto* scratch = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 1, RTC_FORMAT_FLOAT4, 16, 64));
    ASSERT_NE(scratch, nullptr);
    scratch[4 * 64 - 1] = 1.0f;
    EXPECT_EQ(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 1), scratch);  // a refit finds it again
    EXPECT_EQ(rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0), nullptr);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, scratch, 0, 4, 10);
    rtcSetGeometryUserPrimitiveCount(g, 3);
    rtcSetGeometryTessellationRate(g, 4.0f);
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
    EXPECT_EQ(c.take(), RTC_ERROR_NONE) << c.message;
  }
  rtcCommitScene(s);  // the placeholders are left out, the triangles traced
  EXPECT_EQ(c.take(), RTC_ERROR_NONE) << c.message;
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = rayAt(0.2f, 0.2f);
  rtcIntersect1(s, &ctx, &rh);
  EXPECT_EQ(rh.hit.geomID, 0u);
  EXPECT_EQ(rtcGetDeviceProperty(c.device, RTC_DEVICE_PROPERTY_USER_GEOMETRY_SUPPORTED), 0);
  EXPECT_EQ(rtcGetDeviceProperty(c.device, RTC_DEVICE_PROPERTY_TRIANGLE_GEOMETRY_SUPPORTED), 1);
  // A type Embree does not know: NULL, as Embree returns.
  EXPECT_EQ(rtcNewGeometry(c.device, RTCGeometryType(77)), nullptr);
  EXPECT_EQ(c.take(), RTC_ERROR_UNKNOWN);
  rtcSetGeometryUserPrimitiveCount(nullptr, 3);
  EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT);
  rtcReleaseScene(s);
}

TEST(EmbreeApiErrors, UnsupportedFunctionsNameThemselves) {
  Checked c;
  RTCScene s = triangleScene(c.device);
  rtcCommitScene(s);
  RTCPointQuery q{0, 0, 0, 0, 1};
  RTCPointQueryContext pc;
  rtcInitPointQueryContext(&pc);
  EXPECT_FALSE(rtcPointQuery(s, &q, &pc, nullptr, nullptr));
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(c.message.rfind("rtcPointQuery: ", 0), 0u) << c.message;
  rtcCollide(s, s, nullptr, nullptr);
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(c.message.rfind("rtcCollide: ", 0), 0u) << c.message;
  EXPECT_EQ(rtcNewBVH(c.device), nullptr);
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(c.message.rfind("rtcNewBVH: ", 0), 0u) << c.message;
  rtcReleaseScene(s);
}

TEST(EmbreeApiErrors, KindsOfTheConfigStringAndTheEnvironment) {
  for (const char* config : {"mbrt.kind=nope", "threads=1,mbrt.kind=embree", "mbrt.colour=red"}) {
    rtcGetDeviceError(nullptr);
    EXPECT_EQ(rtcNewDevice(config), nullptr) << config;
    EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT) << config;
  }
  setenv("MBRT_EMBREE_KIND", "nope", 1);
  EXPECT_EQ(rtcNewDevice(nullptr), nullptr);
  EXPECT_EQ(rtcGetDeviceError(nullptr), RTC_ERROR_INVALID_ARGUMENT);
  RTCDevice d = rtcNewDevice("mbrt.kind=stbvh");  // the config string wins over the environment
  EXPECT_NE(d, nullptr);
  rtcReleaseDevice(d);
  setenv("MBRT_EMBREE_KIND", "bvh-interp", 1);
  d = rtcNewDevice(nullptr);
  EXPECT_NE(d, nullptr);
  rtcReleaseDevice(d);
  unsetenv("MBRT_EMBREE_KIND");
}

TEST(EmbreeApiErrors, WhereEmbreeWouldCrashOrAssert) {
  Checked c;
  RTCScene s = triangleScene(c.device);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = rayAt(0.2f, 0.2f);
  rtcIntersect1(s, &ctx, &rh);  // not committed
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(c.message, "rtcIntersect1: scene got not committed");
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  rtcSetSceneBuildQuality(s, RTCBuildQuality(99));  // Embree aborts
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_ARGUMENT);
  rtcCommitScene(s);
  EXPECT_EQ(c.take(), RTC_ERROR_NONE);  // the NaN vertex leaves its triangle out, as Embree does
  rtcIntersect1(s, &ctx, &rh);
  EXPECT_EQ(rh.hit.geomID, 0u);
  EXPECT_EQ(rh.ray.tfar, 1.0f);
  RTCRayHit past = rayAt(2.1f, 0.1f);
  rtcIntersect1(s, &ctx, &past);
  EXPECT_EQ(past.hit.geomID, RTC_INVALID_GEOMETRY_ID);

  // A scene with an instance inside an instanced scene: Embree 3 (one
  // instance level) asserts when a ray reaches it; mbrt leaves it out.
  RTCScene middle = rtcNewScene(c.device), top = rtcNewScene(c.device);
  const float identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  for (auto [parent, child] : {std::pair{middle, s}, std::pair{top, middle}}) {
    RTCGeometry i = rtcNewGeometry(c.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(i, child);
    rtcSetGeometryTransform(i, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, identity);
    rtcCommitGeometry(i);
    rtcAttachGeometry(parent, i);
    rtcReleaseGeometry(i);
    rtcCommitScene(parent);
  }
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_NE(c.message.find("one instance level"), std::string::npos) << c.message;
  RTCRayHit nested = rayAt(0.2f, 0.2f);
  rtcIntersect1(top, &ctx, &nested);
  EXPECT_EQ(nested.hit.geomID, RTC_INVALID_GEOMETRY_ID);

  // A singular instance transform: reported, left out.
  RTCScene flat = rtcNewScene(c.device);
  RTCGeometry i = rtcNewGeometry(c.device, RTC_GEOMETRY_TYPE_INSTANCE);
  rtcSetGeometryInstancedScene(i, s);
  const float zero[12] = {};
  rtcSetGeometryTransform(i, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, zero);
  rtcCommitGeometry(i);
  rtcAttachGeometry(flat, i);
  rtcReleaseGeometry(i);
  rtcCommitScene(flat);
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_NE(c.message.find("singular"), std::string::npos) << c.message;
  // A time range outside the shutter.
  RTCGeometry g = rtcNewGeometry(c.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryTimeRange(g, -0.5f, 1.5f);
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_OPERATION);
  EXPECT_EQ(c.message.rfind("rtcSetGeometryTimeRange: ", 0), 0u);
  // A handle of the wrong type (reported on the device of the object it names).
  rtcSetGeometryMask(reinterpret_cast<RTCGeometry>(s), 1);
  EXPECT_EQ(c.take(), RTC_ERROR_INVALID_ARGUMENT);
  EXPECT_NE(c.message.find("not a RTCGeometry"), std::string::npos) << c.message;
  rtcReleaseGeometry(g);
  for (RTCScene x : {flat, top, middle, s}) rtcReleaseScene(x);
}

// embree_verify's error callback throws a C++ exception: it reaches the
// caller of the failing function, as with Embree, and the code stays.
TEST(EmbreeApiErrors, AnErrorCallbackMayThrow) {
  RTCDevice d = rtcNewDevice(nullptr);
  int calls = 0;
  rtcSetDeviceErrorFunction(
      d,
      [](void* calls, RTCError, const char* message) {
        ++*static_cast<int*>(calls);
        throw std::runtime_error(message);
      },
      &calls);
  RTCGeometry g = rtcNewGeometry(d, RTC_GEOMETRY_TYPE_TRIANGLE);
  EXPECT_THROW(rtcSetGeometryTimeStepCount(g, RTC_MAX_TIME_STEP_COUNT + 1), std::runtime_error);
  EXPECT_EQ(rtcGetDeviceError(d), RTC_ERROR_INVALID_ARGUMENT);
  EXPECT_THROW(rtcNewGeometry(d, RTC_GEOMETRY_TYPE_USER), std::runtime_error);
  EXPECT_EQ(rtcGetDeviceError(d), RTC_ERROR_UNKNOWN);
  EXPECT_EQ(calls, 2);  // once per failing call
  rtcReleaseGeometry(g);
  EXPECT_EQ(rtcGetDeviceError(d), RTC_ERROR_NONE);
  rtcReleaseDevice(d);
}

TEST(EmbreeApiErrors, EmptySceneMissesEverything) {
  Checked c;
  RTCScene s = rtcNewScene(c.device);
  rtcCommitScene(s);
  EXPECT_EQ(c.take(), RTC_ERROR_NONE);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = rayAt(0, 0);
  rtcIntersect1(s, &ctx, &rh);
  EXPECT_EQ(rh.hit.geomID, RTC_INVALID_GEOMETRY_ID);
  RTCBounds b;
  rtcGetSceneBounds(s, &b);
  EXPECT_EQ(c.take(), RTC_ERROR_NONE);
  EXPECT_GT(b.lower_x, b.upper_x);
  rtcReleaseScene(s);
}

}  // namespace
}  // namespace mbrt::embree_test
