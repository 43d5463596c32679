// The `auto` structure (docs/auto.md): the scene decomposed into objects
// (auto_plan.h), each an instance of a top level over derived scenes, or
// the whole scene as one object where that measures cheaper. The files of
// src/auto/ that implement it, one idea each:
//   auto_kind.cpp     the build: objects, the top level, the flat trial;
//   auto_objects.cpp  the objects' derived scenes and their stats lines;
//   auto_hits.cpp     hits named in the original scene, clusterOf, stats;
//   auto_refit.cpp    the refit: keys fitted again, trees refitted, only the
//                     objects whose choice no longer holds rebuilt.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "auto/auto_plan.h"
#include "auto/object_choice.h"
#include "auto/ray_cost.h"
#include "scene/scene_context.h"

namespace mbrt::detail {

enum class ObjectType : uint8_t { Rigid, Cluster, World, UserInstance };

// A geometry of a world-space object and where it came from.
struct WorldSource {
  uint32_t geomID = 0;          // in the original scene
  std::vector<uint32_t> prims;  // its primitives there; empty: all of them
};

// One object of the decomposition: one instance of the top level (its
// geometry id there is the object's index).
struct AutoObject {
  ObjectType type = ObjectType::World;
  uint32_t geomID = kInvalidId;  // Rigid, Cluster, UserInstance: the geometry in the original scene
  std::vector<uint32_t> prims;   // Rigid, Cluster: original primID of each child triangle; empty: all
  std::shared_ptr<Scene> scene;  // the derived scene; null for a user instance
  BuiltObject built;             // its structure; none for a user instance (the enclosing context builds it)
  std::vector<Affine3f> keys;    // Rigid: fitted; Cluster: identity per step; World: one identity
  std::vector<Box3f> keyBoxes;   // Rigid, Cluster: the top level's boxes (empty: computed by the top context)
  std::vector<WorldSource> sources;  // World: per geometry of `scene`
  // Rigid: the rest pose the tree was built over (kept: a refit fits keys
  // from it to the new steps), rest[i] being vertex restVertices[i].
  std::vector<Vec3f> rest;
  std::vector<uint32_t> restVertices;
  PartFit fit;                       // Rigid
  std::vector<Affine3f> maps;        // Cluster: its frame -> world per step
  double rmsResidual = 0;            // Cluster: of the mesh's decomposition
  std::string line;                  // its line in mbrt stats
};

// What a refit did, for Accel::lastUpdate.
struct RefitReport {
  size_t keys = 0;                        // rigid instances whose keys were fitted again
  std::map<std::string, size_t> refitted;  // per kind: trees refitted in place
  std::map<std::string, size_t> rebuilt;   // per reason: objects rebuilt
  std::string text() const;
};

class AutoStructure final : public Structure {
 public:
  explicit AutoStructure(const SceneContext& ctx);

  bool intersect(RayQuery& ray, Hit& hit) const override {
    const float tfar = ray.tfar;
    if (!trace_->intersect(ray, hit)) return false;
    if (decomposed_) remapHit(ray, tfar, hit);
    return true;
  }
  bool occluded(RayQuery& ray) const override { return trace_->occluded(ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& counters) const override {
    const float tfar = ray.tfar;
    if (!trace_->intersectCounted(ray, hit, counters)) return false;
    if (decomposed_) remapHit(ray, tfar, hit);
    return true;
  }
  void fillStats(AccelStats& s) const override;
  uint32_t clusterOf(PrimRef p) const override;
  bool refit() override;
  std::string refitSummary() const override { return refitSummary_; }

 private:
  // Build (auto_kind.cpp).
  StructureFactory childFactory();
  void makeTopLevel(BuildBudget& parent);
  void buildDirect();
  bool worthFlatTrial() const;
  void keepCheaperOfFlat();
  // Objects (auto_objects.cpp).
  void addRigid(const RigidPart& part);
  bool addCluster(const ClusterPart& part);
  void returnToWorld(const ClusterPart& part);
  void addWorld();
  void addUserInstance(uint32_t geomID);
  std::shared_ptr<Scene> worldScene(const std::vector<WorldSource>& sources) const;
  std::string rigidLine(size_t index, const AutoObject& o) const;
  std::string describeWorld() const;
  // Hits (auto_hits.cpp).
  void remapHit(RayQuery& ray, float tfar, Hit& hit) const;
  // Refit (auto_refit.cpp).
  void refitRigid(AutoObject& o, size_t index, RefitReport& report);
  void refitCluster(AutoObject& o, size_t index, RefitReport& report);
  void refitTree(BuiltObject& b, const Scene& scene, const StructureFactory& children, bool checkSah,
                 RefitReport& report);
  void makeWorldSpace(AutoObject& o, size_t index, const std::string& why, RefitReport& report);
  void replaceObject(BuiltObject& old, BuiltObject next);

  // The original scene's layout, which a refit needs unchanged.
  struct LayoutEntry {
    GeometryType type;
    uint32_t primitives, steps;
    TimeRange range;
    bool filter;
    size_t vertices;
    const Scene* instanced;
    bool operator==(const LayoutEntry&) const = default;
  };
  static std::vector<LayoutEntry> layoutOf(const Scene& scene);

  const SceneContext& ctx_;
  BuildOptions leafOptions_;
  std::vector<LayoutEntry> layout_;
  std::unique_ptr<BuildBudget> decomposedBudget_;  // charges of the decomposition, until it is kept
  EntryTally tally_;                               // what the objects did while counting_
  std::atomic<bool> counting_{false};
  AutoPlan plan_;
  std::map<const Scene*, const Structure*> userStructures_;  // built by ctx_
  bool decomposed_ = false;  // objects under a top level; else whole_ is the scene as one object
  BuiltObject whole_;
  std::vector<std::unique_ptr<AutoObject>> objects_;
  std::shared_ptr<Scene> topScene_;
  std::unique_ptr<BuildBudget> topBudget_;
  std::unique_ptr<SceneContext> topContext_;
  std::unique_ptr<Structure> top_;
  const Structure* trace_ = nullptr;
  std::string topLine_, choiceLine_;  // stats lines of the top level and of the flat trial
  std::string refitSummary_;
};

}  // namespace mbrt::detail
