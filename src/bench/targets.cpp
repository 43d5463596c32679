// The structures the bench runs: an Accel of any kind (Embree in one of its
// modes), and the frozen-time rows (one structure per frozen time).
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "mbrt/bench.h"

namespace mbrt::bench {
namespace {

using EmbreeMode = BuildOptions::EmbreeMode;

template <class F>
void countedPass(size_t n, TraversalCounters& c, F&& one) {
  tbb::combinable<TraversalCounters> per;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    TraversalCounters& local = per.local();
    for (size_t i = r.begin(); i != r.end(); ++i) one(i, local);
  });
  per.combine_each([&](const TraversalCounters& x) { c.add(x); });
}

class AccelTarget final : public Target {
 public:
  explicit AccelTarget(std::unique_ptr<Accel> a) : accel_(std::move(a)) {}
  void trace(std::span<const Ray> rays, std::span<Hit> hits) const override { accel_->intersect(rays, hits); }
  void occluded(std::span<const Ray> rays, std::span<uint8_t> occ) const override { accel_->occluded(rays, occ); }
  bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters& c) const override {
    countedPass(rays.size(), c, [&](size_t i, TraversalCounters& local) { accel_->intersect(rays[i], hits[i], local); });
    return accel_->options().kind != AccelKind::Embree;
  }
  AccelStats stats() const override { return accel_->stats(); }

 private:
  std::unique_ptr<Accel> accel_;
};

// One static structure per frozen time (`frozen`, or Embree's static BVH);
// each ray goes to the one of the nearest time (the frozen set's rays sit
// exactly on those times).
class FrozenTarget final : public Target {
 public:
  FrozenTarget(const Scene& scene, int K, BuildOptions o) {
    for (int k = 0; k < K; ++k) {
      o.frozenTime = K == 1 ? 0.5f : float(k) / float(K - 1);
      trees_.push_back(Accel::build(scene, o));
    }
  }
  const Accel& treeFor(float time) const {
    const int K = int(trees_.size());
    const int k = K == 1 ? 0 : std::clamp(int(std::lround(time * float(K - 1))), 0, K - 1);
    return *trees_[k];
  }
  void trace(std::span<const Ray> rays, std::span<Hit> hits) const override {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) treeFor(rays[i].time).intersect(rays[i], hits[i]);
    });
  }
  void occluded(std::span<const Ray> rays, std::span<uint8_t> occ) const override {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) occ[i] = treeFor(rays[i].time).occluded(rays[i]) ? 1 : 0;
    });
  }
  bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters& c) const override {
    countedPass(rays.size(), c,
                [&](size_t i, TraversalCounters& local) { treeFor(rays[i].time).intersect(rays[i], hits[i], local); });
    return trees_.front()->options().kind != AccelKind::Embree;
  }
  // One tree's figures (the middle one): the bound is per time.
  AccelStats stats() const override { return trees_[trees_.size() / 2]->stats(); }

 private:
  std::vector<std::unique_ptr<Accel>> trees_;
};

Candidate frozenCandidate(const std::string& name, AccelKind kind, EmbreeMode mode, int K) {
  Candidate c;
  c.name = name;
  c.frozen = true;
  c.peer = kind == AccelKind::Embree;
  c.build = [kind, mode, K](const Scene& scene) -> std::unique_ptr<Target> {
    BuildOptions o;
    o.kind = kind;
    o.embreeMode = mode;
    return std::make_unique<FrozenTarget>(scene, K, o);
  };
  return c;
}

bool available(AccelKind kind) {
  const auto kinds = availableAccelKinds();
  return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

}  // namespace

Candidate accelCandidate(AccelKind kind, EmbreeMode mode) {
  Candidate c;
  c.name = std::string(toString(kind));
  if (kind == AccelKind::Embree) c.name = embreeRowName(mode);
  c.peer = kind == AccelKind::Embree;
  c.build = [kind, mode](const Scene& scene) -> std::unique_ptr<Target> {
    BuildOptions o;
    o.kind = kind;
    o.embreeMode = mode;
    return std::make_unique<AccelTarget>(Accel::build(scene, o));
  };
  return c;
}

std::vector<std::string> candidateNames() {
  std::vector<std::string> names;
  for (AccelKind k : {AccelKind::Brute, AccelKind::BvhInterp, AccelKind::BvhSegments, AccelKind::Frozen,
                      AccelKind::Stbvh, AccelKind::Msbvh, AccelKind::Mbkd, AccelKind::FuzzyKd, AccelKind::Embree,
                      AccelKind::Auto})
    names.push_back(std::string(toString(k)));
  for (EmbreeMode m : {EmbreeMode::Robust, EmbreeMode::Static, EmbreeMode::StaticRobust})
    names.push_back(embreeRowName(m));
  return names;
}

std::vector<Candidate> defaultCandidates(const Options& options, std::vector<std::string>* notes) {
  std::vector<std::string> names = options.accels;
  if (names.empty()) {
    for (AccelKind k : availableAccelKinds())
      if (k != AccelKind::Brute) names.push_back(std::string(toString(k)));
    if (available(AccelKind::Embree))
      for (EmbreeMode m : {EmbreeMode::Robust, EmbreeMode::Static, EmbreeMode::StaticRobust})
        names.push_back(embreeRowName(m));
  }
  const int K = std::max(1, options.frozenTimes);
  std::vector<Candidate> out;
  for (const std::string& n : names) {
    const std::optional<EmbreeMode> mode = parseEmbreeRow(n);
    const auto kind = mode ? std::optional<AccelKind>(AccelKind::Embree) : parseAccelKind(n);
    if (!kind) throw Error("unknown accel '" + n + "'");
    if (!available(*kind)) {
      if (notes) notes->push_back(n + ": not available in this build");
      continue;
    }
    if (mode == EmbreeMode::Static || mode == EmbreeMode::StaticRobust)
      out.push_back(frozenCandidate(n, AccelKind::Embree, *mode, K));
    else if (*kind == AccelKind::Frozen)
      out.push_back(frozenCandidate(n, AccelKind::Frozen, EmbreeMode::Default, K));
    else
      out.push_back(accelCandidate(*kind, mode.value_or(EmbreeMode::Default)));
  }
  return out;
}

}  // namespace mbrt::bench
