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
}

class Accel {
 public:
  // Builds the structure named by options.kind. Throws Error for invalid
  // scenes or options, and before exceeding options.memoryBudget. The build
  // runs in the caller's TBB arena and is deterministic whatever the thread
  // count. The scene must outlive the Accel.
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
  // (returns true); otherwise rebuilds and returns false.
  bool refit();

  // The group a primitive of the top-level scene was placed in by kinds that
  // decompose the scene (fuzzykd: its motion cluster, Günther et al. §4), for
  // pictures and statistics; kInvalidId for other kinds and bad ids.
  uint32_t clusterOf(uint32_t geomID, uint32_t primID) const;

  AccelStats stats() const;
  const BuildOptions& options() const { return options_; }
  const Scene& scene() const { return *scene_; }

 private:
  Accel(const Scene& scene, const BuildOptions& options);
  void construct();

  const Scene* scene_;
  BuildOptions options_;
  std::unique_ptr<detail::Structure> structure_;
  double buildSeconds_ = 0.0;
  mutable std::atomic<uint64_t> invalidRays_{0};
};

}  // namespace mbrt
