// Acceleration structures over a Scene, all behind one interface.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "mbrt/accel_stats.h"
#include "mbrt/build_options.h"
#include "mbrt/ray.h"
#include "mbrt/scene.h"

namespace mbrt {

namespace detail {
class Structure;
struct BuiltStructure;
}

// Thread safety.
//  - Concurrent: intersect, occluded (single rays and batches), stats and
//    clusterOf may run from any number of threads at once, on one Accel or
//    on several, also while other accels are built over the same scene
//    (building only reads the scene). Batches run in parallel themselves,
//    in the calling thread's TBB arena.
//  - Exclusive: rebuild, refit, destroying the Accel, and every change to
//    the scene or to a scene it instances (Scene::add*, setVertices,
//    setMask, setFilter, writing to shared vertex memory): no other call may
//    use that Accel, or any accel over that scene, meanwhile.
//  - Filters (Scene::setFilter) run on the tracing threads, concurrently
//    when several threads trace (or a batch runs in parallel): they must be
//    thread-safe then.
// tests/threads/ checks the concurrent part under ThreadSanitizer
// (scripts/test-tsan.sh).
//
// Lifetime. An Accel refers to its scene (and through it to the scene's
// vertex memory), it does not own it: the scene must outlive the Accel and
// stay where it is. A scene destroyed, moved from or moved into after the
// build (Scene::lifetime() has expired) makes every call of the Accel
// throw Error saying so, rather than read freed memory; the check is one
// load per call. Bindings that own scenes make this impossible instead
// (the Python Accel holds its Scene).
class Accel {
 public:
  // Builds the structure named by options.kind. Throws Error for invalid
  // scenes or options, and before exceeding options.memoryBudget. The build
  // runs in the caller's TBB arena and is deterministic whatever the thread
  // count. The scene must outlive the Accel (see Lifetime above).
  static std::unique_ptr<Accel> build(const Scene& scene, const BuildOptions& options);
  ~Accel();

  // Closest hit; returns hit.valid(). `hit` is overwritten.
  bool intersect(const Ray& ray, Hit& hit) const;
  // Any hit in [tnear, tfar].
  bool occluded(const Ray& ray) const;
  // Same, counting the work done (slower; for benchmarks).
  bool intersect(const Ray& ray, Hit& hit, TraversalCounters& counters) const;

  // Batches, in parallel over TBB in the caller's arena.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  void occluded(std::span<const Ray> rays, std::span<uint8_t> occluded) const;

  // After vertex data or transforms changed: rebuild from the scene.
  void rebuild();
  // Updates bounds without changing the topology where the kind supports it
  // (returns true); otherwise rebuilds and returns false. Structures of
  // instanced scenes are refitted first (a scene with instances refits only
  // where its kind can: auto). `auto` refits what its parts can (docs/auto.md,
  // "Refit") and rebuilds only the objects whose choice no longer holds.
  bool refit();
  // What the last build, rebuild or refit did, in a few words: "build",
  // "rebuild", "refit", "rebuild (kind cannot refit)", or auto's summary
  // such as "refit: 5 instances' keys, 1 tree refitted (msbvh)".
  const std::string& lastUpdate() const { return lastUpdate_; }

  // The group a primitive of the top-level scene was placed in by kinds that
  // decompose the scene (fuzzykd: its motion cluster, Günther et al. §4), for
  // pictures and statistics; kInvalidId for other kinds and bad ids.
  uint32_t clusterOf(uint32_t geomID, uint32_t primID) const;

  AccelStats stats() const;
  const BuildOptions& options() const { return options_; }
  // Throws Error when the scene was destroyed or moved (see Lifetime).
  const Scene& scene() const;
  // False once the scene was destroyed, moved from or assigned to since the
  // build (every other call then throws).
  bool sceneAlive() const { return !sceneLifetime_.expired(); }

 private:
  Accel(const Scene& scene, const BuildOptions& options);
  void construct();
  void checkScene() const {
    if (sceneLifetime_.expired()) sceneGone();
  }
  [[noreturn]] static void sceneGone();

  const Scene* scene_;
  std::weak_ptr<const void> sceneLifetime_;
  BuildOptions options_;
  std::unique_ptr<detail::BuiltStructure> built_;
  detail::Structure* structure_ = nullptr;  // built_'s, traced directly
  double buildSeconds_ = 0.0;
  std::string lastUpdate_;
  mutable std::atomic<uint64_t> invalidRays_{0};
};

}  // namespace mbrt
