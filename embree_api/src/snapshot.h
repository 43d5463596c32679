// An Embree scene as mbrt sees it at a commit: an mbrt::Scene of its
// enabled geometries (quads as two triangles each, invalid primitives left
// out, as Embree leaves them out of its BVH) and, per mbrt geometry, what
// maps a hit back to Embree's ids. Immutable once built, but for the
// vertex buffers a refit replaces (commit.cpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "buffer.h"
#include "geometry.h"
#include "mbrt/scene.h"

namespace mbrt::embree_api {

class Scene;
struct Snapshot;

// The mbrt instance geometries a ray passes on its way from world space to
// a mesh of an instanced scene (the second one for a quaternion key with
// skew or shift, instance_keys.cpp); filled in when the parent adds them.
struct InstancePath {
  const mbrt::Geometry* outer = nullptr;
  const mbrt::Geometry* inner = nullptr;
};

// Maps mbrt triangle i of a mesh to Embree's primitive and, for quads, the
// half it lies in: triangle (v0, v1, v3) or (v2, v3, v1).
struct PrimitiveMap {
  bool quads = false;
  std::shared_ptr<const std::vector<uint32_t>> kept;  // mbrt triangle -> 2*quad+half or triangle; null: identity

  uint32_t embreePrim(uint32_t i, bool& secondHalf) const {
    const uint32_t k = kept ? (*kept)[i] : i;
    secondHalf = quads && (k & 1u);
    return quads ? k >> 1 : k;
  }
};

// What a filter function call needs (filters.cpp).
struct FilterBinding {
  Ref<Geometry> geometry;  // its filter functions and user data
  const mbrt::Geometry* mesh = nullptr;
  uint32_t geomID = RTC_INVALID_GEOMETRY_ID;  // Embree's, in its scene
  uint32_t instID = RTC_INVALID_GEOMETRY_ID;  // the instance this copy is traced through
  std::shared_ptr<const InstancePath> path;   // null at the top level
  PrimitiveMap prims;
};

struct GeomEntry {
  uint32_t embreeID = RTC_INVALID_GEOMETRY_ID;
  PrimitiveMap prims;
  std::shared_ptr<const Snapshot> child;  // instances: where the hit's geomID lives
  const Snapshot* childSource = nullptr;  // the instanced scene's committed snapshot it was read from
  uint64_t childGeneration = 0;           // and that snapshot's generation then
  Ref<Geometry> geometry;
  uint64_t topologyVersion = 0, vertexVersion = 0;  // of the geometry when read
};

struct Snapshot {
  std::shared_ptr<mbrt::Scene> scene;  // null: nothing to trace
  std::vector<GeomEntry> entries;      // by mbrt geometry id
  std::vector<std::unique_ptr<FilterBinding>> bindings;
  std::vector<Ref<Buffer>> buffers;    // every buffer the mbrt scene points into
  bool hasFilters = false;             // some mbrt geometry calls filters.cpp
  uint64_t generation = 0;             // bumped by every refit of the vertex data
  Box3f bounds;                        // rtcGetSceneBounds
  LBounds linearBounds;                // rtcGetSceneLinearBounds
};

// How a scene is read: at its own commit (top level) or as the copy an
// instance traces when the instanced scene has filters (bound to that
// instance, so that the filter sees its instID).
struct SnapshotContext {
  uint32_t instID = RTC_INVALID_GEOMETRY_ID;
  std::shared_ptr<const InstancePath> path;
  bool contextFilter = false;  // RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION of the scene traced
};

// Reads `scene`; problems with one geometry (a missing buffer, a singular
// instance key, ...) leave it out and add a message to `errors`.
std::shared_ptr<Snapshot> buildSnapshot(const Scene& scene, const SnapshotContext& context,
                                        std::vector<std::string>& errors);

}  // namespace mbrt::embree_api
