// `auto`'s refit (docs/auto.md, "Refit"): after new vertex data, each object
// is updated as its choice allows, and only the objects whose choice no
// longer holds are rebuilt:
//  - a rigid part's keys are fitted again from the rest pose its tree was
//    built over to the new steps (its tree stays); a part rigid over the
//    new steps but not from that pose gets its tree again over the new
//    first step; a part no longer rigid at all becomes a world-space object
//    of its own;
//  - a tree that refits in place (bvh-interp, msbvh) is refitted; one whose
//    kind cannot is rebuilt with the cheapest of its trials that can, so
//    that the next frames refit; an object's refitted tree whose SAH cost
//    grew past kRefitSahGrowth times its build's is rebuilt with its kind
//    (checked every kSahCheckRefits refits: the SAH's pass over every
//    primitive costs as much as the refit itself, and a tree degrades
//    slowly; the whole scene as one object is left to the caller's check
//    of Accel::stats().sahCost, as for any kind);
//  - a near-rigid cluster's tree is made again in a frame fitted to the new
//    steps;
// then the top level is made again over the new keys and bounds.
#include <cstdio>

#include "auto/auto_structure.h"
#include "auto/part_bounds.h"
#include "bvh/kinds/cluster_bvh.h"
#include "decompose/decompose.h"

namespace mbrt::detail {
namespace {

// As `mbrt render --frames --update auto`'s default rebuild factor.
constexpr double kRefitSahGrowth = 1.5;
constexpr uint32_t kSahCheckRefits = 4;

std::string count(size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

std::string RefitReport::text() const {
  std::string s;
  const auto add = [&](const std::string& part) { s += (s.empty() ? "" : ", ") + part; };
  if (keys) add(count(keys, "instance's keys", "instances' keys"));
  for (const auto& [kind, n] : refitted) add(count(n, "tree", "trees") + " refitted (" + kind + ")");
  for (const auto& [why, n] : rebuilt) add(count(n, "object", "objects") + " rebuilt (" + why + ")");
  return "refit: " + (s.empty() ? std::string("nothing to update") : s);
}

std::vector<AutoStructure::LayoutEntry> AutoStructure::layoutOf(const Scene& scene) {
  std::vector<LayoutEntry> layout;
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    const bool instance = g.type() == GeometryType::Instance;
    layout.push_back({g.type(), g.numPrimitives(), g.numSteps(), g.timeRange(), g.hasFilter(),
                      instance ? 0 : g.vertices(0).count, instance ? g.instancedScene() : nullptr});
  }
  return layout;
}

bool AutoStructure::refit() {
  if (layoutOf(ctx_.scene()) != layout_) {
    refitSummary_ = "the scene's layout changed";
    return false;
  }
  try {
    RefitReport report;
    if (!decomposed_) {
      refitTree(whole_, ctx_.scene(), childFactory(), false, report);
      trace_ = whole_.structure.get();
      refitSummary_ = report.text();
      return true;
    }
    for (size_t i = 0; i < objects_.size(); ++i) {
      AutoObject& o = *objects_[i];
      switch (o.type) {
        case ObjectType::Rigid:
          refitRigid(o, i, report);
          break;
        case ObjectType::Cluster:
          refitCluster(o, i, report);
          break;
        case ObjectType::World:
          for (uint32_t id = 0; id < o.sources.size(); ++id) {
            const Geometry& g = ctx_.geometry(o.sources[id].geomID);
            for (uint32_t k = 0; k < g.numSteps(); ++k) o.scene->setVertices(id, k, g.vertices(k));
            o.scene->setMask(id, g.mask());
          }
          refitTree(o.built, *o.scene, ctx_.structureFactory(), true, report);
          break;
        case ObjectType::UserInstance:  // its structure is refitted by the enclosing context
          break;
      }
    }
    makeTopLevel(ctx_.budget());
    refitSummary_ = report.text();
    return true;
  } catch (const Error& e) {
    refitSummary_ = e.what();
    return false;
  }
}

void AutoStructure::refitRigid(AutoObject& o, size_t index, RefitReport& report) {
  const Geometry& g = ctx_.geometry(o.geomID);
  const double tolerance = ctx_.options().autoFitTolerance;
  PartFit fit = refitPart(std::span<const Vec3f>(o.rest.data(), o.restVertices.size()), g, o.restVertices, tolerance);
  if (!fit.fits) {
    // Rigid over this frame's steps but not from the kept rest pose (a part
    // near a joint is nearly rigid over a short shutter, not over a walk):
    // its tree made again over this frame's first step, its kind kept.
    fit = fitPart(g, o.restVertices, tolerance);
    if (!fit.fits) return makeWorldSpace(o, index, "no longer rigid", report);
    for (size_t i = 0; i < o.restVertices.size(); ++i) o.rest[i] = g.vertices(0)[o.restVertices[i]];
    o.rest.back() = o.rest[o.restVertices.size() - 1];
    BuiltObject next = buildObjectOfKind(*o.scene, leafOptions_, o.built.kind, ctx_.budget(), ctx_.structureFactory(),
                                         ctx_.structureFactory());
    next.why = o.built.why;
    next.trials = o.built.trials;
    replaceObject(o.built, std::move(next));
    ++report.rebuilt["rigid over this frame, not from its rest pose: its tree over a new one"];
  } else {
    ++report.keys;
  }
  o.fit = std::move(fit);
  o.keys = o.fit.keys;
  o.keyBoxes = partKeyBoxes(g, o.restVertices, o.fit);
  o.line = rigidLine(index, o);
}

// The cluster's frame fitted to the new steps (a decomposition of its
// triangles into one cluster), its tree made again in it; without a usable
// bound there, its triangles become a world-space object.
void AutoStructure::refitCluster(AutoObject& o, size_t index, RefitReport& report) {
  const Geometry& g = ctx_.geometry(o.geomID);
  for (uint32_t k = 0; k < g.numSteps(); ++k) o.scene->setVertices(0, k, g.vertices(k));
  o.scene->setMask(0, g.mask());
  DecomposeParams params;
  params.maxClusters = 1;
  params.startFromPieces = false;
  const Geometry& cluster = o.scene->geometry(0);
  const Decomposition d = decomposeMotion(cluster.triangles(), geometryKeys(cluster), params);
  std::vector<Affine3f> maps;
  for (const Affine3d& m : d.transforms.front()) maps.push_back(m.toFloat());
  BuiltObject b;
  b.budget = trialBudget(ctx_.budget());
  b.context = std::make_unique<SceneContext>(*o.scene, leafOptions_, *b.budget, ctx_.structureFactory());
  b.structure = makeClusterBvh(*b.context, maps);
  if (!b.structure) return makeWorldSpace(o, index, "a cluster without a usable bound in its new frame", report);
  b.measure();
  b.kind = o.built.kind;
  chargeKept(*b.budget, ctx_.budget());
  replaceObject(o.built, std::move(b));
  o.maps = std::move(maps);
  o.keyBoxes = trianglesKeyBoxes(g, o.prims, 0.0f);
  ++report.rebuilt["a cluster tree in a frame fitted again"];
}

// Refits b in place where its kind can; else rebuilds it with the cheapest
// of its trials that refits (b's own kind when none does).
void AutoStructure::refitTree(BuiltObject& b, const Scene& scene, const StructureFactory& children, bool checkSah,
                              RefitReport& report) {
  const std::string kind(toString(b.kind));
  if (b.structure->refit()) {
    AccelStats s;
    if (checkSah && ++b.refits % kSahCheckRefits == 0) b.structure->fillStats(s);
    if (!(s.sahCost > kRefitSahGrowth * b.stats.sahCost)) {
      ++report.refitted[kind];
      return;
    }
    char why[64];
    std::snprintf(why, sizeof why, "%s refitted to SAH x%.2f", kind.c_str(), s.sahCost / b.stats.sahCost);
    BuiltObject next = buildObjectOfKind(scene, leafOptions_, b.kind, ctx_.budget(), ctx_.structureFactory(), children);
    next.why = b.why;
    next.trials = b.trials;
    replaceObject(b, std::move(next));
    ++report.rebuilt[why];
    return;
  }
  const AccelKind nextKind = cheapestRefittingTrial(b);
  const bool sameKind = nextKind == b.kind;
  BuiltObject next = buildObjectOfKind(scene, leafOptions_, nextKind, ctx_.budget(), ctx_.structureFactory(), children);
  next.trials = b.trials;
  for (const auto& [k, cost] : b.trials)
    if (k == nextKind) next.rayCost = cost;
  next.why = sameKind ? b.why
                      : "the cheapest of its trials that refits, where " + kind + " (the build's choice) cannot; " + b.why;
  replaceObject(b, std::move(next));
  ++report.rebuilt[sameKind ? kind + " cannot refit" : kind + " cannot refit: now " + std::string(toString(nextKind))];
}

// A rigid part or cluster whose choice no longer holds: its triangles as a
// world-space object of their own under an identity instance, their kind
// chosen as for any object.
void AutoStructure::makeWorldSpace(AutoObject& o, size_t index, const std::string& why, RefitReport& report) {
  o.type = ObjectType::World;
  o.sources = {{o.geomID, o.prims}};
  o.scene = worldScene(o.sources);
  replaceObject(o.built, buildObject(*o.scene, leafOptions_, ctx_.budget(), ctx_.structureFactory(),
                                     ctx_.structureFactory()));
  o.keys = {Affine3f()};
  o.keyBoxes.clear();
  o.rest = {};
  o.restVertices = {};
  o.line = "object " + std::to_string(index) + ": geometry " + std::to_string(o.geomID) + ", " +
           std::to_string(o.prims.empty() ? ctx_.geometry(o.geomID).numPrimitives() : o.prims.size()) +
           " triangles made world-space by a refit (" + why + "); kind " + std::string(toString(o.built.kind)) +
           ": " + o.built.why;
  ++report.rebuilt[why];
}

// `next` (already charged to the accel's budget) takes old's place; old's
// charge is released, its structure gone before the context it was built on.
void AutoStructure::replaceObject(BuiltObject& old, BuiltObject next) {
  BuildBudget& budget = ctx_.budget();
  if (old.budget) budget.release(std::min(budget.used(), old.budget->used()));
  old.structure.reset();
  old.context.reset();
  old = std::move(next);
}

}  // namespace mbrt::detail
