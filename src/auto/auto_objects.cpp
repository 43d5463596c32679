// The objects of `auto`'s decomposition (docs/auto.md): each one's derived
// scene, its structure and its line in mbrt stats.
#include <algorithm>
#include <cstdio>

#include "auto/auto_structure.h"
#include "auto/stats_number.h"
#include "auto/part_bounds.h"
#include "bvh/kinds/cluster_bvh.h"

namespace mbrt::detail {
namespace {

std::vector<uint32_t> allOrSome(const Geometry& g, const std::vector<uint32_t>& prims) {
  if (!prims.empty()) return prims;
  std::vector<uint32_t> all(g.numPrimitives());
  for (uint32_t p = 0; p < all.size(); ++p) all[p] = p;
  return all;
}

}  // namespace

// A rigid part: its rest pose copied (a refit fits new keys from it, and the
// caller may overwrite or free the buffers it came from), compacted to the
// part's own vertices, its tree static over it, and the fitted keys.
void AutoStructure::addRigid(const RigidPart& part) {
  const Geometry& g = ctx_.geometry(part.geomID);
  auto o = std::make_unique<AutoObject>();
  o->type = ObjectType::Rigid;
  o->geomID = part.geomID;
  o->prims = part.prims;
  o->fit = part.fit;
  o->keys = part.fit.keys;
  const std::vector<uint32_t> tris = allOrSome(g, part.prims);
  o->restVertices = usedVertices(g, tris);
  o->rest.reserve(o->restVertices.size() + 1);
  for (uint32_t v : o->restVertices) o->rest.push_back(g.vertices(0)[v]);
  o->rest.push_back(o->rest.back());  // readable padding after the last vertex (16-byte loads)
  const auto local = [&](uint32_t v) {
    return uint32_t(std::lower_bound(o->restVertices.begin(), o->restVertices.end(), v) - o->restVertices.begin());
  };
  std::vector<Triangle> triangles;
  triangles.reserve(tris.size());
  for (uint32_t t : tris) {
    const Triangle& tri = g.triangles()[t];
    triangles.push_back({local(tri.v0), local(tri.v1), local(tri.v2)});
  }
  VertexBuffer rest;
  rest.data = o->rest.data();
  rest.count = o->restVertices.size();
  rest.padding = sizeof(Vec3f);
  o->scene = std::make_shared<Scene>();
  o->scene->addTriangleMesh(std::move(triangles), std::vector<VertexBuffer>{rest});
  o->built = buildObject(*o->scene, leafOptions_, *decomposedBudget_, ctx_.structureFactory(), ctx_.structureFactory());
  o->keyBoxes = partKeyBoxes(g, part);
  o->line = rigidLine(objects_.size(), *o);
  objects_.push_back(std::move(o));
}

std::string AutoStructure::rigidLine(size_t index, const AutoObject& o) const {
  const size_t n = o.prims.empty() ? ctx_.geometry(o.geomID).numPrimitives() : o.prims.size();
  return "object " + std::to_string(index) + ": geometry " + std::to_string(o.geomID) + ", " +
         (o.prims.empty() ? "all " + std::to_string(n) + " triangles"
                          : "a connected piece of " + std::to_string(n) + " triangles") +
         ": rigid, " + std::to_string(o.keys.size()) + " " + toString(o.fit.form) + " keys, residual " +
         statsNumber(o.fit.maxResidual) + " of its diagonal " + statsNumber(o.fit.diagonal) + "; kind " +
         std::string(toString(o.built.kind)) + ": " + o.built.why;
}

// A near-rigid cluster: its triangles over the mesh's own vertex buffers,
// a tree in the cluster's frame (cluster_bvh.h) under identity keys, one
// per step, so that the top level bounds it per step with the box of its
// vertices. False when its fuzzy boxes have no usable bound.
bool AutoStructure::addCluster(const ClusterPart& part) {
  auto o = std::make_unique<AutoObject>();
  o->type = ObjectType::Cluster;
  o->geomID = part.geomID;
  o->prims = part.prims;
  o->maps = part.maps;
  o->rmsResidual = part.rmsResidual;
  o->sources = {{part.geomID, part.prims}};
  o->scene = worldScene(o->sources);
  BuiltObject& b = o->built;
  b.budget = trialBudget(*decomposedBudget_);
  b.context = std::make_unique<SceneContext>(*o->scene, leafOptions_, *b.budget, ctx_.structureFactory());
  b.structure = makeClusterBvh(*b.context, part.maps);
  if (!b.structure) return false;
  b.measure();
  chargeKept(*b.budget, *decomposedBudget_);
  const Geometry& g = ctx_.geometry(part.geomID);
  o->keys.assign(g.numSteps(), Affine3f());
  o->keyBoxes = trianglesKeyBoxes(g, part.prims, 0.0f);
  o->line = "object " + std::to_string(objects_.size()) + ": geometry " + std::to_string(part.geomID) + ", " +
            std::to_string(part.prims.size()) + " triangles: near-rigid cluster, " + std::to_string(part.maps.size()) +
            " affine keys, the mesh's rms residual " + statsNumber(part.rmsResidual) +
            " of its diagonal; kind cluster-bvh: a static tree over the fuzzy boxes in its frame, " +
            statsNumber(double(b.stats.bytes) / 1e6) + " MB";
  objects_.push_back(std::move(o));
  return true;
}

// A cluster without a usable bound: its triangles stay world-space.
void AutoStructure::returnToWorld(const ClusterPart& part) {
  for (WorldPart& w : plan_.world)
    if (w.geomID == part.geomID) {
      w.prims.insert(w.prims.end(), part.prims.begin(), part.prims.end());
      std::sort(w.prims.begin(), w.prims.end());
      return;
    }
  plan_.world.push_back({part.geomID, part.prims, "a cluster whose fuzzy boxes have no usable bound"});
}

// A scene of the sources' primitives over the original vertex buffers of
// every step: masks, time ranges and (with the original ids) filters as
// they were. `sources` must outlive the scene (its filters read it).
std::shared_ptr<Scene> AutoStructure::worldScene(const std::vector<WorldSource>& sources) const {
  auto world = std::make_shared<Scene>();
  for (const WorldSource& src : sources) {
    const Geometry& g = ctx_.geometry(src.geomID);
    std::vector<VertexBuffer> steps;
    for (uint32_t k = 0; k < g.numSteps(); ++k) steps.push_back(g.vertices(k));
    uint32_t id;
    if (g.type() == GeometryType::Segments) {
      std::vector<Segment> segs(g.segments().begin(), g.segments().end());
      id = world->addSegments(std::move(segs), std::move(steps), std::vector<float>(g.radii().begin(), g.radii().end()),
                              g.timeRange());
    } else {
      std::vector<Triangle> tris;
      if (src.prims.empty()) tris.assign(g.triangles().begin(), g.triangles().end());
      for (uint32_t p : src.prims) tris.push_back(g.triangles()[p]);
      id = world->addTriangleMesh(std::move(tris), std::move(steps), g.timeRange());
    }
    world->setMask(id, g.mask());
    if (g.hasFilter()) {
      const uint32_t geomID = src.geomID;
      const std::vector<uint32_t>* prims = src.prims.empty() ? nullptr : &src.prims;
      world->setFilter(
          id,
          [&g, geomID, prims](const FilterArgs& a) {
            Hit h = a.candidate;
            h.geomID = geomID;
            if (prims) h.primID = (*prims)[h.primID];
            return g.filter()(FilterArgs{a.ray, h, a.userData});
          },
          g.userData());
    }
  }
  return world;
}

// The world-space rest as one object under an identity instance.
void AutoStructure::addWorld() {
  auto o = std::make_unique<AutoObject>();
  o->type = ObjectType::World;
  for (const WorldPart& part : plan_.world) o->sources.push_back({part.geomID, part.prims});
  o->scene = worldScene(o->sources);
  o->built = buildObject(*o->scene, leafOptions_, *decomposedBudget_, ctx_.structureFactory(), ctx_.structureFactory());
  o->keys = {Affine3f()};
  o->line = "object " + std::to_string(objects_.size()) + ": world-space geometry (" + describeWorld() + "); kind " +
            std::string(toString(o->built.kind)) + ": " + o->built.why;
  objects_.push_back(std::move(o));
}

void AutoStructure::addUserInstance(uint32_t geomID) {
  auto o = std::make_unique<AutoObject>();
  o->type = ObjectType::UserInstance;
  o->geomID = geomID;
  o->line = "object " + std::to_string(objects_.size()) + ": instance geometry " + std::to_string(geomID) + " (" +
            std::to_string(ctx_.geometry(geomID).numSteps()) + " keys): kept, its scene built by auto";
  objects_.push_back(std::move(o));
}

std::string AutoStructure::describeWorld() const {
  std::string s;
  size_t listed = 0;
  for (const WorldPart& part : plan_.world) {
    if (++listed > 12) {
      s += ", and " + std::to_string(plan_.world.size() - 12) + " more";
      break;
    }
    s += (s.empty() ? "" : ", ") + std::string("geometry ") + std::to_string(part.geomID) + " " + part.why;
  }
  if (!plan_.userInstances.empty() && !decomposed_)
    s += (s.empty() ? "" : ", ") + std::to_string(plan_.userInstances.size()) + " user instances";
  return s;
}

}  // namespace mbrt::detail
