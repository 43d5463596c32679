// The benchmark engine: per scene the ray sets, then per structure its build,
// timed passes over each set, a counted pass, and hit agreement with brute
// (on a sample of every set) and embree-robust (on every ray both traced).
#include "mbrt/bench.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <fstream>

#include "bench/bench_internal.h"

namespace mbrt::bench {
namespace {

std::vector<size_t> sampleIndices(size_t n, size_t sample) {
  std::vector<size_t> idx;
  if (n == 0 || sample == 0) return idx;
  const size_t m = std::min(n, sample);
  for (size_t i = 0; i < m; ++i) idx.push_back(i * n / m);
  return idx;
}

// Every k-th of `idx`, k chosen so that at most `cap` remain (evenly spread).
std::vector<size_t> thinned(const std::vector<size_t>& idx, size_t cap) {
  if (cap == 0 || idx.size() <= cap) return idx;
  const size_t k = (idx.size() + cap - 1) / cap;
  std::vector<size_t> out;
  for (size_t j = 0; j < idx.size(); j += k) out.push_back(idx[j]);
  return out;
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

// What a structure answered per ray, compactly: the hit distance (inf on a
// miss), or for occlusion 0 (occluded) / inf (not).
using Answers = std::vector<float>;

bool agree(float a, float b) {
  if (std::isinf(a) || std::isinf(b)) return std::isinf(a) && std::isinf(b);
  // Ties on shared edges (other ids, same t) are agreement.
  return std::fabs(a - b) <= 1e-3f * std::max(1.0f, std::fabs(a));
}

// Traces `rays` with the set's query, into answers.
void pass(const Target& target, std::span<const Ray> rays, bool occlusion, Answers& out) {
  out.assign(rays.size(), kInf);
  if (occlusion) {
    std::vector<uint8_t> occ(rays.size());
    target.occluded(rays, occ);
    for (size_t i = 0; i < rays.size(); ++i)
      if (occ[i]) out[i] = 0.0f;
  } else {
    std::vector<Hit> hits(rays.size());
    target.trace(rays, hits);
    for (size_t i = 0; i < rays.size(); ++i)
      if (hits[i].valid()) out[i] = hits[i].t;
  }
}

double rate(const Answers& a) {
  size_t hit = 0;
  for (float t : a) hit += !std::isinf(t);
  return a.empty() ? 0.0 : double(hit) / double(a.size());
}

// A structure's answers on one set: every stride-th ray's.
struct SetOutput {
  Answers answers;  // indexed by ray / stride
  size_t stride = 1;
};

// Brute on a sample of one set.
struct BruteSample {
  std::vector<size_t> idx;
  Answers answers;
};

class Runner {
 public:
  Runner(const Options& o, Report& r) : o_(o), report_(r), progress_{o.progress, o.progressTerminal} {
    const int K = std::max(1, o.frozenTimes);
    for (int k = 0; k < K; ++k) frozenTimes_.push_back(K == 1 ? 0.5f : float(k) / float(K - 1));
  }

  void scene(const ProceduralScene& ps, const std::string& tag, const std::vector<Candidate>& candidates) {
    sceneTag_ = tag_ = tag;
    prepareSets(ps);
    bruteSamples(*ps.scene);
    outputs_.clear();
    const size_t first = report_.results.size();
    for (const Candidate& cand : candidates) measure(ps, cand);
    embreeAgreement(first);
    progress_.done();
  }

 private:
  bool wanted(RaySet set) const { return !o_.secondaryOnly || set == RaySet::Secondary; }

  // The sets, generated from the primary hits of an mbrt reference (fast on
  // every scene: bvh-interp is pathological on `rotate`, which is the point
  // of it; not Embree, which loses hits far from the origin), and their hit
  // rates.
  void prepareSets(const ProceduralScene& ps) {
    progress_.stage(tag_ + "generating rays");
    std::unique_ptr<Target> reference;
    for (AccelKind k : {AccelKind::Stbvh, AccelKind::BvhInterp, AccelKind::Brute}) {
      try {
        reference = accelCandidate(k, BuildOptions::EmbreeMode::Robust).build(*ps.scene);
        break;
      } catch (const Error&) {
      }
    }
    const uint64_t seed = o_.seed ^ hashName(ps.name);
    sets_ = makeRaySets(ps, *reference, o_.width, o_.height, seed, frozenTimes_, o_.secondaryOnly);
    if (!o_.rays.empty()) {
      sets_.sets[size_t(RaySet::Secondary)] = o_.rays;
      sets_.bounces = sets_.inward = 0;
    }
    SceneInfo info;
    info.name = ps.name;
    info.bounces = sets_.bounces;
    info.inward = sets_.inward;
    for (RaySet s : kAllRaySets) {
      Answers a;
      pass(*reference, sets_[s], isOcclusion(s), a);
      info.sets[size_t(s)] = {sets_[s].size(), rate(a)};
    }
    info.primitives = reference->stats().primitives;
    report_.scenes.push_back(info);
  }

  void bruteSamples(const Scene& scene) {
    progress_.stage(tag_ + "brute reference on a sample");
    BuildOptions bo;
    bo.kind = AccelKind::Brute;
    auto brute = Accel::build(scene, bo);
    for (RaySet s : kAllRaySets) {
      BruteSample& b = brute_[size_t(s)];
      b.idx = sampleIndices(sets_[s].size(), o_.bruteSample);
      std::vector<Ray> sample;
      for (size_t i : b.idx) sample.push_back(sets_[s][i]);
      b.answers.assign(sample.size(), kInf);
      if (isOcclusion(s)) {
        std::vector<uint8_t> occ(sample.size());
        brute->occluded(sample, occ);
        for (size_t j = 0; j < occ.size(); ++j)
          if (occ[j]) b.answers[j] = 0.0f;
      } else {
        std::vector<Hit> hits(sample.size());
        brute->intersect(sample, hits);
        for (size_t j = 0; j < hits.size(); ++j)
          if (hits[j].valid()) b.answers[j] = hits[j].t;
      }
    }
  }

  // Build: median of `repeats`, or once when slow. False when it failed.
  bool build(const Scene& scene, const Candidate& cand, Result& res, std::unique_ptr<Target>& target) {
    progress_.step(tag_ + "building");
    std::vector<double> builds;
    try {
      for (int b = 0; b < std::max(1, o_.repeats); ++b) {
        target.reset();
        const auto s = Clock::now();
        target = cand.build(scene);
        builds.push_back(seconds(s));
        if (builds.back() > o_.singleBuildSeconds) break;
      }
    } catch (const Error& e) {
      report_.notes.push_back(res.scene + " / " + cand.name + ": " + e.what());
      return false;
    }
    const AccelStats st = target->stats();
    res.builds = int(builds.size());
    res.buildS = median(builds);
    if (cand.frozen) res.buildS /= double(frozenTimes_.size());  // per structure
    res.primitives = st.primitives;
    res.buildMprims = res.buildS > 0 ? double(st.primitives) / res.buildS * 1e-6 : 0.0;
    res.bytes = st.bytes;
    res.peakBuildBytes = st.peakBuildBytes;
    if (std::isfinite(st.sahCost)) res.sah = st.sahCost;
    return true;
  }

  // Times passes over a set, or over every stride-th ray when the whole set
  // would not fit the time budget (estimated from a probe spread over the
  // whole set: a prefix of the primaries would be all sky). Returns the
  // answers of the traced rays; perRay gets the probe's seconds per ray.
  SetOutput timeSet(const Target& target, RaySet set, RaySet mainSet, bool oneThread, SetResult& fig,
                    double& perRay) {
    const std::vector<Ray>& rays = sets_[set];
    const bool occl = isOcclusion(set);
    SetOutput out;
    fig.traced = true;
    fig.rays = rays.size();
    if (rays.empty()) return out;
    auto every = [&](size_t stride) {
      std::vector<Ray> v;
      for (size_t i = 0; i < rays.size(); i += stride) v.push_back(rays[i]);
      return v;
    };
    const size_t probeStride = std::max<size_t>(1, rays.size() / std::max<size_t>(1, o_.minTimedRays));
    Answers scratch;
    const auto p0 = Clock::now();
    pass(target, every(probeStride), occl, scratch);
    perRay = seconds(p0) / double(scratch.size());
    const int repeats = std::max(1, o_.repeats);
    const double cost = perRay * double(rays.size()) * repeats * (oneThread ? 1.0 + report_.threads : 1.0);
    // The main set gets the whole budget, the others a quarter of it each.
    const double budget = set == mainSet ? o_.passBudgetSeconds : 0.25 * o_.passBudgetSeconds;
    if (cost > budget) out.stride = std::min(probeStride, size_t(std::ceil(cost / budget)));
    const std::vector<Ray> timed = out.stride == 1 ? rays : every(out.stride);
    fig.timedRays = timed.size();
    auto timedMedian = [&](auto&& f) {
      std::vector<double> t;
      for (int i = 0; i < repeats; ++i) {
        const auto s = Clock::now();
        f();
        t.push_back(seconds(s));
      }
      return median(t);
    };
    const std::string what = tag_ + "tracing the " + std::string(toString(set)) + " set, ";
    if (oneThread) {
      progress_.stage(what + "1 thread");
      tbb::task_arena one(1);
      const double t1 = timedMedian([&] { one.execute([&] { pass(target, timed, occl, out.answers); }); });
      fig.mraysSt = t1 > 0 ? double(timed.size()) / t1 * 1e-6 : 0.0;
    }
    progress_.stage(what + "all threads");
    const double tm = timedMedian([&] { pass(target, timed, occl, out.answers); });
    fig.mraysMt = tm > 0 ? double(timed.size()) / tm * 1e-6 : 0.0;
    return out;
  }

  // Traversal counters over the row's main set, on the sample thinned to
  // the counting budget (counting costs about twice a plain trace).
  void count(const Target& target, RaySet set, double perRay, Result& res) {
    progress_.stage(tag_ + "counting");
    const std::vector<Ray>& rays = sets_[set];
    size_t cap = o_.countSample;
    if (perRay > 0.0) cap = std::max(o_.minCountedRays, size_t(o_.countBudgetSeconds / (2.0 * perRay)));
    std::vector<Ray> sample;
    for (size_t i : thinned(sampleIndices(rays.size(), o_.countSample), cap)) sample.push_back(rays[i]);
    std::vector<Hit> hits(sample.size());
    TraversalCounters c;
    if (!target.traceCounted(sample, hits, c) || c.rays == 0) return;
    const double n = double(c.rays);
    res.stepsMean = double(c.nodesVisited) / n;
    res.isectsMean = double(c.primitiveTests) / n;
    res.stepsMax = double(c.maxNodesVisited);
    res.boxTestsMean = double(c.boxTests) / n;
    res.isectsMax = c.maxPrimitiveTests;
    res.countedRays = sample.size();
  }

  // Agreement with brute on the sampled rays that were traced.
  void bruteAgreement(RaySet set, const SetOutput& out, SetResult& fig) const {
    const BruteSample& b = brute_[size_t(set)];
    for (size_t j = 0; j < b.idx.size(); ++j) {
      if (b.idx[j] % out.stride != 0) continue;
      ++fig.bruteChecked;
      fig.mismatchesBrute += !agree(b.answers[j], out.answers[b.idx[j] / out.stride]);
    }
  }

  void measure(const ProceduralScene& ps, const Candidate& cand) {
    Result res;
    res.scene = ps.name;
    res.accel = cand.name;
    res.frozen = cand.frozen;
    res.peer = cand.peer;
    tag_ = sceneTag_ + cand.name + ": ";
    std::unique_ptr<Target> target;
    if (!build(*ps.scene, cand, res, target)) return;
    std::array<SetOutput, kRaySets> outputs;
    for (RaySet s : kAllRaySets) {
      // Frozen rows are static structures: they trace the frozen set only.
      if (!wanted(s) || (cand.frozen && s != RaySet::Frozen)) continue;
      const bool main = s == res.mainSet();
      double perRay = 0.0;
      SetResult& fig = res.set(s);
      // One thread too on the row's main set (the headline), all threads on
      // the others: with the shorter budget of the other sets, that keeps
      // the default run within its half hour.
      const bool oneThread = !o_.secondaryOnly && main;
      outputs[size_t(s)] = timeSet(*target, s, res.mainSet(), oneThread, fig, perRay);
      bruteAgreement(s, outputs[size_t(s)], fig);
      if (main) count(*target, s, perRay, res);
    }
    tag_ = sceneTag_;
    report_.results.push_back(std::move(res));
    outputs_.push_back(std::move(outputs));
  }

  // Every row against embree-robust (watertight) on every ray both traced.
  void embreeAgreement(size_t first) {
    size_t robust = SIZE_MAX;
    for (size_t r = first; r < report_.results.size(); ++r)
      if (report_.results[r].accel == "embree-robust") robust = r;
    if (robust == SIZE_MAX) return;
    for (RaySet s : kAllRaySets) {
      const SetOutput& ref = outputs_[robust - first][size_t(s)];
      if (!report_.results[robust].set(s).traced) continue;
      for (size_t r = first; r < report_.results.size(); ++r) {
        SetResult& fig = report_.results[r].set(s);
        const SetOutput& out = outputs_[r - first][size_t(s)];
        if (r == robust || !fig.traced) continue;
        size_t m = 0;
        for (size_t i = 0; i < fig.rays; ++i)
          if (i % out.stride == 0 && i % ref.stride == 0) m += !agree(ref.answers[i / ref.stride], out.answers[i / out.stride]);
        fig.mismatchesEmbree = m;
      }
    }
  }

  const Options& o_;
  Report& report_;
  Progress progress_;
  std::vector<float> frozenTimes_;
  std::string sceneTag_, tag_;  // "[i/n scene] ", and that with the structure's name
  RaySets sets_;
  std::array<BruteSample, kRaySets> brute_;
  std::vector<std::array<SetOutput, kRaySets>> outputs_;  // per result of the scene
};

}  // namespace

size_t Result::mismatches() const {
  size_t m = 0;
  for (const SetResult& s : sets) m += s.mismatchesBrute + s.mismatchesEmbree.value_or(0);
  return m;
}

void Options::makeQuick() {
  size = 0.02;
  width = height = 128;
  bruteSample = 500;
  countSample = 4000;
  frozenTimes = 8;
  singleBuildSeconds = 0.5;
  passBudgetSeconds = 2.0;
  countBudgetSeconds = 1.0;
}

Report run(const Options& options) {
  std::vector<std::string> names = options.scenes;
  if (names.empty()) names = proceduralSceneNames();
  std::vector<ProceduralScene> scenes;
  Progress progress{options.progress, options.progressTerminal};
  for (const std::string& n : names) {
    progress.stage("building scene " + n);
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
  Runner runner(options, report);
  for (size_t si = 0; si < scenes.size(); ++si) {
    const std::string tag =
        "[" + std::to_string(si + 1) + "/" + std::to_string(scenes.size()) + " " + scenes[si].name + "] ";
    runner.scene(scenes[si], tag, candidates);
  }
  return report;
}

}  // namespace mbrt::bench
