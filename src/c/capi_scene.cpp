// The C API's version, devices, errors, scenes and geometry (mbrt/mbrt.h).
#include "c/handles.h"

using namespace mbrt::capi;

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
    if (scene->animation)
      fail(MBRT_ERROR_INVALID_OPERATION, "the scene belongs to an animation: it is released with it "
                                         "(mbrtReleaseAnimation)");
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
    return scene->data->scene->addTriangleMesh(std::move(triangles), std::move(vertexSteps), range);
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
    return scene->data->scene->addSegments(std::move(segments), std::move(vertexSteps), std::move(r), range);
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
  if (child->animation)
    fail(MBRT_ERROR_INVALID_OPERATION, "the child scene belongs to an animation: its frames cannot be instanced");
  uint32_t id = add(std::shared_ptr<const mbrt::Scene>(child->data, child->data->scene.get()), range);
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
      return scene->data->scene->addInstance(std::move(childScene), std::move(transforms), range);
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
      return scene->data->scene->addInstance(std::move(childScene), std::move(srt), range);
    });
  });
}

void mbrtSetGeometryFilter(MBRTScene scene, uint32_t geomID, MBRTFilterFunc filter, void* userPtr) {
  guarded(deviceOf(scene), 0, "mbrtSetGeometryFilter", [&] {
    checkScene(scene);
    checkGeometry(*scene, geomID);
    if (scene->data->scene->geometry(geomID).type() == mbrt::GeometryType::Instance)
      fail(MBRT_ERROR_INVALID_ARGUMENT, "geometry " + std::to_string(geomID) +
                                            " is an instance: filters belong to triangle and segment geometries");
    checkMutable(*scene);
    if (!filter) {
      scene->data->scene->setFilter(geomID, {}, nullptr);
      return 0;
    }
    scene->data->scene->setFilter(
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
    scene->data->scene->setMask(geomID, mask);
    return 0;
  });
}

uint32_t mbrtGetGeometryCount(MBRTScene scene) {
  return guarded<uint32_t>(deviceOf(scene), 0, "mbrtGetGeometryCount", [&] {
    checkScene(scene);
    return scene->data->scene->numGeometries();
  });
}

}  // extern "C"
