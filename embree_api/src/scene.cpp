// RTCScene: the geometry table, flags, build quality, the progress monitor,
// reference counting.
#include "scene.h"

#include "device.h"
#include "errors.h"

namespace mbrt::embree_api {

Scene::Scene(Device* device) : Object(Tag::Scene, device) {}

Scene::~Scene() {
  if (current_ && current_->monitoredBytes) device()->monitorMemory(-current_->monitoredBytes);
}

uint32_t Scene::attach(Geometry& g) {
  uint32_t id;
  if (!freeIds_.empty()) {
    id = *freeIds_.begin();
    freeIds_.erase(freeIds_.begin());
  } else {
    id = uint32_t(geometries_.size());
    geometries_.emplace_back();
  }
  geometries_[id] = &g;
  tableChanged_ = true;
  return id;
}

void Scene::attachAt(Geometry& g, uint32_t id) {
  if (id == RTC_INVALID_GEOMETRY_ID) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: geomID");
  if (id < geometries_.size() && geometries_[id]) fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry ID provided: it is taken");
  if (id >= geometries_.size()) {
    for (uint32_t i = uint32_t(geometries_.size()); i < id; ++i) freeIds_.insert(i);
    geometries_.resize(size_t(id) + 1);
  }
  freeIds_.erase(id);
  geometries_[id] = &g;
  tableChanged_ = true;
}

void Scene::detach(uint32_t id) {
  if (!geometry(id)) fail(RTC_ERROR_INVALID_OPERATION, "invalid geometry ID " + std::to_string(id));
  geometries_[id] = Ref<Geometry>();
  freeIds_.insert(id);
  tableChanged_ = true;
}

std::shared_ptr<const Committed> Scene::committedShared() const {
  std::lock_guard<std::mutex> lock(commitMutex_);
  return current_;
}

bool Scene::modifiedSinceCommit() const {
  if (tableChanged_ || !committed()) return true;
  for (uint32_t id = 0; id < geometries_.size(); ++id) {
    const Geometry* g = geometries_[id].get();
    if (!g) continue;
    if (id >= committedStates_.size() || !(committedStates_[id] == stateOf(*g))) return true;
  }
  return false;
}

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

namespace {

Scene& sceneOf(RTCScene s) { return require<Scene>(s, "RTCScene"); }

}  // namespace

RTC_API RTCScene rtcNewScene(RTCDevice device) {
  return guarded("rtcNewScene", device, RTCScene(nullptr), [&] {
    return reinterpret_cast<RTCScene>(new Scene(&require<Device>(device, "RTCDevice")));
  });
}

RTC_API RTCDevice rtcGetSceneDevice(RTCScene scene) {
  return guarded("rtcGetSceneDevice", scene, RTCDevice(nullptr), [&] {
    Device* d = sceneOf(scene).device();
    d->retain();  // the caller owns one more reference, as with Embree
    return reinterpret_cast<RTCDevice>(d);
  });
}

RTC_API void rtcRetainScene(RTCScene scene) {
  guarded("rtcRetainScene", scene, [&] { sceneOf(scene).retain(); });
}

RTC_API void rtcReleaseScene(RTCScene scene) {
  guarded("rtcReleaseScene", scene, [&] { sceneOf(scene).release(); });
}

RTC_API unsigned int rtcAttachGeometry(RTCScene scene, RTCGeometry geometry) {
  return guarded("rtcAttachGeometry", scene, unsigned(RTC_INVALID_GEOMETRY_ID), [&] {
    Scene& s = sceneOf(scene);
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    if (s.device() != g.device()) fail(RTC_ERROR_INVALID_ARGUMENT, "inputs are from different devices");
    return unsigned(s.attach(g));
  });
}

RTC_API void rtcAttachGeometryByID(RTCScene scene, RTCGeometry geometry, unsigned int geomID) {
  guarded("rtcAttachGeometryByID", scene, [&] {
    Scene& s = sceneOf(scene);
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    if (s.device() != g.device()) fail(RTC_ERROR_INVALID_ARGUMENT, "inputs are from different devices");
    s.attachAt(g, geomID);
  });
}

RTC_API void rtcDetachGeometry(RTCScene scene, unsigned int geomID) {
  guarded("rtcDetachGeometry", scene, [&] { sceneOf(scene).detach(geomID); });
}

RTC_API RTCGeometry rtcGetGeometry(RTCScene scene, unsigned int geomID) {
  // No reference is added (as in Embree); called from hit shading, so kept cheap.
  const Scene* s = objectOf<Scene>(scene);
  if (s) return reinterpret_cast<RTCGeometry>(s->geometry(geomID));
  return guarded("rtcGetGeometry", scene, RTCGeometry(nullptr), [&] {
    sceneOf(scene);
    return RTCGeometry(nullptr);
  });
}

RTC_API RTCGeometry rtcGetGeometryThreadSafe(RTCScene scene, unsigned int geomID) {
  return rtcGetGeometry(scene, geomID);
}

RTC_API void rtcSetSceneFlags(RTCScene scene, RTCSceneFlags flags) {
  guarded("rtcSetSceneFlags", scene, [&] { sceneOf(scene).flags = flags; });
}

RTC_API RTCSceneFlags rtcGetSceneFlags(RTCScene scene) {
  return guarded("rtcGetSceneFlags", scene, RTC_SCENE_FLAG_NONE, [&] { return sceneOf(scene).flags; });
}

RTC_API void rtcSetSceneBuildQuality(RTCScene scene, RTCBuildQuality quality) {
  guarded("rtcSetSceneBuildQuality", scene, [&] {
    Scene& s = sceneOf(scene);
    const auto q = passedValue(quality);
    if (q != RTC_BUILD_QUALITY_LOW && q != RTC_BUILD_QUALITY_MEDIUM && q != RTC_BUILD_QUALITY_HIGH)
      fail(RTC_ERROR_INVALID_ARGUMENT, "invalid build quality");
    s.buildQuality = quality;  // mbrt's kind decides how it builds
  });
}

RTC_API void rtcSetSceneProgressMonitorFunction(RTCScene scene, RTCProgressMonitorFunction progress, void* ptr) {
  guarded("rtcSetSceneProgressMonitorFunction", scene, [&] {
    Scene& s = sceneOf(scene);
    s.progress = progress;
    s.progressUserPtr = ptr;
  });
}
