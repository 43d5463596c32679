// AccelUpdater (mbrt/accel_update.h): the update policies of frame sequences.
#include "mbrt/accel_update.h"

#include <chrono>
#include <cmath>
#include <cstdio>

namespace mbrt {
namespace {

double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

std::optional<UpdatePolicy> parseUpdatePolicy(std::string_view name) {
  if (name == "refit") return UpdatePolicy::Refit;
  if (name == "rebuild") return UpdatePolicy::Rebuild;
  if (name == "auto") return UpdatePolicy::Auto;
  return std::nullopt;
}

std::string_view toString(UpdatePolicy policy) {
  switch (policy) {
    case UpdatePolicy::Refit: return "refit";
    case UpdatePolicy::Rebuild: return "rebuild";
    case UpdatePolicy::Auto: break;
  }
  return "auto";
}

AccelUpdater::AccelUpdater(UpdatePolicy policy, double rebuildFactor) : policy_(policy), rebuildFactor_(rebuildFactor) {
  if (!(rebuildFactor >= 1.0 && std::isfinite(rebuildFactor)))
    throw Error("the rebuild factor must be a number of at least 1, got " + std::to_string(rebuildFactor));
}

BuildOptions AccelUpdater::buildOptions(BuildOptions options) const {
  options.autoForRefits = policy_ != UpdatePolicy::Rebuild;
  return options;
}

AccelUpdate AccelUpdater::update(std::unique_ptr<Accel>& accel, const Scene& scene, const BuildOptions& options) {
  const BuildOptions o = buildOptions(options);
  return update(accel, scene, [&](const Scene& s) { return Accel::build(s, o); });
}

AccelUpdate AccelUpdater::update(std::unique_ptr<Accel>& accel, const Scene& scene, const Builder& build) {
  AccelUpdate out;
  const auto start = std::chrono::steady_clock::now();
  if (!accel || !accel->sceneAlive() || &accel->scene() != &scene) {
    out.what = accel ? "rebuild (new layout)" : "build";
    accel.reset();  // before the new build: its memory goes first
    accel = build(scene);
    if (policy_ == UpdatePolicy::Auto) lastBuildSah_ = out.sah = accel->stats().sahCost;
    out.seconds = since(start);
    return out;
  }
  if (policy_ == UpdatePolicy::Rebuild) {
    accel->rebuild();
    out.what = "rebuild";
    out.seconds = since(start);
    return out;
  }
  // An accel built elsewhere: its cost as built is that of its nodes now.
  if (policy_ == UpdatePolicy::Auto && lastBuildSah_ == 0.0) lastBuildSah_ = accel->stats().sahCost;
  out.refitted = accel->refit();
  out.what = accel->lastUpdate();  // the kind's own words: auto says what it refitted and rebuilt
  if (policy_ == UpdatePolicy::Auto) {
    out.sah = accel->stats().sahCost;
    const double growth = lastBuildSah_ > 0.0 ? out.sah / lastBuildSah_ : 1.0;
    if (!out.refitted) {
      lastBuildSah_ = out.sah;
    } else if (growth > rebuildFactor_) {
      accel->rebuild();
      lastBuildSah_ = out.sah = accel->stats().sahCost;
      out.refitted = false;
      char buf[64];
      std::snprintf(buf, sizeof buf, "rebuild (SAH x%.2f)", growth);
      out.what = buf;
    }
  }
  out.seconds = since(start);
  return out;
}

}  // namespace mbrt
