#include "auto/object_choice.h"

#include <cmath>
#include <cstdio>
#include <vector>

namespace mbrt::detail {
namespace {

// The kinds tried for a moving object: linear bounds over the shutter, per
// time segment, with temporal splits, and with spatial splits over keys.
constexpr AccelKind kMovingCandidates[] = {AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Stbvh,
                                           AccelKind::Msbvh};

// Memory weighs in as a factor on the SAH cost: twice the memory of the
// smallest candidate must buy a 10 % lower cost.
double weighedCost(double sah, size_t bytes, size_t leastBytes) {
  const double ratio = leastBytes > 0 ? double(bytes) / double(leastBytes) : 1.0;
  return sah * (1.0 + 0.1 * std::log2(std::max(1.0, ratio)));
}

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

BuiltObject buildKind(const Scene& scene, const BuildOptions& options, AccelKind kind, BuildBudget& budget,
                      const StructureFactory& registry, const StructureFactory& children) {
  BuildOptions o = options;
  o.kind = kind;
  BuiltObject b;
  b.kind = kind;
  b.context = std::make_unique<SceneContext>(scene, o, budget, children);
  b.structure = registry(*b.context);
  AccelStats s;
  b.structure->fillStats(s);
  b.context->addChildStats(s);
  b.bytes = s.bytes;
  b.sahCost = s.sahCost;
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

}  // namespace

BuiltObject buildObject(const Scene& scene, const BuildOptions& options, BuildBudget& budget,
                        const StructureFactory& registry, const StructureFactory& children) {
  if (options.autoLeafKind) {
    BuiltObject b = buildKind(scene, options, *options.autoLeafKind, budget, registry, children);
    b.why = "forced by the leaf-kind option";
    return b;
  }
  if (scene.maxSegments() == 0) {
    const bool frozen = frozenServesAllTimes(scene);
    BuiltObject b = buildKind(scene, options, frozen ? AccelKind::Frozen : AccelKind::BvhInterp, budget, registry, children);
    b.why = frozen ? "static: a BVH with one box per node serves every time"
                   : "static, with partial time ranges or instances: linear bounds";
    return b;
  }
  std::vector<BuiltObject> trials;
  size_t leastBytes = ~size_t(0);
  for (AccelKind k : kMovingCandidates) {
    trials.push_back(buildKind(scene, options, k, budget, registry, children));
    leastBytes = std::min(leastBytes, trials.back().bytes);
  }
  size_t best = 0;
  std::string figures;
  for (size_t i = 0; i < trials.size(); ++i) {
    const double c = weighedCost(trials[i].sahCost, trials[i].bytes, leastBytes);
    if (c < weighedCost(trials[best].sahCost, trials[best].bytes, leastBytes)) best = i;
    figures += std::string(i ? ", " : "") + std::string(toString(trials[i].kind)) + " " +
               number(trials[i].sahCost) + " / " + megabytes(trials[i].bytes);
  }
  BuiltObject b = std::move(trials[best]);
  b.why = "lowest SAH cost weighed by memory among trial builds (SAH / memory: " + figures + ")";
  return b;
}

}  // namespace mbrt::detail
