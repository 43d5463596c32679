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

namespace {

constexpr std::array<std::pair<BuildOptions::EmbreeMode, std::string_view>, 4> kEmbreeModes{{
    {BuildOptions::EmbreeMode::Robust, "robust"},
    {BuildOptions::EmbreeMode::Default, "default"},
    {BuildOptions::EmbreeMode::Static, "static"},
    {BuildOptions::EmbreeMode::StaticRobust, "static-robust"}}};

}  // namespace

std::string_view toString(BuildOptions::EmbreeMode mode) {
  for (const auto& [m, name] : kEmbreeModes)
    if (m == mode) return name;
  return "unknown";
}

std::optional<BuildOptions::EmbreeMode> parseEmbreeMode(std::string_view name) {
  for (const auto& [m, n] : kEmbreeModes)
    if (n == name) return m;
  return std::nullopt;
}

std::string embreeRowName(BuildOptions::EmbreeMode mode) {
  if (mode == BuildOptions::EmbreeMode::Default) return "embree";
  return "embree-" + std::string(toString(mode));
}

std::optional<BuildOptions::EmbreeMode> parseEmbreeRow(std::string_view row) {
  if (row == "embree") return BuildOptions::EmbreeMode::Default;
  constexpr std::string_view kPrefix = "embree-";
  if (!row.starts_with(kPrefix)) return std::nullopt;
  const auto mode = parseEmbreeMode(row.substr(kPrefix.size()));
  if (mode == BuildOptions::EmbreeMode::Default) return std::nullopt;  // spelled "embree"
  return mode;
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
