// RTCGeometry: triangle meshes, quad meshes and instances, as the caller
// describes them (buffers, time steps and range, mask, user data, filter
// functions, instance keys). A scene commit reads them into mbrt's scene
// model (snapshot.h). Other geometry types are refused by rtcNewGeometry
// (with an inert placeholder handed out, see isPlaceholder).
#pragma once

#include <cstdint>
#include <vector>

#include "buffer.h"
#include "handles.h"
#include "mbrt/math.h"

namespace mbrt::embree_api {

class Scene;

// One time step of an instance: a matrix, or a quaternion decomposition
// (rtcSetGeometryTransformQuaternion).
struct InstanceKey {
  bool quaternion = false;
  Affine3f matrix;
  RTCQuaternionDecomposition decomposition{};
};

class Geometry final : public Object {
 public:
  static constexpr Tag kTag = Tag::Geometry;
  Geometry(Device* device, RTCGeometryType type);
  ~Geometry() override;

  RTCGeometryType type() const { return type_; }
  bool isMesh() const { return type_ == RTC_GEOMETRY_TYPE_TRIANGLE || type_ == RTC_GEOMETRY_TYPE_QUAD; }
  bool isInstance() const { return type_ == RTC_GEOMETRY_TYPE_INSTANCE; }
  // A geometry of a type mbrt does not have (user, subdivision, curves,
  // points, grids): rtcNewGeometry reported the error and handed out this
  // inert stand-in, so that a program going on regardless does not crash;
  // its setters do nothing, its new buffers are scratch memory, and scene
  // commits leave it out.
  bool isPlaceholder() const { return !isMesh() && !isInstance(); }
  // Scratch memory given out for a placeholder's buffers, by type and slot
  // (rtcGetGeometryBufferData hands the latest one back).
  struct Scratch {
    RTCBufferType type;
    unsigned slot;
    Ref<Buffer> buffer;
  };
  std::vector<Scratch> scratch;
  // Index items per primitive: 3 (triangles) or 4 (quads).
  unsigned corners() const { return type_ == RTC_GEOMETRY_TYPE_QUAD ? 4 : 3; }

  // Time steps: resizes the vertex buffers (meshes) or keys (instances).
  void setTimeStepCount(uint32_t steps);
  uint32_t timeSteps() const { return timeSteps_; }

  // Bumped by changes that need a rebuild (topology, keys, masks, filters,
  // time) and by changes of vertex data only (which may refit).
  void changedTopology() { ++topologyVersion_; }
  void changedVertices() { ++vertexVersion_; }
  uint64_t topologyVersion() const { return topologyVersion_; }
  uint64_t vertexVersion() const { return vertexVersion_; }

  float timeStart = 0.0f, timeEnd = 1.0f;
  uint32_t mask = 0xFFFFFFFFu;
  void* userData = nullptr;
  RTCFilterFunctionN intersectFilter = nullptr;
  RTCFilterFunctionN occludedFilter = nullptr;
  RTCBuildQuality buildQuality = RTC_BUILD_QUALITY_MEDIUM;
  bool enabled = true;

  // Meshes.
  BufferView index;
  std::vector<BufferView> vertices;    // one per time step
  std::vector<BufferView> attributes;  // rtcSetGeometryVertexAttributeCount slots

  // Instances.
  Ref<Scene> instanced;
  std::vector<InstanceKey> keys;  // one per time step

 private:
  RTCGeometryType type_;
  uint32_t timeSteps_ = 1;
  uint64_t topologyVersion_ = 1, vertexVersion_ = 1;
};

}  // namespace mbrt::embree_api
