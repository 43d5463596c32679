// Accel: validates the scene and rays, times the build, keeps statistics.
#include "mbrt/accel.h"

#include <tbb/parallel_for.h>

#include <bit>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cmath>
#include <limits>

#include "accel/structure_factory.h"
#include "core/isolated_work.h"
#include "core/simd.h"
#include "scene/scene_context.h"

namespace mbrt {

namespace {

// isValidRay on two 4-lane loads, org with tnear and dir with tfar: the
// seven values that must be finite compared at once (NaN fails), the
// direction's three against zero. tfar may be +inf; a NaN tfar fails
// tnear <= tfar, tnear being finite by then.
inline bool validRay(const Ray& r) {
  static_assert(offsetof(Ray, tnear) == 12 && offsetof(Ray, dir) == 16 && offsetof(Ray, tfar) == 28);
  using P = detail::Pack<4>;
  const P orgNear = P::loadu(&r.org.x), dirFar = P::loadu(&r.dir.x);
  const P inf = P::set1(kInf);
  const bool finite = lessMask(abs(orgNear), inf) == 0xFu && (lessMask(abs(dirFar), inf) & 0x7u) == 0x7u;
  const bool moving = (equalMask(dirFar, P::set1(0.0f)) & 0x7u) != 0x7u;
  return finite && moving && r.time >= 0.0f && r.time <= 1.0f && r.tnear <= r.tfar;
}

}  // namespace

bool isValidRay(const Ray& r) { return validRay(r); }

namespace {

constexpr float kMaxFloat = std::numeric_limits<float>::max();

// 2^k as a double, for |k| < 1023 (here |k| <= 149).
inline double powerOfTwo(int k) { return std::bit_cast<double>(uint64_t(k + 1023) << 52); }

// x * 2^k rounded once to float, as std::ldexp(x, k): the double product is
// exact (24 significant bits times 2^k stays within double's range), so
// its one rounding to float is ldexp's. No libm call on the per-ray path.
inline float scaleByPowerOfTwo(float x, int k) { return float(double(x) * powerOfTwo(k)); }

// e with x = f * 2^e, f in [0.5, 1), for finite x != 0 (std::frexp's
// exponent): read from the double, where float denormals are normal.
inline int binaryExponent(float x) { return int(std::bit_cast<uint64_t>(double(x)) >> 52 & 0x7FFu) - 1022; }

// Structures trace every ray with its direction scaled by a power of two,
// 2^k, so that its largest component lies in [1, 2); tnear and tfar are
// scaled by 2^-k and hit distances back by 2^k. Powers of two keep this
// exact, bar underflow into denormals (of tnear, tfar, t, and of direction
// components below ~1e-38 times the largest one). The slab tests, the
// watertight shear and the segment test's |dir| then never overflow nor
// underflow, whatever the direction's scale (1e-45 to 3e38). The interval
// is clamped to finite floats: a hit's t is always finite.
class ScaledRay {
 public:
  explicit ScaledRay(const Ray& ray) {
    const Vec3f a{std::fabs(ray.dir.x), std::fabs(ray.dir.y), std::fabs(ray.dir.z)};
    exponent_ = 1 - binaryExponent(maxComponent(a));  // max = f * 2^e, f in [0.5, 1)
    const Vec3f dir{scaleByPowerOfTwo(ray.dir.x, exponent_), scaleByPowerOfTwo(ray.dir.y, exponent_),
                    scaleByPowerOfTwo(ray.dir.z, exponent_)};
    const float tnear = scaleByPowerOfTwo(ray.tnear, -exponent_);
    const float tfar = scaleByPowerOfTwo(std::min(ray.tfar, kMaxFloat), -exponent_);
    empty_ = !(tnear <= kMaxFloat) || !(tfar >= -kMaxFloat);  // beyond the float range
    query_.setup(ray.org, dir, std::max(tnear, -kMaxFloat), std::min(tfar, kMaxFloat), ray.time, ray.mask);
  }
  bool empty() const { return empty_; }
  detail::RayQuery& query() { return query_; }
  void unscale(Hit& hit) const { hit.t = scaleByPowerOfTwo(hit.t, exponent_); }

 private:
  detail::RayQuery query_;
  int exponent_ = 0;
  bool empty_ = false;
};

}  // namespace

void TraversalCounters::add(const TraversalCounters& o) {
  rays += o.rays;
  nodesVisited += o.nodesVisited;
  boxTests += o.boxTests;
  leavesVisited += o.leavesVisited;
  primitiveTests += o.primitiveTests;
  blockPrimitiveTests += o.blockPrimitiveTests;
  maxNodesVisited = std::max(maxNodesVisited, o.maxNodesVisited);
  maxPrimitiveTests = std::max(maxPrimitiveTests, o.maxPrimitiveTests);
}

// What a build makes: its memory budget, the context (and with it the
// structures of instanced scenes) and the structure, which lives on both.
// Accel traces through `structure` directly: one virtual call per ray.
namespace detail {
struct BuiltStructure {
  BuiltStructure(const Scene& scene, const BuildOptions& options)
      : budget(options.memoryBudget), context(scene, options, budget, makeStructure), structure(makeStructure(context)) {}
  BuildBudget budget;
  SceneContext context;
  std::unique_ptr<Structure> structure;
};
}  // namespace detail

Accel::Accel(const Scene& scene, const BuildOptions& options)
    : scene_(&scene), sceneLifetime_(scene.lifetime()), options_(options) {}
Accel::~Accel() = default;

void Accel::sceneGone() {
  throw Error("the scene this accel was built on was destroyed or moved: build a new accel on the scene "
              "that holds the geometry now");
}

const Scene& Accel::scene() const {
  checkScene();
  return *scene_;
}


std::unique_ptr<Accel> Accel::build(const Scene& scene, const BuildOptions& options) {
  if (options.branching != 2 && options.branching != 4 && options.branching != 8)
    throw Error("branching must be 2, 4 or 8, got " + std::to_string(options.branching));
  if (options.maxLeafSize < 1 || options.maxLeafSize > 64)
    throw Error("maxLeafSize must be in [1, 64], got " + std::to_string(options.maxLeafSize));
  if (options.sahBins < 2 || options.sahBins > 256)
    throw Error("sahBins must be in [2, 256], got " + std::to_string(options.sahBins));
  if (!(options.frozenTime >= 0.0f && options.frozenTime <= 1.0f))
    throw Error("frozen time must be in [0, 1]");
  if (!(options.traversalCost > 0.0f)) throw Error("traversal cost must be positive");
  if (!(options.autoFitTolerance >= 0.0f && options.autoFitTolerance < 1.0f))
    throw Error("auto fit tolerance must be in [0, 1)");
  if (options.autoLeafKind == AccelKind::Auto) throw Error("the leaf kind of auto cannot be auto");
  std::unique_ptr<Accel> accel(new Accel(scene, options));
  accel->construct();
  return accel;
}

void Accel::construct() {
  scene_->validate(options_.maxInstanceDepth);
  structure_ = nullptr;
  built_.reset();
  const auto start = std::chrono::steady_clock::now();
  // Isolated: a caller's parallel loop around the build cannot cut it short.
  detail::runIsolatedFromCancellation([&] { built_ = std::make_unique<detail::BuiltStructure>(*scene_, options_); });
  structure_ = built_->structure.get();
  buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  invalidRays_ = 0;
  lastUpdate_ = "build";
}

void Accel::rebuild() {
  checkScene();
  construct();
  lastUpdate_ = "rebuild";
}

bool Accel::refit() {
  checkScene();
  scene_->validate(options_.maxInstanceDepth);
  bool refitted = false;
  std::string summary;
  if (structure_)
    detail::runIsolatedFromCancellation([&] {
      const bool children = built_->context.refitChildren();
      refitted = children && structure_->refit();
      summary = children ? structure_->refitSummary() : "the kind of an instanced scene cannot refit";
    });
  if (refitted) {
    lastUpdate_ = summary.empty() ? "refit" : summary;
    return true;
  }
  construct();
  lastUpdate_ = "rebuild (" + (summary.empty() ? std::string("kind cannot refit") : summary) + ")";
  return false;
}

bool Accel::intersect(const Ray& ray, Hit& hit) const {
  checkScene();
  hit = Hit();
  if (!validRay(ray)) {
    invalidRays_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  ScaledRay q(ray);
  if (q.empty() || !structure_->intersect(q.query(), hit)) return false;
  q.unscale(hit);
  return true;
}

bool Accel::occluded(const Ray& ray) const {
  checkScene();
  if (!validRay(ray)) {
    invalidRays_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  ScaledRay q(ray);
  return !q.empty() && structure_->occluded(q.query());
}

bool Accel::intersect(const Ray& ray, Hit& hit, TraversalCounters& counters) const {
  checkScene();
  hit = Hit();
  if (!validRay(ray)) {
    invalidRays_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  ScaledRay q(ray);
  TraversalCounters one;
  one.rays = 1;
  const bool found = !q.empty() && structure_->intersectCounted(q.query(), hit, one);
  if (found) q.unscale(hit);
  one.maxNodesVisited = one.nodesVisited;
  one.maxPrimitiveTests = one.primitiveTests;
  counters.add(one);
  return found;
}

void Accel::intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
  if (hits.size() < rays.size()) throw Error("intersect: fewer hits than rays");
  checkScene();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) intersect(rays[i], hits[i]);
  });
}

void Accel::occluded(std::span<const Ray> rays, std::span<uint8_t> out) const {
  if (out.size() < rays.size()) throw Error("occluded: fewer results than rays");
  checkScene();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) out[i] = occluded(rays[i]) ? 1 : 0;
  });
}

uint32_t Accel::clusterOf(uint32_t geomID, uint32_t primID) const {
  checkScene();
  if (geomID >= scene_->numGeometries() || primID >= scene_->geometry(geomID).numPrimitives()) return kInvalidId;
  return structure_->clusterOf({geomID, primID});
}

AccelStats Accel::stats() const {
  checkScene();
  AccelStats s;
  structure_->fillStats(s);
  built_->context.addChildStats(s);
  s.primitives = built_->context.totalPrimitives();
  s.peakBuildBytes = built_->budget.peak();
  s.kind = std::string(toString(options_.kind));
  s.buildSeconds = buildSeconds_;
  s.invalidRays = invalidRays_.load();
  s.update = lastUpdate_;
  return s;
}

}  // namespace mbrt
