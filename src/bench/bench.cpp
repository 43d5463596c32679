// The benchmark engine: rays, builds, timings, counters and hit agreement.
#include "mbrt/bench.h"

#include <tbb/combinable.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>

namespace mbrt::bench {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Counter-based random numbers: the same rays whatever the thread count.
uint64_t mix(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
float uniform(uint64_t seed, uint64_t index, uint64_t stream) {
  return float(mix(seed ^ mix(index * 4 + stream)) >> 40) * (1.0f / 16777216.0f);
}
uint64_t hashName(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (char c : s) h = (h ^ uint8_t(c)) * 1099511628211ull;
  return h;
}

class AccelTarget final : public Target {
 public:
  explicit AccelTarget(std::unique_ptr<Accel> a) : accel_(std::move(a)) {}
  void trace(std::span<const Ray> rays, std::span<Hit> hits) const override { accel_->intersect(rays, hits); }
  bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters& c) const override {
    countedPass(rays, hits, c, [&](size_t i, TraversalCounters& local) { accel_->intersect(rays[i], hits[i], local); });
    return accel_->options().kind != AccelKind::Embree;
  }
  AccelStats stats() const override { return accel_->stats(); }

  template <class F>
  static void countedPass(std::span<const Ray> rays, std::span<Hit>, TraversalCounters& c, F&& one) {
    tbb::combinable<TraversalCounters> per;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      TraversalCounters& local = per.local();
      for (size_t i = r.begin(); i != r.end(); ++i) one(i, local);
    });
    per.combine_each([&](const TraversalCounters& x) { c.add(x); });
  }

 private:
  std::unique_ptr<Accel> accel_;
};

// `frozen`: one static BVH per frozen time; each ray goes to the tree of
// the nearest time (the frozen set's rays sit exactly on those times).
class FrozenTarget final : public Target {
 public:
  FrozenTarget(const Scene& scene, int K) {
    for (int k = 0; k < K; ++k) {
      BuildOptions o;
      o.kind = AccelKind::Frozen;
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
  bool traceCounted(std::span<const Ray> rays, std::span<Hit> hits, TraversalCounters& c) const override {
    AccelTarget::countedPass(rays, hits, c, [&](size_t i, TraversalCounters& local) {
      treeFor(rays[i].time).intersect(rays[i], hits[i], local);
    });
    return true;
  }
  // One tree's figures (the middle one): the bound is per time.
  AccelStats stats() const override {
    AccelStats s = trees_[trees_.size() / 2]->stats();
    return s;
  }

 private:
  std::vector<std::unique_ptr<Accel>> trees_;
};

bool hitsAgree(const Hit& a, const Hit& b) {
  if (a.valid() != b.valid()) return false;
  if (!a.valid()) return true;
  // Ties on shared edges (other ids, same t) are agreement.
  return std::fabs(a.t - b.t) <= 1e-3f * std::max(1.0f, std::fabs(a.t));
}

std::vector<size_t> sampleIndices(size_t n, size_t sample) {
  std::vector<size_t> idx;
  if (n == 0 || sample == 0) return idx;
  const size_t m = std::min(n, sample);
  for (size_t i = 0; i < m; ++i) idx.push_back(i * n / m);
  return idx;
}

std::string cpuName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      const size_t c = line.find(':');
      return c == std::string::npos ? line : line.substr(c + 2);
    }
  return "unknown";
}

struct Progress {
  std::FILE* out;
  void operator()(const std::string& s) const {
    if (!out) return;
    std::fprintf(out, "\r\033[K%s", s.c_str());
    std::fflush(out);
  }
  void done() const {
    if (out) std::fprintf(out, "\r\033[K");
  }
};

template <class F>
double timedMedian(int repeats, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    const auto s = Clock::now();
    f();
    t.push_back(seconds(s));
  }
  return median(t);
}

// Every k-th of `idx`, k chosen so that at most `cap` remain (evenly spread,
// as `idx` is over the image).
std::vector<size_t> thinned(const std::vector<size_t>& idx, size_t cap) {
  if (cap == 0 || idx.size() <= cap) return idx;
  const size_t k = (idx.size() + cap - 1) / cap;
  std::vector<size_t> out;
  for (size_t j = 0; j < idx.size(); j += k) out.push_back(idx[j]);
  return out;
}

// Mean/max traversal counters over rays[idx]; returns how many rays were counted.
size_t countedFigures(const Target& target, std::span<const Ray> rays, const std::vector<size_t>& idx,
                      std::optional<double>& stepsMean, std::optional<double>* stepsMax, std::optional<double>* boxMean,
                      std::optional<double>& isectsMean, std::optional<uint64_t>* isectsMax) {
  std::vector<Ray> sample;
  for (size_t i : idx) sample.push_back(rays[i]);
  std::vector<Hit> hits(sample.size());
  TraversalCounters c;
  if (!target.traceCounted(sample, hits, c) || c.rays == 0) return 0;
  const double n = double(c.rays);
  stepsMean = double(c.nodesVisited) / n;
  isectsMean = double(c.primitiveTests) / n;
  if (stepsMax) *stepsMax = double(c.maxNodesVisited);
  if (boxMean) *boxMean = double(c.boxTests) / n;
  if (isectsMax) *isectsMax = c.maxPrimitiveTests;
  return sample.size();
}

}  // namespace

void Options::makeQuick() {
  size = 0.02;
  width = height = 128;
  bruteSample = 500;
  countSample = 4000;
  frozenTimes = 8;
  singleBuildSeconds = 0.5;
  passBudgetSeconds = 5.0;
  countBudgetSeconds = 1.25;
}

Candidate accelCandidate(AccelKind kind) {
  Candidate c;
  c.name = std::string(toString(kind));
  c.build = [kind](const Scene& scene) -> std::unique_ptr<Target> {
    BuildOptions o;
    o.kind = kind;
    return std::make_unique<AccelTarget>(Accel::build(scene, o));
  };
  return c;
}

std::vector<Candidate> defaultCandidates(const Options& options, std::vector<std::string>* notes) {
  std::vector<std::string> names = options.accels;
  const auto kinds = availableAccelKinds();
  if (names.empty())
    for (AccelKind k : kinds)
      if (k != AccelKind::Brute) names.push_back(std::string(toString(k)));
  std::vector<Candidate> out;
  for (const std::string& n : names) {
    const auto kind = parseAccelKind(n);
    if (!kind) throw Error("unknown accel '" + n + "'");
    if (std::find(kinds.begin(), kinds.end(), *kind) == kinds.end()) {
      if (notes) notes->push_back(n + ": not available in this build");
      continue;
    }
    if (*kind == AccelKind::Frozen) {
      Candidate c;
      c.name = "frozen";
      c.frozen = true;
      const int K = options.frozenTimes;
      c.build = [K](const Scene& scene) -> std::unique_ptr<Target> { return std::make_unique<FrozenTarget>(scene, K); };
      out.push_back(std::move(c));
    } else {
      out.push_back(accelCandidate(*kind));
    }
  }
  return out;
}

std::vector<Ray> makeRays(const ProceduralScene& ps, const Target& reference, int width, int height, uint64_t seed,
                          const std::vector<float>* snapTimes) {
  const CameraSpec& cam = ps.camera;
  const Vec3f fwd = normalize(cam.target - cam.eye);
  const Vec3f right = normalize(cross(fwd, cam.up));
  const Vec3f up = cross(right, fwd);
  const float tanHalf = std::tan(cam.verticalFovDegrees * float(std::numbers::pi) / 360.0f);
  const float aspect = float(width) / float(height);
  const size_t n = size_t(width) * size_t(height);
  std::vector<Ray> primary(n);
  for (size_t i = 0; i < n; ++i) {
    const float px = (float(i % width) + uniform(seed, i, 0)) / float(width);
    const float py = (float(i / width) + uniform(seed, i, 1)) / float(height);
    Ray& r = primary[i];
    r.org = cam.eye;
    r.dir = fwd + right * ((2 * px - 1) * tanHalf * aspect) + up * ((1 - 2 * py) * tanHalf);
    r.time = uniform(seed, i, 2);
    if (snapTimes && !snapTimes->empty()) {
      float best = (*snapTimes)[0];
      for (float t : *snapTimes)
        if (std::fabs(t - r.time) < std::fabs(best - r.time)) best = t;
      r.time = best;
    }
  }
  std::vector<Hit> hits(n);
  reference.trace(primary, hits);
  const float eps = 1e-4f * std::max(1e-3f, length(cam.eye - cam.target));
  std::vector<Ray> rays = primary;
  for (size_t i = 0; i < n; ++i) {
    const Hit& h = hits[i];
    if (!h.valid() || !(length(h.Ng) > 0.0f)) continue;
    const Ray& p = primary[i];
    Vec3f nrm = normalize(h.Ng);
    if (dot(nrm, p.dir) > 0) nrm = -nrm;
    // Cosine-distributed direction about the normal.
    const float u1 = uniform(seed, i, 3), u2 = uniform(seed ^ 0x5bd1e995u, i, 3);
    const float r = std::sqrt(u1), phi = 2.0f * float(std::numbers::pi) * u2;
    const Vec3f a = std::fabs(nrm.x) > 0.9f ? Vec3f(0, 1, 0) : Vec3f(1, 0, 0);
    const Vec3f t1 = normalize(cross(a, nrm)), t2 = cross(nrm, t1);
    Ray b;
    b.org = p.org + p.dir * h.t + nrm * eps;
    b.dir = t1 * (r * std::cos(phi)) + t2 * (r * std::sin(phi)) + nrm * std::sqrt(std::max(0.0f, 1 - u1));
    b.tnear = eps;
    b.time = p.time;
    rays.push_back(b);
  }
  return rays;
}

Report run(const Options& options) {
  std::vector<std::string> names = options.scenes;
  if (names.empty()) names = proceduralSceneNames();
  std::vector<ProceduralScene> scenes;
  Progress progress{options.progress};
  for (const std::string& n : names) {
    progress("building scene " + n);
    scenes.push_back(makeProceduralScene(n, options.size, options.seed));
  }
  return run(options, scenes);
}

Report run(const Options& options, const std::vector<ProceduralScene>& scenes) {
  if (!options.rays.empty() && scenes.size() != 1)
    throw Error("rays from a file go with exactly one scene (got " + std::to_string(scenes.size()) + ")");
  Report report;
  report.cpu = cpuName();
  report.threads = tbb::info::default_concurrency();
  report.commit = options.commit;
  report.options = options;
  std::vector<Candidate> candidates = defaultCandidates(options, &report.notes);
  for (const Candidate& c : options.extra) candidates.push_back(c);
  Progress progress{options.progress};
  const int K = std::max(1, options.frozenTimes);
  std::vector<float> frozenTimes;
  for (int k = 0; k < K; ++k) frozenTimes.push_back(K == 1 ? 0.5f : float(k) / float(K - 1));

  for (size_t si = 0; si < scenes.size(); ++si) {
    const ProceduralScene& ps = scenes[si];
    const Scene& scene = *ps.scene;
    const std::string tag = "[" + std::to_string(si + 1) + "/" + std::to_string(scenes.size()) + " " + ps.name + "] ";

    // Reference for the bounces: the fastest structure at hand on every scene
    // (bvh-interp is pathological on `rotate`, which is the point of it).
    progress(tag + "generating rays");
    std::unique_ptr<Target> reference;
    for (AccelKind k : {AccelKind::Embree, AccelKind::Stbvh, AccelKind::BvhInterp, AccelKind::Brute}) {
      try {
        reference = accelCandidate(k).build(scene);
        break;
      } catch (const Error&) {
      }
    }
    const uint64_t seed = options.seed ^ hashName(ps.name);
    const std::vector<Ray> rays =
        options.rays.empty() ? makeRays(ps, *reference, options.width, options.height, seed) : options.rays;
    const std::vector<Ray> frozenRays = makeRays(ps, *reference, options.width, options.height, seed, &frozenTimes);
    reference.reset();

    // Brute on samples of both sets, once per scene.
    progress(tag + "brute reference on a sample");
    auto bruteOn = [&](const std::vector<Ray>& set, std::vector<size_t>& idx, std::vector<Hit>& hits) {
      idx = sampleIndices(set.size(), options.bruteSample);
      std::vector<Ray> sample;
      for (size_t i : idx) sample.push_back(set[i]);
      hits.assign(sample.size(), Hit());
      BuildOptions o;
      o.kind = AccelKind::Brute;
      Accel::build(scene, o)->intersect(sample, hits);
    };
    std::vector<size_t> bruteIdx, bruteFrozenIdx;
    std::vector<Hit> bruteHits, bruteFrozenHits;
    bruteOn(rays, bruteIdx, bruteHits);
    bruteOn(frozenRays, bruteFrozenIdx, bruteFrozenHits);
    const std::vector<size_t> countIdx = sampleIndices(rays.size(), options.countSample);
    const std::vector<size_t> countFrozenIdx = sampleIndices(frozenRays.size(), options.countSample);

    std::vector<std::vector<Hit>> allHits;  // per result: main-set hits (for the embree check)
    std::vector<size_t> strides;            // per result: which of them were traced (i % stride == 0)
    const size_t firstResult = report.results.size();
    for (const Candidate& cand : candidates) {
      const std::string ctag = tag + cand.name + ": ";
      Result res;
      res.scene = ps.name;
      res.accel = cand.name;
      // Build: median of `repeats`, or once when slow.
      progress(ctag + "building");
      std::unique_ptr<Target> target;
      std::vector<double> builds;
      try {
        for (int b = 0; b < std::max(1, options.repeats); ++b) {
          target.reset();
          const auto s = Clock::now();
          target = cand.build(scene);
          builds.push_back(seconds(s));
          if (builds.back() > options.singleBuildSeconds) break;
        }
      } catch (const Error& e) {
        report.notes.push_back(ps.name + " / " + cand.name + ": " + e.what());
        continue;
      }
      const AccelStats st = target->stats();
      res.builds = int(builds.size());
      res.buildS = median(builds);
      if (cand.frozen) res.buildS /= double(K);  // per tree
      res.primitives = st.primitives;
      res.buildMprims = res.buildS > 0 ? double(st.primitives) / res.buildS * 1e-6 : 0.0;
      res.bytes = st.bytes;
      res.peakBuildBytes = st.peakBuildBytes;
      if (std::isfinite(st.sahCost)) res.sah = st.sahCost;

      // Times passes over `set`, or over every stride-th ray when the whole
      // set would not fit the time budget (estimated from a probe over the
      // whole image: rays are in pixel order, so a prefix would be all sky).
      // `hits` gets the traced rays' hits; returns the stride.
      double perRayMt = 0.0;  // the slower of the probes (main and frozen set), s per ray on all threads
      auto traceSet = [&](const std::vector<Ray>& set, std::vector<Hit>& hits, double& st1, double& mt) {
        hits.assign(set.size(), Hit());
        auto every = [&](size_t stride) {
          std::vector<Ray> out;
          for (size_t i = 0; i < set.size(); i += stride) out.push_back(set[i]);
          return out;
        };
        const size_t probeStride = std::max<size_t>(1, set.size() / std::max<size_t>(1, options.minTimedRays));
        const std::vector<Ray> probe = every(probeStride);
        std::vector<Hit> probeHits(probe.size());
        const auto ps0 = Clock::now();
        target->trace(probe, probeHits);
        const double perRay = seconds(ps0) / double(std::max<size_t>(probe.size(), 1));
        perRayMt = std::max(perRayMt, perRay);
        const double passes = double(std::max(1, options.repeats)) * (st1 < 0 ? 1.0 : 1.0 + double(report.threads));
        size_t stride = 1;
        if (perRay * double(set.size()) * passes > options.passBudgetSeconds)
          stride = std::min(probeStride, size_t(std::ceil(perRay * double(set.size()) * passes / options.passBudgetSeconds)));
        const std::vector<Ray> timed = stride == 1 ? set : every(stride);
        std::vector<Hit> timedHits(timed.size());
        progress(ctag + "tracing, 1 thread");
        tbb::task_arena one(1);
        const double tst =
            st1 < 0 ? 0.0 : timedMedian(options.repeats, [&] { one.execute([&] { target->trace(timed, timedHits); }); });
        progress(ctag + "tracing, all threads");
        const double tmt = timedMedian(options.repeats, [&] { target->trace(timed, timedHits); });
        for (size_t k = 0; k < timed.size(); ++k) hits[k * stride] = timedHits[k];
        if (st1 >= 0) st1 = tst > 0 ? double(timed.size()) / tst * 1e-6 : 0.0;
        mt = tmt > 0 ? double(timed.size()) / tmt * 1e-6 : 0.0;
        return stride;
      };
      // Agreement with brute on the sampled rays that were traced.
      size_t checked = 0;
      auto bruteMismatches = [&](const std::vector<size_t>& idx, const std::vector<Hit>& ref,
                                 const std::vector<Hit>& hits, size_t stride) {
        size_t m = 0;
        checked = 0;
        for (size_t j = 0; j < idx.size(); ++j) {
          if (idx[j] % stride != 0) continue;
          ++checked;
          m += !hitsAgree(ref[j], hits[idx[j]]);
        }
        return m;
      };

      // The frozen set, traced by every structure.
      std::vector<Hit> frozenHits;
      double noSt = -1.0;
      const size_t frozenStride = traceSet(frozenRays, frozenHits, noSt, res.frozenSet.mraysMt);
      res.frozenSet.timedRays = (frozenRays.size() + frozenStride - 1) / frozenStride;
      res.frozenSet.rays = frozenRays.size();
      // The counted passes share countBudgetSeconds (counting costs about
      // twice a plain trace); the main set is counted after its timed pass,
      // which refines the estimate.
      auto countCap = [&] {
        const double perCounted = 2.0 * perRayMt;
        if (perCounted <= 0.0) return options.countSample;
        return std::max(options.minCountedRays, size_t(0.5 * options.countBudgetSeconds / perCounted));
      };
      progress(ctag + "counting");
      countedFigures(*target, frozenRays, thinned(countFrozenIdx, countCap()), res.frozenSet.stepsMean, nullptr,
                     nullptr, res.frozenSet.isectsMean, nullptr);
      res.frozenSet.mismatches =
          bruteMismatches(bruteFrozenIdx, bruteFrozenHits, frozenHits, frozenStride);

      std::vector<Hit> hits;
      if (cand.frozen) {
        // Its job is the frozen set: the row reports it.
        double st1 = 0.0;
        const size_t stride = traceSet(frozenRays, hits, st1, res.mraysMt);
        res.timedRays = (frozenRays.size() + stride - 1) / stride;
        res.mraysSt = st1;
        res.rays = frozenRays.size();
        res.stepsMean = res.frozenSet.stepsMean;
        res.isectsMean = res.frozenSet.isectsMean;
        res.countedRays = countedFigures(*target, frozenRays, thinned(countFrozenIdx, countCap()), res.stepsMean,
                                         &res.stepsMax, &res.boxTestsMean, res.isectsMean, &res.isectsMax);
        res.mismatchesBrute = bruteMismatches(bruteFrozenIdx, bruteFrozenHits, hits, stride);
        res.bruteChecked = checked;
        hits.clear();
        strides.push_back(1);
      } else {
        double st1 = 0.0;
        const size_t stride = traceSet(rays, hits, st1, res.mraysMt);
        res.timedRays = (rays.size() + stride - 1) / stride;
        strides.push_back(stride);
        res.mraysSt = st1;
        res.rays = rays.size();
        progress(ctag + "counting");
        res.countedRays = countedFigures(*target, rays, thinned(countIdx, countCap()), res.stepsMean, &res.stepsMax,
                                         &res.boxTestsMean, res.isectsMean, &res.isectsMax);
        res.mismatchesBrute = bruteMismatches(bruteIdx, bruteHits, hits, stride);
        res.bruteChecked = checked;
      }
      res.mismatches = res.mismatchesBrute;
      report.results.push_back(std::move(res));
      allHits.push_back(std::move(hits));
    }

    // Against Embree on every ray of the main set.
    const Result* embree = nullptr;
    size_t embreeAt = 0;
    for (size_t r = firstResult; r < report.results.size(); ++r)
      if (report.results[r].accel == "embree") {
        embree = &report.results[r];
        embreeAt = r - firstResult;
      }
    if (embree) {
      const std::vector<Hit>& eh = allHits[embreeAt];
      for (size_t r = firstResult; r < report.results.size(); ++r) {
        Result& res = report.results[r];
        const std::vector<Hit>& h = allHits[r - firstResult];
        if (&res == embree || h.empty()) continue;
        size_t m = 0;
        const size_t sa = strides[r - firstResult], sb = strides[embreeAt];
        for (size_t i = 0; i < std::min(h.size(), eh.size()); ++i)
          if (i % sa == 0 && i % sb == 0) m += !hitsAgree(eh[i], h[i]);
        res.mismatchesEmbree = m;
        res.mismatches += m;
      }
    }
  }
  progress.done();
  return report;
}

}  // namespace mbrt::bench
