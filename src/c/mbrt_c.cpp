// The C API (mbrt/mbrt.h) over the C++ API: handles with a checked tag,
// every exception turned into an error code and message on the device.
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
#include "mbrt/build_options.h"
#include "mbrt/error.h"
#include "mbrt/quaternion.h"
#include "mbrt/scene.h"

namespace {

// Tags at the start of every handle. Cleared on release, so that a released
// handle whose memory was not reused is refused too.
constexpr uint32_t kDeviceTag = 0x4d424456u;  // "MBDV"
constexpr uint32_t kSceneTag = 0x4d425343u;   // "MBSC"
constexpr uint32_t kAccelTag = 0x4d424143u;   // "MBAC"

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
thread_local ErrorSlot tNoDeviceError;
thread_local std::string tReturnedMessage;

}  // namespace

struct MBRTDeviceT {
  uint32_t tag = kDeviceTag;
  std::mutex mutex;  // guards error and callback: errors may come from tracing threads
  ErrorSlot error;
  MBRTErrorCallback callback = nullptr;
  void* userPtr = nullptr;
  std::atomic<uint64_t> liveScenes{0};
};

namespace {
// A scene and what the C layer knows of it. Shared: instances in other
// scenes keep it alive after its handle is released.
struct SceneData {
  mbrt::Scene scene;
  std::vector<std::shared_ptr<SceneData>> children;  // the scenes it instances
  // Live accels that trace this scene, directly or through instances:
  // while nonzero the scene may not change.
  std::atomic<uint64_t> users{0};
};
}  // namespace

struct MBRTSceneT {
  uint32_t tag = kSceneTag;
  MBRTDeviceT* device;
  std::shared_ptr<SceneData> data = std::make_shared<SceneData>();
  std::atomic<uint64_t> liveAccels{0};  // accels built on this scene itself
};

struct MBRTAccelT {
  uint32_t tag = kAccelTag;
  MBRTSceneT* scene;
  std::unique_ptr<mbrt::Accel> accel;
};

namespace {

void record(MBRTDeviceT* device, MBRTError code, const std::string& message) {
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

[[noreturn]] void fail(MBRTError code, std::string message) { throw CError{code, std::move(message)}; }

void require(bool ok, const char* what) {
  if (!ok) fail(MBRT_ERROR_INVALID_ARGUMENT, what);
}

// Handle checks. The device of a bad handle is unknown: such errors go to
// the thread's no-device slot.
MBRTDeviceT* deviceOf(MBRTDevice d) { return d && d->tag == kDeviceTag ? d : nullptr; }
MBRTDeviceT* deviceOf(MBRTScene s) { return s && s->tag == kSceneTag ? s->device : nullptr; }
MBRTDeviceT* deviceOf(MBRTAccel a) { return a && a->tag == kAccelTag ? a->scene->device : nullptr; }

void checkDevice(MBRTDevice d) { require(d && d->tag == kDeviceTag, "NULL or invalid device handle"); }
void checkScene(MBRTScene s) { require(s && s->tag == kSceneTag, "NULL or invalid scene handle"); }
void checkAccel(MBRTAccel a) { require(a && a->tag == kAccelTag, "NULL or invalid accel handle"); }

std::vector<std::vector<mbrt::Vec3f>> copySteps(const MBRTVertexBuffer* steps, uint32_t numSteps) {
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
bool reaches(const SceneData& from, const SceneData* target) {
  if (&from == target) return true;
  for (const auto& c : from.children)
    if (reaches(*c, target)) return true;
  return false;
}

// Adds `delta` to the users of a scene and of every scene it instances.
void addUsers(SceneData& data, int64_t delta) {
  data.users.fetch_add(uint64_t(delta));
  for (const auto& c : data.children) addUsers(*c, delta);
}

// Accels hold on to the scene's geometry: a scene traced by a live accel is
// frozen.
void checkMutable(const MBRTSceneT& scene) {
  uint64_t users = scene.data->users.load();
  if (users)
    fail(MBRT_ERROR_INVALID_OPERATION, "the scene is traced by " + std::to_string(users) +
                                           " live accel(s) (directly or through instances); release them first");
}

void checkGeometry(const MBRTSceneT& scene, uint32_t geomID) {
  if (geomID >= scene.data->scene.numGeometries())
    fail(MBRT_ERROR_INVALID_ARGUMENT, "geometry id " + std::to_string(geomID) + " out of range (the scene has " +
                                          std::to_string(scene.data->scene.numGeometries()) + ")");
}

mbrt::TimeRange timeRange(float time0, float time1) {
  require(std::isfinite(time0) && std::isfinite(time1) && 0.0f <= time0 && time0 <= time1 && time1 <= 1.0f,
          "time range must satisfy 0 <= time0 <= time1 <= 1");
  return {time0, time1};
}

// The names of the kinds this build can construct, as NUL-terminated
// strings that live as long as the library (mbrtGetKindName hands them out).
const std::vector<std::string>& kindNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> out;
    for (auto k : mbrt::availableAccelKinds()) out.emplace_back(mbrt::toString(k));
    return out;
  }();
  return names;
}

mbrt::Ray toRay(const MBRTRay& r) {
  mbrt::Ray ray;
  ray.org = {r.org[0], r.org[1], r.org[2]};
  ray.tnear = r.tnear;
  ray.dir = {r.dir[0], r.dir[1], r.dir[2]};
  ray.tfar = r.tfar;
  ray.time = r.time;
  ray.mask = r.mask;
  return ray;
}

MBRTRay fromRay(const mbrt::Ray& r) {
  MBRTRay out;
  out.org[0] = r.org.x, out.org[1] = r.org.y, out.org[2] = r.org.z;
  out.tnear = r.tnear;
  out.dir[0] = r.dir.x, out.dir[1] = r.dir.y, out.dir[2] = r.dir.z;
  out.tfar = r.tfar;
  out.time = r.time;
  out.mask = r.mask;
  return out;
}

void toHit(const mbrt::Hit& h, MBRTHit& out) {
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

void missHit(MBRTHit* hit) {
  if (!hit) return;
  toHit(mbrt::Hit{}, *hit);
}

}  // namespace

extern "C" {

int mbrtGetVersion(int* major, int* minor, int* patch) {
  if (major) *major = MBRT_VERSION_MAJOR;
  if (minor) *minor = MBRT_VERSION_MINOR;
  if (patch) *patch = MBRT_VERSION_PATCH;
  return MBRT_VERSION;
}

MBRTDevice mbrtNewDevice(void) {
  return guarded<MBRTDevice>(nullptr, nullptr, "mbrtNewDevice", [] { return new MBRTDeviceT; });
}

void mbrtReleaseDevice(MBRTDevice device) {
  guarded(deviceOf(device), 0, "mbrtReleaseDevice", [&] {
    checkDevice(device);
    uint64_t live = device->liveScenes.load();
    if (live)
      fail(MBRT_ERROR_INVALID_OPERATION,
           "the device has " + std::to_string(live) + " live scene(s); release them first");
    device->tag = 0;
    delete device;
    return 0;
  });
}

void mbrtSetErrorCallback(MBRTDevice device, MBRTErrorCallback callback, void* userPtr) {
  guarded(deviceOf(device), 0, "mbrtSetErrorCallback", [&] {
    checkDevice(device);
    std::lock_guard<std::mutex> lock(device->mutex);
    device->callback = callback;
    device->userPtr = userPtr;
    return 0;
  });
}

MBRTError mbrtGetError(MBRTDevice device, const char** message) {
  // Allocates nothing, so it cannot fail: the strings are moved.
  if (device && device->tag != kDeviceTag) {
    if (message) *message = "mbrtGetError: invalid device handle";
    return MBRT_ERROR_INVALID_ARGUMENT;
  }
  ErrorSlot taken;
  if (!device) {
    std::swap(taken, tNoDeviceError);
  } else {
    std::lock_guard<std::mutex> lock(device->mutex);
    std::swap(taken, device->error);
  }
  tReturnedMessage = std::move(taken.message);
  if (message) *message = tReturnedMessage.c_str();
  return taken.code;
}

MBRTScene mbrtNewScene(MBRTDevice device) {
  return guarded<MBRTScene>(deviceOf(device), nullptr, "mbrtNewScene", [&] {
    checkDevice(device);
    auto* s = new MBRTSceneT;
    s->device = device;
    device->liveScenes.fetch_add(1);
    return s;
  });
}

void mbrtReleaseScene(MBRTScene scene) {
  guarded(deviceOf(scene), 0, "mbrtReleaseScene", [&] {
    checkScene(scene);
    uint64_t live = scene->liveAccels.load();
    if (live)
      fail(MBRT_ERROR_INVALID_OPERATION,
           "the scene has " + std::to_string(live) + " live accel(s) built on it; release them first");
    scene->device->liveScenes.fetch_sub(1);
    scene->tag = 0;
    delete scene;
    return 0;
  });
}

uint32_t mbrtNewTriangleMesh(MBRTScene scene, const uint32_t* indices, size_t numTriangles,
                             const MBRTVertexBuffer* steps, uint32_t numSteps, float time0, float time1) {
  return guarded<uint32_t>(deviceOf(scene), MBRT_INVALID_ID, "mbrtNewTriangleMesh", [&] {
    checkScene(scene);
    require(indices || numTriangles == 0, "indices is NULL");
    mbrt::TimeRange range = timeRange(time0, time1);
    auto vertexSteps = copySteps(steps, numSteps);
    std::vector<mbrt::Triangle> triangles(numTriangles);
    for (size_t i = 0; i < numTriangles; ++i) triangles[i] = {indices[3 * i], indices[3 * i + 1], indices[3 * i + 2]};
    checkMutable(*scene);
    return scene->data->scene.addTriangleMesh(std::move(triangles), std::move(vertexSteps), range);
  });
}

uint32_t mbrtNewSegments(MBRTScene scene, const uint32_t* indices, size_t numSegments, const MBRTVertexBuffer* steps,
                         uint32_t numSteps, const float* radii, float time0, float time1) {
  return guarded<uint32_t>(deviceOf(scene), MBRT_INVALID_ID, "mbrtNewSegments", [&] {
    checkScene(scene);
    require(indices || numSegments == 0, "indices is NULL");
    mbrt::TimeRange range = timeRange(time0, time1);
    auto vertexSteps = copySteps(steps, numSteps);
    require(radii || vertexSteps[0].empty(), "radii is NULL");
    std::vector<float> r(radii, radii + vertexSteps[0].size());
    std::vector<mbrt::Segment> segments(numSegments);
    for (size_t i = 0; i < numSegments; ++i) segments[i] = {indices[2 * i], indices[2 * i + 1]};
    checkMutable(*scene);
    return scene->data->scene.addSegments(std::move(segments), std::move(vertexSteps), std::move(r), range);
  });
}

}  // extern "C"

namespace {

// Checks what every instance needs and adds it: `add` adds the instance of
// the child's scene to the C++ scene and returns its id.
template <class Add>
uint32_t addInstanceOf(MBRTScene scene, MBRTScene child, const void* keys, uint32_t numKeys, float time0,
                       float time1, Add&& add) {
  checkScene(scene);
  require(child && child->tag == kSceneTag, "NULL or invalid child scene handle");
  require(child->device == scene->device, "the child scene belongs to another device");
  require(child != scene, "a scene cannot instance itself");
  require(keys != nullptr, "keys is NULL");
  require(numKeys >= 1, "numKeys must be at least 1");
  mbrt::TimeRange range = timeRange(time0, time1);
  // A cycle would keep the scenes alive forever (shared ownership) and
  // could never be built: refused here rather than at the build.
  if (reaches(*child->data, scene->data.get()))
    fail(MBRT_ERROR_INVALID_ARGUMENT, "the child scene instances this scene (an instance cycle)");
  checkMutable(*scene);
  uint32_t id = add(std::shared_ptr<const mbrt::Scene>(child->data, &child->data->scene), range);
  scene->data->children.push_back(child->data);
  return id;
}

}  // namespace

extern "C" {

uint32_t mbrtNewInstance(MBRTScene scene, MBRTScene child, const float* keys, uint32_t numKeys, float time0,
                         float time1) {
  return guarded<uint32_t>(deviceOf(scene), MBRT_INVALID_ID, "mbrtNewInstance", [&] {
    return addInstanceOf(scene, child, keys, numKeys, time0, time1, [&](auto childScene, mbrt::TimeRange range) {
      std::vector<mbrt::Affine3f> transforms(numKeys);
      for (uint32_t k = 0; k < numKeys; ++k) {
        const float* m = keys + 12 * size_t(k);  // row-major 3x4: columns are the images of the axes
        mbrt::Affine3f& a = transforms[k];
        a.vx = {m[0], m[4], m[8]};
        a.vy = {m[1], m[5], m[9]};
        a.vz = {m[2], m[6], m[10]};
        a.p = {m[3], m[7], m[11]};
      }
      return scene->data->scene.addInstance(std::move(childScene), std::move(transforms), range);
    });
  });
}

uint32_t mbrtNewInstanceSRT(MBRTScene scene, MBRTScene child, const MBRTSRTKey* keys, uint32_t numKeys,
                            float time0, float time1) {
  return guarded<uint32_t>(deviceOf(scene), MBRT_INVALID_ID, "mbrtNewInstanceSRT", [&] {
    return addInstanceOf(scene, child, keys, numKeys, time0, time1, [&](auto childScene, mbrt::TimeRange range) {
      std::vector<mbrt::SRTKey> srt(numKeys);
      for (uint32_t k = 0; k < numKeys; ++k) {
        const MBRTSRTKey& c = keys[k];
        srt[k].scale = {c.scale[0], c.scale[1], c.scale[2]};
        srt[k].rotation = {c.rotation[0], c.rotation[1], c.rotation[2], c.rotation[3]};
        srt[k].translation = {c.translation[0], c.translation[1], c.translation[2]};
      }
      return scene->data->scene.addInstance(std::move(childScene), std::move(srt), range);
    });
  });
}

void mbrtSetGeometryFilter(MBRTScene scene, uint32_t geomID, MBRTFilterFunc filter, void* userPtr) {
  guarded(deviceOf(scene), 0, "mbrtSetGeometryFilter", [&] {
    checkScene(scene);
    checkGeometry(*scene, geomID);
    if (scene->data->scene.geometry(geomID).type() == mbrt::GeometryType::Instance)
      fail(MBRT_ERROR_INVALID_ARGUMENT, "geometry " + std::to_string(geomID) +
                                            " is an instance: filters belong to triangle and segment geometries");
    checkMutable(*scene);
    if (!filter) {
      scene->data->scene.setFilter(geomID, {}, nullptr);
      return 0;
    }
    scene->data->scene.setFilter(
        geomID,
        [filter](const mbrt::FilterArgs& args) {
          MBRTRay ray = fromRay(args.ray);
          MBRTHit hit;
          toHit(args.candidate, hit);
          return filter(args.userData, &ray, &hit) != 0;
        },
        userPtr);
    return 0;
  });
}

void mbrtSetGeometryMask(MBRTScene scene, uint32_t geomID, uint32_t mask) {
  guarded(deviceOf(scene), 0, "mbrtSetGeometryMask", [&] {
    checkScene(scene);
    checkGeometry(*scene, geomID);
    checkMutable(*scene);
    scene->data->scene.setMask(geomID, mask);
    return 0;
  });
}

uint32_t mbrtGetGeometryCount(MBRTScene scene) {
  return guarded<uint32_t>(deviceOf(scene), 0, "mbrtGetGeometryCount", [&] {
    checkScene(scene);
    return scene->data->scene.numGeometries();
  });
}

uint32_t mbrtGetKindCount(void) {
  return guarded<uint32_t>(nullptr, 0, "mbrtGetKindCount", [] { return uint32_t(kindNames().size()); });
}

const char* mbrtGetKindName(uint32_t index) {
  return guarded<const char*>(nullptr, nullptr, "mbrtGetKindName", [&]() -> const char* {
    const auto& names = kindNames();
    if (index >= names.size())
      fail(MBRT_ERROR_INVALID_ARGUMENT, "kind index " + std::to_string(index) + " out of range (" +
                                            std::to_string(names.size()) + " kinds)");
    return names[index].c_str();
  });
}

void mbrtDefaultBuildOptions(MBRTBuildOptions* options) {
  guarded(nullptr, 0, "mbrtDefaultBuildOptions", [&] {
    require(options != nullptr, "options is NULL");
    mbrt::BuildOptions d;
    options->branching = d.branching;
    options->maxLeafSize = d.maxLeafSize;
    options->sahBins = d.sahBins;
    options->traversalCost = d.traversalCost;
    options->frozenTime = d.frozenTime;
    options->memoryBudget = d.memoryBudget;
    options->maxInstanceDepth = d.maxInstanceDepth;
    return 0;
  });
}

MBRTAccel mbrtNewAccel(MBRTScene scene, const char* kind, const MBRTBuildOptions* options) {
  return guarded<MBRTAccel>(deviceOf(scene), nullptr, "mbrtNewAccel", [&] {
    checkScene(scene);
    require(kind != nullptr, "kind is NULL");
    auto parsed = mbrt::parseAccelKind(kind);
    if (!parsed) {
      std::string names;
      for (const auto& k : kindNames()) names += (names.empty() ? "" : ", ") + k;
      fail(MBRT_ERROR_INVALID_ARGUMENT, std::string("unknown kind \"") + kind + "\" (kinds: " + names + ")");
    }
    mbrt::BuildOptions o;
    o.kind = *parsed;
    if (options) {
      o.branching = options->branching;
      o.maxLeafSize = options->maxLeafSize;
      o.sahBins = options->sahBins;
      o.traversalCost = options->traversalCost;
      o.frozenTime = options->frozenTime;
      o.memoryBudget = options->memoryBudget;
      o.maxInstanceDepth = options->maxInstanceDepth;
    }
    auto a = std::make_unique<MBRTAccelT>();
    a->scene = scene;
    a->accel = mbrt::Accel::build(scene->data->scene, o);
    scene->liveAccels.fetch_add(1);
    addUsers(*scene->data, 1);
    return a.release();
  });
}

void mbrtReleaseAccel(MBRTAccel accel) {
  guarded(deviceOf(accel), 0, "mbrtReleaseAccel", [&] {
    checkAccel(accel);
    accel->scene->liveAccels.fetch_sub(1);
    addUsers(*accel->scene->data, -1);
    accel->tag = 0;
    delete accel;
    return 0;
  });
}

int mbrtGetAccelStats(MBRTAccel accel, MBRTAccelStats* stats) {
  return guarded(deviceOf(accel), 0, "mbrtGetAccelStats", [&] {
    checkAccel(accel);
    require(stats != nullptr, "stats is NULL");
    mbrt::AccelStats s = accel->accel->stats();
    std::memset(stats, 0, sizeof(*stats));
    std::strncpy(stats->kind, s.kind.c_str(), sizeof(stats->kind) - 1);
    stats->primitives = s.primitives;
    stats->references = s.references;
    stats->innerNodes = s.innerNodes;
    stats->leafNodes = s.leafNodes;
    stats->maxDepth = s.maxDepth;
    stats->bytes = s.bytes;
    stats->peakBuildBytes = s.peakBuildBytes;
    stats->sahCost = s.sahCost;
    stats->buildSeconds = s.buildSeconds;
    stats->invalidRays = s.invalidRays;
    return 1;
  });
}

int mbrtIntersect1(MBRTAccel accel, const MBRTRay* ray, MBRTHit* hit) {
  return guarded(deviceOf(accel), (missHit(hit), 0), "mbrtIntersect1", [&] {
    checkAccel(accel);
    require(ray != nullptr, "ray is NULL");
    require(hit != nullptr, "hit is NULL");
    mbrt::Hit h;
    bool found = accel->accel->intersect(toRay(*ray), h);
    toHit(h, *hit);
    return found ? 1 : 0;
  });
}

int mbrtOccluded1(MBRTAccel accel, const MBRTRay* ray) {
  return guarded(deviceOf(accel), 0, "mbrtOccluded1", [&] {
    checkAccel(accel);
    require(ray != nullptr, "ray is NULL");
    return accel->accel->occluded(toRay(*ray)) ? 1 : 0;
  });
}

int mbrtIntersectM(MBRTAccel accel, const MBRTRay* rays, MBRTHit* hits, size_t count) {
  return guarded(deviceOf(accel), 0, "mbrtIntersectM", [&] {
    checkAccel(accel);
    require(count == 0 || (rays && hits), "rays or hits is NULL");
    const mbrt::Accel& a = *accel->accel;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) {
        mbrt::Hit h;
        a.intersect(toRay(rays[i]), h);
        toHit(h, hits[i]);
      }
    });
    return 1;
  });
}

int mbrtOccludedM(MBRTAccel accel, const MBRTRay* rays, uint8_t* occluded, size_t count) {
  return guarded(deviceOf(accel), 0, "mbrtOccludedM", [&] {
    checkAccel(accel);
    require(count == 0 || (rays && occluded), "rays or occluded is NULL");
    const mbrt::Accel& a = *accel->accel;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i < r.end(); ++i) occluded[i] = a.occluded(toRay(rays[i])) ? 1 : 0;
    });
    return 1;
  });
}

}  // extern "C"
