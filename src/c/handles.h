// The handles of the C API (mbrt/mbrt.h) and what every call shares: the
// tag checks, the guard that turns every exception into an error code and a
// message on the device, and the conversions between C and C++ types.
#pragma once

#include "mbrt/mbrt.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <vector>

#include "mbrt/accel.h"
#include "mbrt/accel_update.h"
#include "mbrt/build_options.h"
#include "mbrt/error.h"
#include "mbrt/io/animation.h"
#include "mbrt/quaternion.h"
#include "mbrt/scene.h"

namespace mbrt::capi {

// Tags at the start of every handle. Cleared on release, so that a released
// handle whose memory was not reused is refused too.
constexpr uint32_t kDeviceTag = 0x4d424456u;  // "MBDV"
constexpr uint32_t kSceneTag = 0x4d425343u;   // "MBSC"
constexpr uint32_t kAccelTag = 0x4d424143u;   // "MBAC"
constexpr uint32_t kAnimationTag = 0x4d42414eu;  // "MBAN"

// An error to report with a chosen code (the others are mapped by type).
struct CError {
  MBRTError code;
  std::string message;
};

struct ErrorSlot {
  MBRTError code = MBRT_ERROR_NONE;
  std::string message;
};

// Errors without a valid device, and the text mbrtGetError hands out.
inline thread_local ErrorSlot tNoDeviceError;
inline thread_local std::string tReturnedMessage;

}  // namespace mbrt::capi

struct MBRTDeviceT {
  uint32_t tag = mbrt::capi::kDeviceTag;
  std::mutex mutex;  // guards error and callback: errors may come from tracing threads
  mbrt::capi::ErrorSlot error;
  MBRTErrorCallback callback = nullptr;
  void* userPtr = nullptr;
  std::atomic<uint64_t> liveScenes{0};
};

namespace mbrt::capi {
// A scene and what the C layer knows of it. Shared: instances in other
// scenes keep it alive after its handle is released.
struct SceneData {
  std::shared_ptr<mbrt::Scene> scene = std::make_shared<mbrt::Scene>();
  std::vector<std::shared_ptr<SceneData>> children;  // the scenes it instances
  // Live accels that trace this scene, directly or through instances:
  // while nonzero the scene may not change.
  std::atomic<uint64_t> users{0};
};
}  // namespace mbrt::capi

struct MBRTSceneT {
  uint32_t tag = mbrt::capi::kSceneTag;
  MBRTDeviceT* device;
  std::shared_ptr<mbrt::capi::SceneData> data = std::make_shared<mbrt::capi::SceneData>();
  std::atomic<uint64_t> liveAccels{0};  // accels built on this scene itself
  // The animation whose frames this scene is (mbrtGetAnimationScene); null
  // for a scene of mbrtNewScene. Only the animation changes it.
  struct MBRTAnimationT* animation = nullptr;
};

struct MBRTAccelT {
  uint32_t tag = mbrt::capi::kAccelTag;
  MBRTSceneT* scene;
  std::unique_ptr<mbrt::Accel> accel;  // null after a failed mbrtUpdateAccel
  mbrt::BuildOptions options;          // what it was built with: the options of later builds
  uint64_t sceneVersion = 0;           // the scene's version at the last build or update
  mbrt::AccelUpdater updater;          // mbrtUpdateAccel's policy and what it remembers
};

struct MBRTAnimationT {
  uint32_t tag = mbrt::capi::kAnimationTag;
  MBRTDeviceT* device;
  std::unique_ptr<mbrt::Animation> animation;
  MBRTSceneT* scene = nullptr;  // its frames, owned by the animation
};

namespace mbrt::capi {

inline void record(MBRTDeviceT* device, MBRTError code, const std::string& message) {
  if (!device) {
    tNoDeviceError.code = code;
    tNoDeviceError.message = message;
    return;
  }
  MBRTErrorCallback callback;
  void* userPtr;
  {
    std::lock_guard<std::mutex> lock(device->mutex);
    device->error.code = code;
    device->error.message = message;
    callback = device->callback;
    userPtr = device->userPtr;
  }
  if (callback) callback(userPtr, code, message.c_str());
}

// Runs body(); any exception becomes an error on `device` and `failure` is
// returned. The error is recorded (and the callback called) after the
// handlers, outside any catch block; whatever is thrown while mapping or
// recording (only bad_alloc can be) is dropped rather than let through.
template <class R, class F>
R guarded(MBRTDeviceT* device, R failure, const char* call, F&& body) {
  MBRTError code = MBRT_ERROR_NONE;
  std::string message;
  try {
    try {
      return body();
    } catch (const CError& e) {
      code = e.code;
      message = e.message;
    } catch (const std::bad_alloc&) {
      code = MBRT_ERROR_OUT_OF_MEMORY;
      message = "out of memory";
    } catch (const mbrt::Error& e) {
      // The build budget's error (core/build_budget.h) names the budget.
      message = e.what();
      code = message.find("memory budget") != std::string::npos ? MBRT_ERROR_OUT_OF_MEMORY
                                                                 : MBRT_ERROR_INVALID_ARGUMENT;
    } catch (const std::invalid_argument& e) {
      code = MBRT_ERROR_INVALID_ARGUMENT;
      message = e.what();
    } catch (const std::out_of_range& e) {
      code = MBRT_ERROR_INVALID_ARGUMENT;
      message = e.what();
    } catch (const std::exception& e) {
      code = MBRT_ERROR_UNKNOWN;
      message = e.what();
    } catch (...) {
      code = MBRT_ERROR_UNKNOWN;
      message = "unknown exception";
    }
  } catch (...) {
    code = MBRT_ERROR_OUT_OF_MEMORY;  // copying a message failed
  }
  try {
    record(device, code, std::string(call) + ": " + message);
  } catch (...) {
  }
  return failure;
}

[[noreturn]] inline void fail(MBRTError code, std::string message) { throw CError{code, std::move(message)}; }

inline void require(bool ok, const char* what) {
  if (!ok) fail(MBRT_ERROR_INVALID_ARGUMENT, what);
}

// Handle checks. The device of a bad handle is unknown: such errors go to
// the thread's no-device slot.
inline MBRTDeviceT* deviceOf(MBRTDevice d) { return d && d->tag == kDeviceTag ? d : nullptr; }
inline MBRTDeviceT* deviceOf(MBRTScene s) { return s && s->tag == kSceneTag ? s->device : nullptr; }
inline MBRTDeviceT* deviceOf(MBRTAccel a) { return a && a->tag == kAccelTag ? a->scene->device : nullptr; }
inline MBRTDeviceT* deviceOf(MBRTAnimation a) { return a && a->tag == kAnimationTag ? a->device : nullptr; }

inline void checkDevice(MBRTDevice d) { require(d && d->tag == kDeviceTag, "NULL or invalid device handle"); }
inline void checkScene(MBRTScene s) { require(s && s->tag == kSceneTag, "NULL or invalid scene handle"); }
inline void checkAccel(MBRTAccel a) { require(a && a->tag == kAccelTag, "NULL or invalid accel handle"); }
inline void checkAnimation(MBRTAnimation a) {
  require(a && a->tag == kAnimationTag, "NULL or invalid animation handle");
}

// The structure of an accel that may be traced: not left without one by a
// failed update, and not stale (an animation's frame changed its scene
// since the last build or update).
inline const mbrt::Accel& traced(MBRTAccel a) {
  checkAccel(a);
  if (!a->accel)
    fail(MBRT_ERROR_INVALID_OPERATION, "the accel's last update failed: update it again (mbrtUpdateAccel)");
  if (a->sceneVersion != a->scene->data->scene->version())
    fail(MBRT_ERROR_INVALID_OPERATION,
         "the animation's scene changed (mbrtSetAnimationFrame) since the accel was built or updated: call "
         "mbrtUpdateAccel first");
  return *a->accel;
}

inline std::vector<std::vector<mbrt::Vec3f>> copySteps(const MBRTVertexBuffer* steps, uint32_t numSteps) {
  require(steps != nullptr, "steps is NULL");
  require(numSteps >= 1, "numSteps must be at least 1");
  std::vector<std::vector<mbrt::Vec3f>> out(numSteps);
  for (uint32_t k = 0; k < numSteps; ++k) {
    const MBRTVertexBuffer& b = steps[k];
    if (b.count > 0 && !b.data) fail(MBRT_ERROR_INVALID_ARGUMENT, "vertex step " + std::to_string(k) + " has NULL data");
    if (b.stride < 3 * sizeof(float))
      fail(MBRT_ERROR_INVALID_ARGUMENT, "vertex step " + std::to_string(k) + " has a stride below 12 bytes");
    if (b.count != steps[0].count)
      fail(MBRT_ERROR_INVALID_ARGUMENT, "vertex step " + std::to_string(k) + " has " + std::to_string(b.count) +
                                            " vertices, step 0 has " + std::to_string(steps[0].count));
    out[k].resize(b.count);
    for (size_t i = 0; i < b.count; ++i)
      std::memcpy(&out[k][i], static_cast<const char*>(b.data) + i * b.stride, sizeof(mbrt::Vec3f));
  }
  return out;
}

// True when `target` is `from` or a scene `from` instances, at any depth.
inline bool reaches(const SceneData& from, const SceneData* target) {
  if (&from == target) return true;
  for (const auto& c : from.children)
    if (reaches(*c, target)) return true;
  return false;
}

// Adds `delta` to the users of a scene and of every scene it instances.
inline void addUsers(SceneData& data, int64_t delta) {
  data.users.fetch_add(uint64_t(delta));
  for (const auto& c : data.children) addUsers(*c, delta);
}

// Accels hold on to the scene's geometry: a scene traced by a live accel is
// frozen.
inline void checkMutable(const MBRTSceneT& scene) {
  if (scene.animation)
    fail(MBRT_ERROR_INVALID_OPERATION, "the scene belongs to an animation: only its frames change it");
  uint64_t users = scene.data->users.load();
  if (users)
    fail(MBRT_ERROR_INVALID_OPERATION, "the scene is traced by " + std::to_string(users) +
                                           " live accel(s) (directly or through instances); release them first");
}

inline void checkGeometry(const MBRTSceneT& scene, uint32_t geomID) {
  if (geomID >= scene.data->scene->numGeometries())
    fail(MBRT_ERROR_INVALID_ARGUMENT, "geometry id " + std::to_string(geomID) + " out of range (the scene has " +
                                          std::to_string(scene.data->scene->numGeometries()) + ")");
}

inline mbrt::TimeRange timeRange(float time0, float time1) {
  require(std::isfinite(time0) && std::isfinite(time1) && 0.0f <= time0 && time0 <= time1 && time1 <= 1.0f,
          "time range must satisfy 0 <= time0 <= time1 <= 1");
  return {time0, time1};
}

// The names of the kinds this build can construct, as NUL-terminated
// strings that live as long as the library (mbrtGetKindName hands them out).
inline const std::vector<std::string>& kindNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (auto k : mbrt::availableAccelKinds()) out.emplace_back(mbrt::toString(k));
    return out;
  }();
  return names;
}

inline mbrt::Ray toRay(const MBRTRay& r) {
  mbrt::Ray ray;
  ray.org = {r.org[0], r.org[1], r.org[2]};
  ray.tnear = r.tnear;
  ray.dir = {r.dir[0], r.dir[1], r.dir[2]};
  ray.tfar = r.tfar;
  ray.time = r.time;
  ray.mask = r.mask;
  return ray;
}

inline MBRTRay fromRay(const mbrt::Ray& r) {
  MBRTRay out;
  out.org[0] = r.org.x, out.org[1] = r.org.y, out.org[2] = r.org.z;
  out.tnear = r.tnear;
  out.dir[0] = r.dir.x, out.dir[1] = r.dir.y, out.dir[2] = r.dir.z;
  out.tfar = r.tfar;
  out.time = r.time;
  out.mask = r.mask;
  return out;
}

inline void toHit(const mbrt::Hit& h, MBRTHit& out) {
  out.t = h.t;
  out.u = h.u;
  out.v = h.v;
  out.ng[0] = h.Ng.x;
  out.ng[1] = h.Ng.y;
  out.ng[2] = h.Ng.z;
  out.geomID = h.geomID;
  out.primID = h.primID;
  out.instID = h.instID;
}

inline void missHit(MBRTHit* hit) {
  if (!hit) return;
  toHit(mbrt::Hit{}, *hit);
}

}  // namespace mbrt::capi

