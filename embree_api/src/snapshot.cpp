// Reads an Embree scene into mbrt's scene model (snapshot.h).
#include "snapshot.h"

#include "bounds.h"
#include "filters.h"
#include "instance_keys.h"
#include "mesh_read.h"
#include "scene.h"

namespace mbrt::embree_api {
namespace {

std::string geometryName(uint32_t id) { return "geometry " + std::to_string(id); }

class SnapshotBuilder {
 public:
  SnapshotBuilder(const Scene& scene, const SnapshotContext& context, std::vector<std::string>& errors)
      : scene_(scene), context_(context), errors_(errors) {}

  std::shared_ptr<Snapshot> build() {
    snap_ = std::make_shared<Snapshot>();
    mbrt_ = std::make_shared<mbrt::Scene>();
    const auto& table = scene_.geometries();
    for (uint32_t id = 0; id < table.size(); ++id) {
      Geometry* g = table[id].get();
      if (!g || !g->enabled || g->isPlaceholder()) continue;  // placeholders: reported at rtcNewGeometry
      if (g->isMesh())
        addMesh(id, *g);
      else
        addInstanceGeometry(id, *g);
    }
    if (mbrt_->numGeometries() > 0) snap_->scene = mbrt_;
    const SceneBounds b = snap_->scene ? boundsOf(*snap_->scene) : SceneBounds{};
    snap_->bounds = b.box;
    snap_->linearBounds = b.linear;
    return snap_;
  }

 private:
  bool filtered(const Geometry& g) const {
    return g.intersectFilter || g.occludedFilter || context_.contextFilter;
  }

  void addEntry(uint32_t id, Geometry& g, PrimitiveMap prims, std::shared_ptr<const Snapshot> child,
                const Snapshot* source = nullptr) {
    GeomEntry e;
    e.childSource = source;
    e.childGeneration = source ? source->generation : 0;
    e.embreeID = id;
    e.prims = std::move(prims);
    e.child = std::move(child);
    e.geometry = &g;
    e.topologyVersion = g.topologyVersion();
    e.vertexVersion = g.vertexVersion();
    snap_->entries.push_back(std::move(e));
  }

  void addMesh(uint32_t id, Geometry& g) {
    MeshData m;
    std::string error;
    if (!readMesh(g, m, error)) {
      errors_.push_back(geometryName(id) + " " + error + ": left out");
      return;
    }
    if (m.triangles.empty()) return;
    const uint32_t mid = m.copies.empty() ? mbrt_->addTriangleMesh(std::move(m.triangles), m.views, m.range)
                                          : mbrt_->addTriangleMesh(std::move(m.triangles), std::move(m.copies), m.range);
    mbrt_->setMask(mid, g.mask);
    for (auto& b : m.buffers) snap_->buffers.push_back(b);
    if (filtered(g)) {
      auto binding = std::make_unique<FilterBinding>();
      binding->geometry = &g;
      binding->mesh = &mbrt_->geometry(mid);
      binding->geomID = id;
      binding->instID = context_.instID;
      binding->path = context_.path;
      binding->prims = m.prims;
      const FilterBinding* b = binding.get();
      mbrt_->setFilter(mid, [b](const FilterArgs& args) { return runFilters(*b, args); });
      snap_->bindings.push_back(std::move(binding));
      snap_->hasFilters = true;
    }
    addEntry(id, g, m.prims, nullptr);
  }

  void addInstanceGeometry(uint32_t id, Geometry& g) {
    Scene* childScene = g.instanced.get();
    if (!childScene) {
      errors_.push_back(geometryName(id) + ": an instance without an instanced scene: left out");
      return;
    }
    if (childScene == &scene_) {
      errors_.push_back(geometryName(id) + ": a scene cannot instance itself: left out");
      return;
    }
    const std::shared_ptr<const Committed> committed = childScene->committedShared();
    if (!committed) {
      errors_.push_back(geometryName(id) + ": its instanced scene was not committed: left out");
      return;
    }
    const Snapshot& plain = *committed->snapshot;
    if (!plain.scene) return;  // an empty scene: nothing to hit
    for (const GeomEntry& e : plain.entries)
      if (e.child) {
        // Embree 3 as built by Debian has RTC_MAX_INSTANCE_LEVEL_COUNT 1:
        // a hit reports one instance id.
        errors_.push_back(geometryName(id) +
                          ": instances a scene with instances; one instance level is supported "
                          "(RTC_MAX_INSTANCE_LEVEL_COUNT 1): left out");
        return;
      }
    // A scene whose geometries run filters is read again for this instance,
    // so that its filters know the instance they are traced through.
    std::shared_ptr<const Snapshot> child = committed->snapshot;
    auto path = std::make_shared<InstancePath>();
    if (plain.hasFilters || context_.contextFilter) {
      SnapshotContext bound;
      bound.instID = id;
      bound.path = path;
      bound.contextFilter = context_.contextFilter;
      child = SnapshotBuilder(*childScene, bound, errors_).build();
      if (!child->scene) return;
      snap_->hasFilters = snap_->hasFilters || child->hasFilters;
    }
    uint32_t mid;
    std::string error;
    if (!addInstance(*mbrt_, g, child->scene, mid, *path, error)) {
      errors_.push_back(geometryName(id) + " " + error + ": left out");
      return;
    }
    mbrt_->setMask(mid, g.mask);
    addEntry(id, g, PrimitiveMap{}, std::move(child), &plain);
  }

  const Scene& scene_;
  const SnapshotContext& context_;
  std::vector<std::string>& errors_;
  std::shared_ptr<Snapshot> snap_;
  std::shared_ptr<mbrt::Scene> mbrt_;
};

}  // namespace

std::shared_ptr<Snapshot> buildSnapshot(const Scene& scene, const SnapshotContext& context,
                                        std::vector<std::string>& errors) {
  return SnapshotBuilder(scene, context, errors).build();
}

}  // namespace mbrt::embree_api
