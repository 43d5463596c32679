#include "auto/auto_kind.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <map>

#include "auto/auto_plan.h"
#include "auto/object_choice.h"
#include "auto/one_instance.h"
#include "auto/part_bounds.h"
#include "bvh/kinds/cluster_bvh.h"
#include "scene/primitive_intersect.h"

namespace mbrt::detail {
namespace {

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The flat alternative (the whole scene as one object, no top level) is
// also built and measured when the scene is small (up to
// kFlatTrialPrimitives: its trial builds are cheap, whatever the number of
// objects: demo, and crowd at small sizes, where an instance holds a few
// dozen triangles and its ray transform costs more than its tree saves),
// or when the top level would hold few objects whose keys turn or scale
// little (there linear bounds over the original mesh are nearly as tight
// as the instance's static tree, and the instance's ray transform and
// second traversal set-up cost more than they save: translate, sponza).
// Large scenes with large turns (rotate) or many objects (crowd) are what
// instances are for: there the flat trees are many times larger and their
// trial builds would take longer than all the rest, so they are not tried.
// A forced leaf kind asks for the decomposition: no flat trial then.
constexpr size_t kFlatTrialObjects = 4;
constexpr float kFlatTrialLinearChange = 0.1f;  // largest element change of a key's 3x3 part (~6 degrees)
constexpr size_t kFlatTrialPrimitives = 65536;

// Hits on an extracted rigid part whose |cos| between the ray and the
// normal is below this are tested again in world space (remapHit).
constexpr float kRetestCosine = 0.1f;

float linearChange(const std::vector<Affine3f>& keys) {
  float most = 0;
  for (const Affine3f& k : keys)
    for (const Vec3f& col : {k.vx - keys.front().vx, k.vy - keys.front().vy, k.vz - keys.front().vz})
      most = std::max({most, std::fabs(col.x), std::fabs(col.y), std::fabs(col.z)});
  return most;
}

// "rigid, kind frozen" from an object's line, for counts of many objects.
std::string kindOfLine(const std::string& line) {
  const std::string what = line.find(": rigid,") != std::string::npos            ? "rigid"
                           : line.find(": near-rigid cluster,") != std::string::npos ? "near-rigid"
                                                                                      : "other";
  const size_t k = line.find("; kind ");
  if (k == std::string::npos) return what;
  const size_t end = line.find(':', k + 7);
  return what + " " + line.substr(k + 7, end == std::string::npos ? std::string::npos : end - k - 7);
}

class AutoStructure final : public Structure {
 public:
  explicit AutoStructure(const SceneContext& ctx);

  bool intersect(RayQuery& ray, Hit& hit) const override {
    const float tfar = ray.tfar;
    if (!trace_->intersect(ray, hit)) return false;
    if (remap_) remapHit(ray, tfar, hit);
    return true;
  }
  bool occluded(RayQuery& ray) const override { return trace_->occluded(ray); }
  bool intersectCounted(RayQuery& ray, Hit& hit, TraversalCounters& counters) const override {
    const float tfar = ray.tfar;
    if (!trace_->intersectCounted(ray, hit, counters)) return false;
    if (remap_) remapHit(ray, tfar, hit);
    return true;
  }
  void fillStats(AccelStats& s) const override;
  uint32_t clusterOf(PrimRef p) const override;

 private:
  enum class ObjectType : uint8_t { Rigid, Cluster, World, UserInstance };
  struct TopEntry {
    ObjectType type;
    uint32_t geomID;                      // in the original scene (Rigid, Cluster, UserInstance)
    const std::vector<uint32_t>* prims;   // Rigid, Cluster: original primID of each child triangle; null: the same
  };
  struct WorldEntry {
    uint32_t geomID;
    const std::vector<uint32_t>* prims;
  };

  void remapHit(RayQuery& ray, float tfar, Hit& hit) const;
  StructureFactory childFactory();
  void addRigid(const RigidPart& part);
  bool addCluster(const ClusterPart& part);
  void returnToWorld(const ClusterPart& part);
  void addWorld();
  void addUserInstance(uint32_t geomID);
  void buildDirect();
  bool worthFlatTrial() const;
  void keepCheaperOfFlat();
  std::string describeWorld() const;

  const SceneContext& ctx_;
  BuildOptions leafOptions_;
  std::unique_ptr<BuildBudget> decomposedBudget_;  // charges of the decomposition, until it is kept
  EntryTally tally_;                               // what the objects did while counting_
  std::atomic<bool> counting_{false};
  AutoPlan plan_;
  std::map<const Scene*, const Structure*> userStructures_;  // built by ctx_
  std::vector<std::shared_ptr<Scene>> scenes_;               // derived scenes
  std::shared_ptr<Scene> topScene_;
  std::vector<BuiltObject> objects_;
  struct PendingObject {
    std::unique_ptr<Structure> structure;
    AccelKind kind;
  };
  std::map<const Scene*, PendingObject> pending_;  // for the top context's factory
  std::unique_ptr<SceneContext> topContext_;
  std::unique_ptr<Structure> top_;
  const Structure* trace_ = nullptr;
  bool remap_ = false;
  std::vector<std::pair<uint32_t, std::vector<Box3f>>> rigidKeyBoxes_;  // until the top context takes them
  std::vector<TopEntry> topMap_;      // per top-level geometry of topScene_
  std::vector<WorldEntry> worldMap_;  // per geometry of the world-space object
  std::vector<std::string> lines_;
};

AutoStructure::AutoStructure(const SceneContext& ctx) : ctx_(ctx), leafOptions_(ctx.options()) {
  for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id)
    if (ctx.geometry(id).type() == GeometryType::Instance)
      userStructures_[ctx.geometry(id).instancedScene()] = &ctx.child(id);
  plan_ = planDecomposition(ctx.scene(), ctx.options().autoFitTolerance);
  if (!plan_.extracts()) {
    buildDirect();
    return;
  }
  decomposedBudget_ = trialBudget(ctx.budget());
  topScene_ = std::make_shared<Scene>();
  for (const RigidPart& part : plan_.rigid) addRigid(part);
  for (const ClusterPart& part : plan_.clusters)
    if (!addCluster(part)) returnToWorld(part);
  if (!plan_.world.empty()) addWorld();
  for (uint32_t id : plan_.userInstances) addUserInstance(id);
  BuildOptions topOptions = ctx.options();
  topOptions.kind = AccelKind::Stbvh;
  topContext_ = std::make_unique<SceneContext>(*topScene_, topOptions, *decomposedBudget_, childFactory());
  for (auto& [id, boxes] : rigidKeyBoxes_) topContext_->setInstanceKeyBoxes(id, std::move(boxes));
  rigidKeyBoxes_.clear();
  if (topScene_->numGeometries() == 1) {
    top_ = std::make_unique<OneInstance>(*topContext_);
    lines_.push_back("top level: none, its one instance tested directly");
  } else {
    top_ = ctx.structureFactory()(*topContext_);
    lines_.push_back("top level: stbvh over " + std::to_string(topScene_->numGeometries()) + " instances");
  }
  trace_ = top_.get();
  remap_ = true;
  if (worthFlatTrial()) keepCheaperOfFlat();
  if (top_) chargeKept(*decomposedBudget_, ctx.budget());
}

bool AutoStructure::worthFlatTrial() const {
  if (leafOptions_.autoLeafKind) return false;
  // Clusters save only where their fuzzy boxes are tight: always measured
  // against the mesh's own linear bounds.
  if (!plan_.clusters.empty()) return true;
  if (ctx_.totalPrimitives() <= kFlatTrialPrimitives) return true;
  if (topScene_->numGeometries() > kFlatTrialObjects) return false;
  for (const RigidPart& part : plan_.rigid)
    if (linearChange(part.fit.keys) > kFlatTrialLinearChange) return false;
  return true;
}

// Measures the decomposition and the whole scene built as one object on the
// same sampled rays (ray_cost.h) and keeps the cheaper, each weighed by the
// cache factor of its bytes (all its objects and the top level).
void AutoStructure::keepCheaperOfFlat() {
  const std::vector<RayQuery> rays = sampleRays(ctx_);
  counting_ = true;
  const RayCost counted = measureRayCost(*top_, rays, &tally_);
  counting_ = false;
  AccelStats splitStats;
  top_->fillStats(splitStats);
  topContext_->addChildStats(splitStats);
  const double split = counted.total(weightsFor(ctx_.scene()), AccelKind::Stbvh, splitStats.bytes, splitStats.leafBlockBytes);
  // buildObject charges the kept kind to flatBudget; flat.budget holds it.
  const std::unique_ptr<BuildBudget> flatBudget = trialBudget(ctx_.budget());
  BuiltObject flat = buildObject(ctx_.scene(), leafOptions_, *flatBudget, ctx_.structureFactory(), childFactory());
  const std::string figures = "cost per sampled ray / memory: decomposed " + number(split) + " (" +
                              number(counted.entries) + " instance entries per ray) / " +
                              number(double(splitStats.bytes) / 1e6) + " MB, whole scene as one object " +
                              number(flat.rayCost) + " / " + number(double(flat.bytes) / 1e6) + " MB";
  if (!(flat.rayCost < split)) {
    lines_.push_back("kept the decomposition (" + figures + ")");
    return;
  }
  top_.reset();
  topContext_.reset();
  objects_.clear();
  pending_.clear();
  topMap_.clear();
  worldMap_.clear();
  remap_ = false;
  chargeKept(*flat.budget, ctx_.budget());
  objects_.push_back(std::move(flat));
  trace_ = objects_.back().structure.get();
  lines_.assign(1, "object 0: the whole scene as one object, cheaper than its decomposition (" + figures + "); kind " +
                       std::string(toString(objects_.back().kind)) + ": " + objects_.back().why);
}

// Nothing rigid to extract: the whole scene is one object.
void AutoStructure::buildDirect() {
  objects_.push_back(buildObject(ctx_.scene(), leafOptions_, ctx_.budget(), ctx_.structureFactory(), childFactory()));
  trace_ = objects_.back().structure.get();
  lines_.push_back("object 0: the whole scene, nothing rigid extracted (" + describeWorld() + "); kind " +
                   std::string(toString(objects_.back().kind)) + ": " + objects_.back().why);
}

// Instanced scenes: the derived objects built here, the user's scenes
// built by the enclosing context; others (below user scenes, where only
// their bounds are read) get the oracle, which builds nothing.
StructureFactory AutoStructure::childFactory() {
  return [this](const SceneContext& c) -> std::unique_ptr<Structure> {
    auto p = pending_.find(&c.scene());
    if (p != pending_.end() && p->second.structure)
      return std::make_unique<EntryCounting>(std::move(p->second.structure), tally_, counting_,
                                             p->second.kind == AccelKind::Frozen);
    auto u = userStructures_.find(&c.scene());
    if (u != userStructures_.end()) return std::make_unique<BorrowedStructure>(*u->second);
    BuildOptions o = c.options();
    o.kind = AccelKind::Brute;
    auto context = std::make_unique<SceneContext>(c.scene(), o, c.budget(), childFactory());
    auto s = ctx_.structureFactory()(*context);
    return std::make_unique<OwningStructure>(std::move(context), std::move(s));
  };
}

void AutoStructure::addRigid(const RigidPart& part) {
  const Geometry& g = ctx_.geometry(part.geomID);
  std::vector<Triangle> tris;
  if (part.prims.empty()) tris.assign(g.triangles().begin(), g.triangles().end());
  for (uint32_t p : part.prims) tris.push_back(g.triangles()[p]);
  auto child = std::make_shared<Scene>();
  child->addTriangleMesh(std::move(tris), std::vector<VertexBuffer>{g.vertices(0)});
  objects_.push_back(buildObject(*child, leafOptions_, *decomposedBudget_, ctx_.structureFactory(), ctx_.structureFactory()));
  pending_[child.get()] = {std::move(objects_.back().structure), objects_.back().kind};
  const uint32_t id = topScene_->addInstance(child, part.fit.keys, g.timeRange());
  topScene_->setMask(id, g.mask());
  rigidKeyBoxes_.emplace_back(id, partKeyBoxes(g, part));
  scenes_.push_back(std::move(child));
  topMap_.push_back({ObjectType::Rigid, part.geomID, part.prims.empty() ? nullptr : &part.prims});
  const size_t n = part.prims.empty() ? g.numPrimitives() : part.prims.size();
  lines_.push_back("object " + std::to_string(id) + ": geometry " + std::to_string(part.geomID) + ", " +
                   (part.prims.empty() ? "all " + std::to_string(n) + " triangles"
                                       : "a connected piece of " + std::to_string(n) + " triangles") +
                   ": rigid, " + std::to_string(part.fit.keys.size()) + " affine keys, residual " +
                   number(part.fit.maxResidual) + " of its diagonal " + number(part.fit.diagonal) + "; kind " +
                   std::string(toString(objects_.back().kind)) + ": " + objects_.back().why);
}

// A near-rigid cluster: its triangles over the mesh's own vertex buffers,
// a tree in the cluster's frame (cluster_bvh.h) under identity keys, one
// per step, so that the top level bounds it per step with the box of its
// vertices. False when its fuzzy boxes have no usable bound.
bool AutoStructure::addCluster(const ClusterPart& part) {
  const Geometry& g = ctx_.geometry(part.geomID);
  std::vector<Triangle> tris;
  for (uint32_t p : part.prims) tris.push_back(g.triangles()[p]);
  std::vector<VertexBuffer> steps;
  for (uint32_t k = 0; k < g.numSteps(); ++k) steps.push_back(g.vertices(k));
  auto child = std::make_shared<Scene>();
  child->setMask(child->addTriangleMesh(std::move(tris), std::move(steps), g.timeRange()), g.mask());
  BuiltObject b;
  b.budget = trialBudget(*decomposedBudget_);
  b.context = std::make_unique<SceneContext>(*child, leafOptions_, *b.budget, ctx_.structureFactory());
  b.structure = makeClusterBvh(*b.context, part.maps);
  if (!b.structure) return false;
  AccelStats s;
  b.structure->fillStats(s);
  b.bytes = s.bytes;
  b.leafBlockBytes = s.leafBlockBytes;
  b.sahCost = s.sahCost;
  chargeKept(*b.budget, *decomposedBudget_);
  objects_.push_back(std::move(b));
  pending_[child.get()] = {std::move(objects_.back().structure), objects_.back().kind};
  const uint32_t id = topScene_->addInstance(child, std::vector<Affine3f>(g.numSteps(), Affine3f()), g.timeRange());
  topScene_->setMask(id, g.mask());
  rigidKeyBoxes_.emplace_back(id, trianglesKeyBoxes(g, part.prims, 0.0f));
  scenes_.push_back(std::move(child));
  topMap_.push_back({ObjectType::Cluster, part.geomID, &part.prims});
  lines_.push_back("object " + std::to_string(id) + ": geometry " + std::to_string(part.geomID) + ", " +
                   std::to_string(part.prims.size()) + " triangles: near-rigid cluster, " +
                   std::to_string(part.maps.size()) + " affine keys, the mesh's rms residual " +
                   number(part.rmsResidual) + " of its diagonal; kind cluster-bvh: a static tree over the "
                   "fuzzy boxes in its frame, " + number(double(objects_.back().bytes) / 1e6) + " MB");
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

// The world-space rest as one object under an identity instance: its
// geometries keep masks, time ranges and (with the original ids) filters.
void AutoStructure::addWorld() {
  auto world = std::make_shared<Scene>();
  for (const WorldPart& part : plan_.world) {
    const Geometry& g = ctx_.geometry(part.geomID);
    std::vector<VertexBuffer> steps;
    for (uint32_t k = 0; k < g.numSteps(); ++k) steps.push_back(g.vertices(k));
    uint32_t id;
    if (g.type() == GeometryType::Segments) {
      std::vector<Segment> segs(g.segments().begin(), g.segments().end());
      id = world->addSegments(std::move(segs), std::move(steps), std::vector<float>(g.radii().begin(), g.radii().end()),
                              g.timeRange());
    } else {
      std::vector<Triangle> tris;
      if (part.prims.empty()) tris.assign(g.triangles().begin(), g.triangles().end());
      for (uint32_t p : part.prims) tris.push_back(g.triangles()[p]);
      id = world->addTriangleMesh(std::move(tris), std::move(steps), g.timeRange());
    }
    world->setMask(id, g.mask());
    const std::vector<uint32_t>* prims = part.prims.empty() ? nullptr : &part.prims;
    if (g.hasFilter()) {
      const uint32_t geomID = part.geomID;
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
    worldMap_.push_back({part.geomID, prims});
  }
  objects_.push_back(buildObject(*world, leafOptions_, *decomposedBudget_, ctx_.structureFactory(), ctx_.structureFactory()));
  pending_[world.get()] = {std::move(objects_.back().structure), objects_.back().kind};
  const uint32_t id = topScene_->addInstance(world, std::vector<Affine3f>{Affine3f()});
  scenes_.push_back(std::move(world));
  topMap_.push_back({ObjectType::World, kInvalidId, nullptr});
  lines_.push_back("object " + std::to_string(id) + ": world-space geometry (" + describeWorld() + "); kind " +
                   std::string(toString(objects_.back().kind)) + ": " + objects_.back().why);
}

void AutoStructure::addUserInstance(uint32_t geomID) {
  const Geometry& g = ctx_.geometry(geomID);
  uint32_t id;
  if (g.hasSRTKeys())
    id = topScene_->addInstance(g.instancedSceneShared(), std::vector<SRTKey>(g.srtKeys().begin(), g.srtKeys().end()),
                                g.timeRange());
  else
    id = topScene_->addInstance(g.instancedSceneShared(),
                                std::vector<Affine3f>(g.transforms().begin(), g.transforms().end()), g.timeRange());
  topScene_->setMask(id, g.mask());
  topMap_.push_back({ObjectType::UserInstance, geomID, nullptr});
  lines_.push_back("object " + std::to_string(id) + ": instance geometry " + std::to_string(geomID) + " (" +
                   std::to_string(g.numSteps()) + " keys): kept, its scene built by auto");
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
  if (!plan_.userInstances.empty() && !remap_ && topScene_ == nullptr)
    s += (s.empty() ? "" : ", ") + std::to_string(plan_.userInstances.size()) + " user instances";
  return s;
}

// An extracted part's hit is tested again on the original triangle with the
// world-space ray, so that t, u, v and Ng are the mesh's own (in the rest
// frame, the float transform of a grazing ray moves t by ~1e-7 / cos).
// Where the world test misses (the ray passes within the fit's residual of
// an edge), the instance's hit stands, its normal as the mesh's: cof(M) n =
// det(M) M^-T n.
void AutoStructure::remapHit(RayQuery& ray, float tfar, Hit& hit) const {
  if (hit.instID >= topMap_.size()) return;
  const TopEntry& e = topMap_[hit.instID];
  switch (e.type) {
    case ObjectType::Rigid: {
      const uint32_t primID = e.prims ? (*e.prims)[hit.primID] : hit.primID;
      // A grazing hit is tested again on the original triangle with the
      // world-space ray: there the ray's float transform into the instance
      // moves t by ~1e-7 / cos θ. Steeper hits keep the instance's t, u, v
      // (within ~1e-6 of the world test's), saving the fetch of the
      // original mesh's vertices at two steps (docs/auto.md, "Hits name the
      // original scene").
      const float dn = dot(hit.Ng, ray.dir);
      if (dn * dn < kRetestCosine * kRetestCosine * dot(hit.Ng, hit.Ng) * dot(ray.dir, ray.dir)) {
        RayQuery world = ray;
        world.tfar = tfar;
        Hit exact;
        if (leaf_detail::candidate(ctx_.geometry(e.geomID), {e.geomID, primID}, world, exact)) {
          hit = exact;
          ray.tfar = exact.t;
          break;
        }
      }
      // The instance's normal M^-T n, turned into the mesh's cof(M) n.
      hit.Ng = hit.Ng * topScene_->geometry(hit.instID).transformAt(ray.time).determinant();
      hit.geomID = e.geomID;
      hit.primID = primID;
      hit.instID = kInvalidId;
      break;
    }
    case ObjectType::Cluster:  // world-space triangles: the hit is the mesh's own
      hit.geomID = e.geomID;
      hit.primID = (*e.prims)[hit.primID];
      hit.instID = kInvalidId;
      break;
    case ObjectType::World: {
      const WorldEntry& w = worldMap_[hit.geomID];
      hit.geomID = w.geomID;
      if (w.prims) hit.primID = (*w.prims)[hit.primID];
      hit.instID = kInvalidId;
      break;
    }
    case ObjectType::UserInstance:
      hit.instID = e.geomID;
      break;
  }
}

void AutoStructure::fillStats(AccelStats& s) const {
  if (top_) {
    top_->fillStats(s);
    topContext_->addChildStats(s);
  } else {
    trace_->fillStats(s);
    objects_.front().context->addChildStats(s);
  }
  // Scenes of many objects: the first ones in full, the rest counted.
  constexpr size_t kListed = 16;
  for (size_t i = 0; i < lines_.size(); ++i)
    if (i < kListed || i + 1 == lines_.size()) s.objects += lines_[i] + "\n";
  if (lines_.size() > kListed + 1) {
    std::map<std::string, size_t> kinds;
    for (size_t i = kListed; i + 1 < lines_.size(); ++i) ++kinds[kindOfLine(lines_[i])];
    std::string counts;
    for (const auto& [kind, n] : kinds) counts += (counts.empty() ? "" : ", ") + std::to_string(n) + " " + kind;
    s.objects += "... and " + std::to_string(lines_.size() - kListed - 1) + " more objects (" + counts + ")\n";
  }
}

// The object a primitive was placed in: its rigid part's instance, else the
// world-space object (or, without extraction, 0).
uint32_t AutoStructure::clusterOf(PrimRef p) const {
  if (!remap_) return 0;
  for (uint32_t i = 0; i < topMap_.size(); ++i) {
    const TopEntry& e = topMap_[i];
    if (e.geomID != p.geomID || e.type == ObjectType::World) continue;
    if (!e.prims || std::binary_search(e.prims->begin(), e.prims->end(), p.primID)) return i;
  }
  for (uint32_t i = 0; i < topMap_.size(); ++i)
    if (topMap_[i].type == ObjectType::World) return i;
  return kInvalidId;
}

}  // namespace

std::unique_ptr<Structure> makeAuto(const SceneContext& context) {
  return std::make_unique<AutoStructure>(context);
}

}  // namespace mbrt::detail
