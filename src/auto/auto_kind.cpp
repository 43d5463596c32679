// The build of `auto` (docs/auto.md): the decomposition into objects, the
// top level over them, and the flat trial that may keep the whole scene as
// one object instead.
#include "auto/auto_kind.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "auto/auto_structure.h"
#include "auto/stats_number.h"
#include "auto/one_instance.h"
#include "auto/trace_confirm.h"

namespace mbrt::detail {
namespace {

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

float linearChange(const std::vector<Affine3f>& keys) {
  float most = 0;
  for (const Affine3f& k : keys)
    for (const Vec3f& col : {k.vx - keys.front().vx, k.vy - keys.front().vy, k.vz - keys.front().vz})
      most = std::max({most, std::fabs(col.x), std::fabs(col.y), std::fabs(col.z)});
  return most;
}

}  // namespace

AutoStructure::AutoStructure(const SceneContext& ctx)
    : ctx_(ctx), leafOptions_(ctx.options()), layout_(layoutOf(ctx.scene())) {
  for (uint32_t id = 0; id < ctx.scene().numGeometries(); ++id)
    if (ctx.geometry(id).type() == GeometryType::Instance)
      userStructures_[ctx.geometry(id).instancedScene()] = &ctx.child(id);
  plan_ = planDecomposition(ctx.scene(), ctx.options().autoFitTolerance, !ctx.options().autoForRefits);
  if (!plan_.extracts()) {
    buildDirect();
    return;
  }
  decomposed_ = true;
  decomposedBudget_ = trialBudget(ctx.budget());
  for (const RigidPart& part : plan_.rigid) addRigid(part);
  for (const ClusterPart& part : plan_.clusters)
    if (!addCluster(part)) returnToWorld(part);
  if (!plan_.world.empty()) addWorld();
  for (uint32_t id : plan_.userInstances) addUserInstance(id);
  makeTopLevel(*decomposedBudget_);
  if (worthFlatTrial()) keepCheaperOfFlat();
  if (decomposed_) chargeKept(*decomposedBudget_, ctx.budget());
}

// The top level over the objects, made again by every refit (new keys, new
// bounds): an stbvh over their instances, or the one instance itself.
void AutoStructure::makeTopLevel(BuildBudget& parent) {
  auto scene = std::make_shared<Scene>();
  for (const auto& o : objects_) {
    uint32_t id;
    if (o->type == ObjectType::UserInstance) {
      const Geometry& g = ctx_.geometry(o->geomID);
      id = g.hasSRTKeys() ? scene->addInstance(g.instancedSceneShared(),
                                               std::vector<SRTKey>(g.srtKeys().begin(), g.srtKeys().end()),
                                               g.timeRange())
                          : scene->addInstance(g.instancedSceneShared(),
                                               std::vector<Affine3f>(g.transforms().begin(), g.transforms().end()),
                                               g.timeRange());
    } else {
      const bool world = o->type == ObjectType::World;
      id = scene->addInstance(o->scene, o->keys, world ? TimeRange{} : ctx_.geometry(o->geomID).timeRange());
    }
    if (o->type != ObjectType::World) scene->setMask(id, ctx_.geometry(o->geomID).mask());
  }
  BuildOptions topOptions = ctx_.options();
  topOptions.kind = AccelKind::Stbvh;
  auto budget = trialBudget(parent);
  auto context = std::make_unique<SceneContext>(*scene, topOptions, *budget, childFactory());
  for (uint32_t i = 0; i < objects_.size(); ++i)
    if (!objects_[i]->keyBoxes.empty()) context->setInstanceKeyBoxes(i, objects_[i]->keyBoxes);
  std::unique_ptr<Structure> top;
  if (scene->numGeometries() == 1) {
    top = std::make_unique<OneInstance>(*context);
    topLine_ = "top level: none, its one instance tested directly";
  } else {
    top = ctx_.structureFactory()(*context);
    topLine_ = "top level: stbvh over " + std::to_string(scene->numGeometries()) + " instances";
  }
  top_.reset();
  topContext_.reset();
  if (topBudget_) parent.release(std::min(parent.used(), topBudget_->used()));
  chargeKept(*budget, parent);
  topScene_ = std::move(scene);
  topBudget_ = std::move(budget);
  topContext_ = std::move(context);
  top_ = std::move(top);
  trace_ = top_.get();
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
// cache factor of its bytes (all its objects and the top level); where the
// two are within the model's error, a measured trace decides
// (trace_confirm.h).
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
  const std::string figures = "cost per sampled ray / memory: decomposed " + statsNumber(split) + " (" +
                              statsNumber(counted.entries) + " instance entries per ray) / " +
                              statsNumber(double(splitStats.bytes) / 1e6) + " MB, whole scene as one object " +
                              statsNumber(flat.rayCost) + " / " + statsNumber(double(flat.stats.bytes) / 1e6) + " MB";
  const TraceCandidate candidates[] = {{"decomposed", top_.get(), split},
                                       {"whole scene as one object", flat.structure.get(), flat.rayCost}};
  const TraceChoice choice = confirmByTrace(candidates, flat.rayCost < split ? 1 : 0, rays, leafOptions_);
  if (choice.chosen == 0) {
    choiceLine_ = "kept the decomposition (" + figures + ")" + choice.line;
    return;
  }
  top_.reset();
  topContext_.reset();
  topBudget_.reset();
  topScene_.reset();
  objects_.clear();
  decomposed_ = false;
  chargeKept(*flat.budget, ctx_.budget());
  whole_ = std::move(flat);
  trace_ = whole_.structure.get();
  choiceLine_ = "object 0: the whole scene as one object, cheaper than its decomposition (" + figures + ")" +
                choice.line + "; kind " + std::string(toString(whole_.kind)) + ": " + whole_.why;
}

// Nothing rigid to extract: the whole scene is one object.
void AutoStructure::buildDirect() {
  whole_ = buildObject(ctx_.scene(), leafOptions_, ctx_.budget(), ctx_.structureFactory(), childFactory());
  trace_ = whole_.structure.get();
  choiceLine_ = "object 0: the whole scene, nothing rigid extracted (" + describeWorld() + "); kind " +
                std::string(toString(whole_.kind)) + ": " + whole_.why;
}

// Instanced scenes: the objects' derived scenes get the objects' structures
// (owned by the objects, counted while counting_), the user's scenes those
// the enclosing context built; others (below user scenes, where only their
// bounds are read) the oracle, which builds nothing.
StructureFactory AutoStructure::childFactory() {
  return [this](const SceneContext& c) -> std::unique_ptr<Structure> {
    for (const auto& o : objects_)
      if (o->scene.get() == &c.scene() && o->built.structure)
        return std::make_unique<EntryCounting>(*o->built.structure, o->built.stats, tally_, counting_,
                                               o->built.kind == AccelKind::Frozen);
    auto u = userStructures_.find(&c.scene());
    if (u != userStructures_.end()) return std::make_unique<BorrowedStructure>(*u->second);
    BuildOptions o = c.options();
    o.kind = AccelKind::Brute;
    auto context = std::make_unique<SceneContext>(c.scene(), o, c.budget(), childFactory());
    auto s = ctx_.structureFactory()(*context);
    return std::make_unique<OwningStructure>(std::move(context), std::move(s));
  };
}

std::unique_ptr<Structure> makeAuto(const SceneContext& context) {
  return std::make_unique<AutoStructure>(context);
}

}  // namespace mbrt::detail
