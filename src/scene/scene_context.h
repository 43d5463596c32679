// What a structure sees of a scene: its geometries, the primitives to index,
// their bounds over time, and the structures of instanced scenes (built
// recursively with the same options, once per distinct scene).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "core/build_budget.h"
#include "core/prim_ref.h"
#include "core/structure.h"
#include "scene/instance_space.h"
#include "mbrt/accel_stats.h"
#include "mbrt/build_options.h"
#include "mbrt/scene.h"

namespace mbrt::detail {

// The key boxes of one primitive: what keyBox gives, with the geometry and
// the primitive's vertices looked up once (Fig. 4 bounds read many keys).
struct PrimKeys {
  const Geometry* geometry;
  const float* stepTimes;  // Geometry::stepTime of each key (no division per key)
  const Box3f* instance;   // instances: their key boxes; else null
  uint32_t v[3];           // vertices (a segment repeats its second)
  float radius;            // segments: the larger vertex radius; else 0

  Box3f operator()(uint32_t key) const {
    if (instance) return instance[key];
    const VertexBuffer& vb = geometry->vertices(key);
    Box3f b(vb[v[0]]);
    b.extend(vb[v[1]]);
    b.extend(vb[v[2]]);
    return {b.lower - Vec3f(radius), b.upper + Vec3f(radius)};
  }
};

class SceneContext;

// Makes the structure of an instanced scene's context. The façade hands its
// kind registry down (accel/structure_factory.h), so that this layer never
// calls up into the kinds.
using StructureFactory = std::function<std::unique_ptr<Structure>(const SceneContext&)>;

class SceneContext {
 public:
  // makeChild builds the structures of instanced scenes; a scene with
  // instances and no factory is refused with an Error.
  SceneContext(const Scene& scene, const BuildOptions& options, BuildBudget& budget,
               const StructureFactory& makeChild = {});
  ~SceneContext();

  const Scene& scene() const { return *scene_; }
  const Geometry& geometry(uint32_t geomID) const { return *geometries_[geomID]; }
  const BuildOptions& options() const { return options_; }
  BuildBudget& budget() const { return *budget_; }
  // The factory of instanced scenes' structures: kinds that build
  // structures of other kinds over derived scenes (auto) use it too.
  const StructureFactory& structureFactory() const { return makeChild_; }

  // Every primitive of this level, in geometry then primitive order.
  std::vector<PrimRef> primitives() const;
  size_t numPrimitives() const { return numPrimitives_; }
  // Primitives at this level plus those of instanced scenes (counted once).
  size_t totalPrimitives() const;

  // The structure of an instance's scene.
  const Structure& child(uint32_t geomID) const { return *childOf_[geomID]; }
  // How an instance's ray is taken into its space (instance_space.h).
  const InstanceMotion& instanceMotion(uint32_t geomID) const { return instanceMotions_[geomID]; }
  // After new vertex data: refits the structures of instanced scenes (their
  // own instanced scenes first) and makes their bounds and this level's
  // instance key boxes again. False when one of them cannot refit.
  bool refitChildren();

  // Bounds, see primitive_bounds.h.
  Box3f keyBox(PrimRef ref, uint32_t key) const { return keys(ref)(key); }
  PrimKeys keys(PrimRef ref) const;
  // Replaces an instance's key boxes (one per key) by the caller's, before
  // any structure is built over this context. The caller guarantees what
  // the computed ones do: the lerp of consecutive boxes holds the instance
  // between its keys (auto: the boxes of the mesh an instance was fitted to,
  // auto/part_bounds.h).
  void setInstanceKeyBoxes(uint32_t geomID, std::vector<Box3f> boxes);
  // Union of the geometries alive in [range.lo, range.hi] over that range.
  Box3f boundsOver(TimeRange range) const;
  // Bytes of the structures of instanced scenes.
  void addChildStats(AccelStats& stats) const;

 private:
  struct Child {
    std::unique_ptr<SceneContext> context;
    std::unique_ptr<Structure> structure;
  };
  void computeInstanceKeyBoxes();
  void computeGeometryKeyBoxes();

  const Scene* scene_;
  BuildOptions options_;
  BuildBudget* budget_;
  StructureFactory makeChild_;
  std::vector<const Geometry*> geometries_;
  size_t numPrimitives_ = 0;
  std::map<const Scene*, Child> children_;
  std::vector<const Structure*> childOf_;                // per geometry (instances only)
  std::vector<const SceneContext*> childContextOf_;      // per geometry (instances only)
  std::vector<std::vector<Box3f>> instanceKeyBoxes_;     // per geometry (instances only)
  std::vector<InstanceMotion> instanceMotions_;          // per geometry (instances only; empty without)
  std::vector<std::vector<Box3f>> geometryKeyBoxes_;     // per geometry, per key (when instanced)
  std::vector<std::vector<float>> stepTimes_;            // per geometry, per key
};

// Inline: the bounds of every reference start here.
inline PrimKeys SceneContext::keys(PrimRef ref) const {
  const Geometry& g = *geometries_[ref.geomID];
  const float* times = stepTimes_[ref.geomID].data();
  switch (g.type()) {
    case GeometryType::Triangles: {
      const Triangle& t = g.triangles()[ref.primID];
      return {&g, times, nullptr, {t.v0, t.v1, t.v2}, 0.0f};
    }
    case GeometryType::Segments: {
      const Segment& s = g.segments()[ref.primID];
      return {&g, times, nullptr, {s.v0, s.v1, s.v1}, std::max(g.radii()[s.v0], g.radii()[s.v1])};
    }
    case GeometryType::Instance:
      break;
  }
  return {&g, times, instanceKeyBoxes_[ref.geomID].data(), {0, 0, 0}, 0.0f};
}

}  // namespace mbrt::detail
