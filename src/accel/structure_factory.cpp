// Maps accel kinds to their builders.
#include <array>

#include "accel/structure_factory.h"

#include "accel/brute.h"
#include "auto/auto_kind.h"
#include "bvh/kinds/bvh_interp.h"
#include "bvh/kinds/bvh_segments.h"
#include "bvh/kinds/frozen.h"
#include "fuzzykd/fuzzykd.h"
#include "kd/mbkd.h"
#include "bvh/kinds/stbvh.h"
#include "scene/scene_context.h"
#include "msbvh/msbvh.h"
#ifdef MBRT_HAVE_EMBREE
#include "embree/embree_structure.h"
#endif

namespace mbrt {
namespace {

struct KindName {
  AccelKind kind;
  std::string_view name;
};
constexpr std::array<KindName, 10> kNames{{{AccelKind::Brute, "brute"},
                                          {AccelKind::BvhInterp, "bvh-interp"},
                                          {AccelKind::BvhSegments, "bvh-segments"},
                                          {AccelKind::Frozen, "frozen"},
                                          {AccelKind::Stbvh, "stbvh"},
                                          {AccelKind::Msbvh, "msbvh"},
                                          {AccelKind::Mbkd, "mbkd"},
                                          {AccelKind::FuzzyKd, "fuzzykd"},
                                          {AccelKind::Embree, "embree"},
                                          {AccelKind::Auto, "auto"}}};

}  // namespace

std::string_view toString(AccelKind kind) {
  for (const auto& k : kNames)
    if (k.kind == kind) return k.name;
  return "unknown";
}

std::optional<AccelKind> parseAccelKind(std::string_view name) {
  for (const auto& k : kNames)
    if (k.name == name) return k.kind;
  return std::nullopt;
}

std::vector<AccelKind> availableAccelKinds() {
  std::vector<AccelKind> kinds{AccelKind::Brute, AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Frozen,
                                AccelKind::Stbvh, AccelKind::Msbvh, AccelKind::Mbkd, AccelKind::FuzzyKd};
#ifdef MBRT_HAVE_EMBREE
  kinds.push_back(AccelKind::Embree);
#endif
  kinds.push_back(AccelKind::Auto);
  return kinds;
}

namespace detail {

std::unique_ptr<Structure> makeStructure(const SceneContext& context) {
  switch (context.options().kind) {
    case AccelKind::Brute:
      return makeBrute(context);
    case AccelKind::BvhInterp:
      return makeBvhInterp(context);
    case AccelKind::BvhSegments:
      return makeBvhSegments(context);
    case AccelKind::Frozen:
      return makeFrozen(context);
    case AccelKind::Stbvh:
      return makeStbvh(context);
    case AccelKind::Msbvh:
      return makeMsbvh(context);
    case AccelKind::Mbkd:
      return makeMbkd(context);
    case AccelKind::FuzzyKd:
      return makeFuzzyKd(context);
    case AccelKind::Auto:
      return makeAuto(context);
#ifdef MBRT_HAVE_EMBREE
    case AccelKind::Embree:
      return makeEmbree(context);
#endif
    default:
      throw Error("accel kind '" + std::string(toString(context.options().kind)) +
                  "' is not available in this build");
  }
}

}  // namespace detail
}  // namespace mbrt
