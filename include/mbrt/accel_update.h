// How an Accel follows a scene that changes from frame to frame (an
// Animation, mbrt/io/animation.h): refit, rebuild, or refit until the tree
// has grown too costly (docs/renderer.md, "Update policies").
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "mbrt/accel.h"

namespace mbrt {

//   Refit    Accel::refit (bounds only, the topology of the last build) where
//            the kind can refit (bvh-interp, msbvh), a rebuild elsewhere;
//   Rebuild  a new build every frame;
//   Auto     refit while the SAH cost stays within rebuildFactor times the
//            cost right after the last rebuild, rebuild once it grows past it.
enum class UpdatePolicy { Refit, Rebuild, Auto };
// "refit", "rebuild", "auto".
std::optional<UpdatePolicy> parseUpdatePolicy(std::string_view name);
std::string_view toString(UpdatePolicy policy);

// What one update did.
struct AccelUpdate {
  // "build", "rebuild (new layout)", "refit", "rebuild",
  // "rebuild (kind cannot refit)", "rebuild (SAH x1.62)", or after a refit
  // the kind's own summary (Accel::lastUpdate): `auto` says what it
  // refitted and rebuilt, "refit: 2 instances' keys, 1 tree refitted
  // (msbvh)".
  std::string what;
  bool refitted = false;  // the tree was refitted and kept
  double seconds = 0.0;   // the build, refit or rebuild, with Auto's SAH check
  double sah = 0.0;       // the SAH cost after the update (Auto only; 0 otherwise)
};

// The policy and what it remembers between frames. Updates need exclusive
// access to the accel and the scene (mbrt/accel.h) and run in the caller's
// TBB arena.
class AccelUpdater {
 public:
  using Builder = std::function<std::unique_ptr<Accel>(const Scene&)>;

  // Throws Error for a rebuild factor below 1 or not finite.
  explicit AccelUpdater(UpdatePolicy policy = UpdatePolicy::Auto, double rebuildFactor = 1.5);
  UpdatePolicy policy() const { return policy_; }
  double rebuildFactor() const { return rebuildFactor_; }
  // `options` as an accel this policy updates is best built with: under
  // Refit and Auto, BuildOptions::autoForRefits (auto builds only what
  // refits). What update(accel, scene, options) builds with; a Builder
  // should build with it too.
  BuildOptions buildOptions(BuildOptions options) const;

  // Brings `accel` up to date with `scene` after the scene changed. A new
  // Accel is built with `build` when `accel` is null, was built over another
  // scene, or over one replaced since its build (Scene::lifetime() expired,
  // as an Animation's scene is when its layout changes: "rebuild (new
  // layout)"); otherwise the accel is refitted or rebuilt by the policy.
  AccelUpdate update(std::unique_ptr<Accel>& accel, const Scene& scene, const Builder& build);
  // The same, building with buildOptions(options).
  AccelUpdate update(std::unique_ptr<Accel>& accel, const Scene& scene, const BuildOptions& options);

 private:
  UpdatePolicy policy_;
  double rebuildFactor_;
  double lastBuildSah_ = 0.0;  // Auto: the cost right after the last (re)build; 0: not known yet
};

}  // namespace mbrt
