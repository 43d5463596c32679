// Instance transforms: Embree's matrix formats, quaternion decompositions
// and how they become mbrt instance keys.
//
// Embree interpolates matrix keys element-wise (as mbrt does) and a
// quaternion decomposition M = T * R * S per step by lerping T and the
// upper-triangular S (scale, skew, shift) and slerping R. Without skew or
// shift (and with scales that keep their signs) that is an mbrt SRT key;
// otherwise the instance becomes two mbrt instances: SRT keys (T, R, unit
// scale) over a scene holding one instance with the S matrices as
// element-wise keys, the same motion exactly.
#pragma once

#include <memory>
#include <string>

#include "geometry.h"
#include "mbrt/scene.h"
#include "snapshot.h"

namespace mbrt::embree_api {

// rtcSetGeometryTransform's formats; fails with Embree's error otherwise.
Affine3f loadTransform(RTCFormat format, const float* m);
void storeTransform(const Affine3f& a, RTCFormat format, float* m);

// The upper-triangular S of a decomposition: scale, skew and shift.
Affine3f scaleSkewShift(const RTCQuaternionDecomposition& d);
// T * R * S of a decomposition (at one step).
Affine3f decompositionMatrix(const RTCQuaternionDecomposition& d);

// The transform of instance g at `time` (rtcGetGeometryTransform).
Affine3f transformAt(const Geometry& g, float time);

// Adds instance g over `child` to `scene`: sets `id` and `path` (the mbrt
// instance geometries a ray passes), or returns false with the reason
// (singular or non-finite keys, matrix and quaternion keys mixed).
bool addInstance(mbrt::Scene& scene, const Geometry& g, std::shared_ptr<const mbrt::Scene> child, uint32_t& id,
                 InstancePath& path, std::string& error);

}  // namespace mbrt::embree_api
