// Instance geometries: the instanced scene and one transform per time step,
// a matrix or a quaternion decomposition.
#include "device.h"
#include "errors.h"
#include "geometry.h"
#include "instance_keys.h"
#include "scene.h"

using namespace mbrt::embree_api;

namespace {

Geometry& instanceOf(RTCGeometry geometry) {
  Geometry& g = require<Geometry>(geometry, "RTCGeometry");
  if (!g.isInstance()) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  return g;
}

InstanceKey& keyOf(Geometry& g, unsigned int timeStep) {
  if (timeStep >= g.keys.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid timestep");
  return g.keys[timeStep];
}

}  // namespace

RTC_API void rtcSetGeometryInstancedScene(RTCGeometry geometry, RTCScene scene) {
  guarded("rtcSetGeometryInstancedScene", geometry, [&] {
    Geometry& g = instanceOf(geometry);
    Scene& s = require<Scene>(scene, "RTCScene");
    if (s.device() != g.device()) fail(RTC_ERROR_INVALID_ARGUMENT, "inputs are from different devices");
    g.instanced = &s;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryTransform(RTCGeometry geometry, unsigned int timeStep, RTCFormat format, const void* xfm) {
  guarded("rtcSetGeometryTransform", geometry, [&] {
    Geometry& g = instanceOf(geometry);
    if (!xfm) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null transform");
    const mbrt::Affine3f m = loadTransform(format, static_cast<const float*>(xfm));
    InstanceKey& k = keyOf(g, timeStep);
    k.quaternion = false;
    k.matrix = m;
    g.changedTopology();
  });
}

RTC_API void rtcSetGeometryTransformQuaternion(RTCGeometry geometry, unsigned int timeStep,
                                               const RTCQuaternionDecomposition* qd) {
  guarded("rtcSetGeometryTransformQuaternion", geometry, [&] {
    Geometry& g = instanceOf(geometry);
    if (!qd) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null quaternion decomposition");
    InstanceKey& k = keyOf(g, timeStep);
    k.quaternion = true;
    k.decomposition = *qd;
    k.matrix = decompositionMatrix(*qd);
    g.changedTopology();
  });
}

RTC_API void rtcGetGeometryTransform(RTCGeometry geometry, float time, RTCFormat format, void* xfm) {
  guarded("rtcGetGeometryTransform", geometry, [&] {
    Geometry& g = instanceOf(geometry);
    if (!xfm) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null transform");
    storeTransform(transformAt(g, time), format, static_cast<float*>(xfm));
  });
}
