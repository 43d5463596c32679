#include "auto/object_choice.h"

#include <cmath>
#include <cstdio>
#include <vector>

#include "auto/trace_confirm.h"

namespace mbrt::detail {
namespace {

// The kinds tried for a moving object: linear bounds over the shutter, per
// time segment, with temporal splits, and with spatial splits over keys.
constexpr AccelKind kMovingCandidates[] = {AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Stbvh,
                                           AccelKind::Msbvh};
constexpr double kNearCost = 0.02;
constexpr size_t kMinTracedPrimitives = 2048;

std::string megabytes(size_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f MB", double(bytes) / 1e6);
  return buf;
}

std::string number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

BuiltObject buildKind(const Scene& scene, const BuildOptions& options, AccelKind kind, const BuildBudget& budget,
                      const StructureFactory& registry, const StructureFactory& children) {
  BuildOptions o = options;
  o.kind = kind;
  BuiltObject b;
  b.kind = kind;
  b.budget = trialBudget(budget);
  b.context = std::make_unique<SceneContext>(scene, o, *b.budget, children);
  b.structure = registry(*b.context);
  b.measure();
  return b;
}

// A frozen BVH serves every time when nothing moves, every geometry lives
// over the whole shutter and no filter would see the frozen time.
bool frozenServesAllTimes(const Scene& scene) {
  for (uint32_t id = 0; id < scene.numGeometries(); ++id) {
    const Geometry& g = scene.geometry(id);
    if (g.type() == GeometryType::Instance || g.numSteps() != 1 || g.hasFilter()) return false;
    if (!(g.timeRange() == TimeRange{0.0f, 1.0f})) return false;
  }
  return true;
}

bool isBudgetError(const Error& e) { return std::string(e.what()).find("memory budget") != std::string::npos; }

// Builds each candidate, measures it on the sampled rays and keeps the one
// of lowest weighed cost; trials that exceed the budget are skipped while
// another fits.
BuiltObject chooseAmong(const std::vector<AccelKind>& kinds, const Scene& scene, const BuildOptions& options,
                        const BuildBudget& budget, const StructureFactory& registry, const StructureFactory& children) {
  std::vector<BuiltObject> trials;
  std::string figures;
  for (AccelKind k : kinds) {
    try {
      trials.push_back(buildKind(scene, options, k, budget, registry, children));
    } catch (const Error& e) {
      if (!isBudgetError(e) || (trials.empty() && k == kinds.back())) throw;
      figures += std::string(figures.empty() ? "" : ", ") + std::string(toString(k)) + " over the budget";
    }
  }
  if (trials.empty()) throw Error("memory budget exceeded by every candidate kind of an auto object");
  const std::vector<RayQuery> rays = sampleRays(*trials.front().context);
  const RayCostWeights weights = weightsFor(scene);
  for (BuiltObject& t : trials)
    t.rayCost = measureRayCost(*t.structure, rays).total(weights, t.kind, t.stats.bytes, t.stats.leafBlockBytes);
  size_t best = 0;
  for (size_t i = 0; i < trials.size(); ++i)
    if (trials[i].rayCost < trials[best].rayCost) best = i;
  // Within kNearCost of the best one's cost, the smallest candidate: a cost
  // that close is within the sample's scatter, the memory is not.
  const double bestCost = trials[best].rayCost;
  for (size_t i = 0; i < trials.size(); ++i)
    if (trials[i].rayCost <= bestCost * (1.0 + kNearCost) && trials[i].stats.bytes < trials[best].stats.bytes) best = i;
  for (size_t i = 0; i < trials.size(); ++i) {
    figures += std::string(figures.empty() ? "" : ", ") + std::string(toString(trials[i].kind)) + " " +
               number(trials[i].rayCost) + " / " + megabytes(trials[i].stats.bytes);
  }
  std::vector<std::pair<AccelKind, double>> costs;
  std::vector<TraceCandidate> candidates;
  for (const BuiltObject& t : trials) {
    costs.emplace_back(t.kind, t.rayCost);
    candidates.push_back({std::string(toString(t.kind)), t.structure.get(), t.rayCost});
  }
  // Small objects are left to the model: their trace would cost more of
  // the build than their choice can save (crowd: 101 objects).
  TraceChoice confirmed;
  confirmed.chosen = best;
  if (scene.numPrimitives() >= kMinTracedPrimitives) confirmed = confirmByTrace(candidates, best, rays, options);
  BuiltObject b = std::move(trials[confirmed.chosen]);
  b.trials = std::move(costs);
  b.why = "lowest measured ray cost, its cache factor included (the smallest within 2 %), among trial builds (cost per sampled ray / memory: " +
          figures + ")" + confirmed.line;
  return b;
}

}  // namespace

bool refitsInPlace(AccelKind kind) { return kind == AccelKind::BvhInterp || kind == AccelKind::Msbvh; }

AccelKind cheapestRefittingTrial(const BuiltObject& b) {
  if (refitsInPlace(b.kind)) return b.kind;
  AccelKind best = b.kind;
  double bestCost = 0;
  for (const auto& [kind, cost] : b.trials)
    if (refitsInPlace(kind) && (best == b.kind || cost < bestCost)) {
      best = kind;
      bestCost = cost;
    }
  return best;
}

BuiltObject buildObjectOfKind(const Scene& scene, const BuildOptions& options, AccelKind kind, BuildBudget& budget,
                              const StructureFactory& registry, const StructureFactory& children) {
  BuiltObject b = buildKind(scene, options, kind, budget, registry, children);
  chargeKept(*b.budget, budget);
  return b;
}

std::unique_ptr<BuildBudget> trialBudget(const BuildBudget& budget) {
  if (budget.limit() == 0) return std::make_unique<BuildBudget>(0);
  const size_t left = budget.limit() > budget.used() ? budget.limit() - budget.used() : 0;
  return std::make_unique<BuildBudget>(std::max<size_t>(left, 1));  // 0 would mean unlimited
}

void chargeKept(const BuildBudget& trial, BuildBudget& budget) {
  const size_t kept = trial.used(), peak = std::max(trial.peak(), kept);
  budget.charge(peak, "an auto object");
  budget.release(peak - kept);
}

BuiltObject buildObject(const Scene& scene, const BuildOptions& options, BuildBudget& budget,
                        const StructureFactory& registry, const StructureFactory& children) {
  BuiltObject b;
  if (options.autoLeafKind) {
    b = buildKind(scene, options, *options.autoLeafKind, budget, registry, children);
    b.why = "forced by the leaf-kind option";
  } else if (scene.maxSegments() == 0 && !frozenServesAllTimes(scene)) {
    b = buildKind(scene, options, AccelKind::BvhInterp, budget, registry, children);
    b.why = "static, with partial time ranges or instances: linear bounds";
  } else if (scene.maxSegments() == 0) {
    b = chooseAmong({AccelKind::Frozen, AccelKind::BvhInterp}, scene, options, budget, registry, children);
    b.why = "static: " + b.why;
  } else {
    std::vector<AccelKind> kinds;
    for (AccelKind k : kMovingCandidates)
      if (!options.autoForRefits || refitsInPlace(k)) kinds.push_back(k);
    b = chooseAmong(kinds, scene, options, budget, registry, children);
  }
  chargeKept(*b.budget, budget);
  return b;
}

}  // namespace mbrt::detail
