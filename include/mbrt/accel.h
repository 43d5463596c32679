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

#include "mbrt/ray.h"
#include "mbrt/scene.h"

namespace mbrt {

enum class AccelKind {
  Brute,        // tests every primitive: the oracle
  BvhInterp,    // BVH with linear bounds over the whole shutter
  BvhSegments,  // one linear-bounds BVH per global time segment
  Frozen,       // static BVH of the scene frozen at BuildOptions::frozenTime
  Stbvh,        // Woop et al. 2017
  Msbvh,        // Grünschloß et al. 2011
  Mbkd,         // Yang et al. 2017
  FuzzyKd,      // Günther et al. 2006
  Embree,       // Intel Embree 3, when built in
};

std::string_view toString(AccelKind kind);
std::optional<AccelKind> parseAccelKind(std::string_view name);
// The kinds this build of mbrt can construct, in a stable order.
std::vector<AccelKind> availableAccelKinds();

struct BuildOptions {
  AccelKind kind = AccelKind::BvhInterp;
  int branching = 8;          // BVH node width: 2, 4 or 8
  int maxLeafSize = 8;        // primitives per BVH leaf at most
  int sahBins = 32;           // bins of the binned SAH
  float traversalCost = 1.0f;     // C_T of the SAH (intersection cost is 1)
  float frozenTime = 0.5f;    // time of the `frozen` kind
  size_t memoryBudget = 0;    // bytes the build may use; 0 = unlimited
  int maxInstanceDepth = 8;   // nesting of instances
  // `embree` only: Robust (RTC_SCENE_FLAG_ROBUST, watertight as mbrt; what the
  // oracle tests compare with), Default (Embree's default flags, what its
  // users run) or Static (default flags, Embree's static BVH over the scene
  // frozen at frozenTime). A field, not kinds: no test that walks every kind
  // meets a non-watertight structure, and no kind list changes.
  enum class EmbreeMode : uint8_t { Robust, Default, Static } embreeMode = EmbreeMode::Robust;
};

// Structure statistics. sahCost follows DESIGN.md's one formula for all
// kinds (C_T = C_I = 1, areas averaged over time, MBSAH segment counts).
struct AccelStats {
  std::string kind;
  size_t primitives = 0;        // triangles + segments + instances, all levels
  size_t references = 0;        // primitive references in leaves
  size_t innerNodes = 0;
  size_t leafNodes = 0;
  size_t maxDepth = 0;
  size_t bytes = 0;             // structure memory, excluding vertex buffers
  size_t peakBuildBytes = 0;    // largest memory in use during the build
  double sahCost = 0.0;
  double buildSeconds = 0.0;
  uint64_t invalidRays = 0;     // rays refused since the build
};

// Per-ray work, for the papers' metrics (DESIGN.md): nodes visited, box tests
// (an 8-wide node is 8) and ray-primitive tests.
struct TraversalCounters {
  uint64_t rays = 0;
  uint64_t nodesVisited = 0;
  uint64_t boxTests = 0;
  uint64_t primitiveTests = 0;
  uint64_t maxNodesVisited = 0;
  uint64_t maxPrimitiveTests = 0;

  void add(const TraversalCounters& o);
};

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
