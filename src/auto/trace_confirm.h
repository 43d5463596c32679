// The measured confirmation of `auto`'s choices (docs/auto.md, "Measured
// confirmation"). The cost model (ray_cost.h) counts work; its weights were
// fitted to time with an error of ~8 % rms, and the same counts can cost
// more in one structure than in another (an instance's ray transform, a
// motion node against a static one). Where candidates lie within
// kModelError of the model's choice, each is traced on the same sampled rays,
// several rounds interleaved (candidate A, B, A, B, ...: a load that comes
// and goes slows all of them alike), each timed pass after an untimed one
// that warms the caches as a renderer's steady state does; the median of
// each candidate's rounds is its measured cost. The measured best is kept
// only when it beats the model's choice by more than kMeasuredMargin: on a
// tie within the noise the model's choice stands.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/structure.h"
#include "mbrt/build_options.h"

namespace mbrt::detail {

constexpr double kModelError = 0.15;      // ~2x the model's rms error against thread time
constexpr double kMeasuredMargin = 0.03;  // a measured gain smaller than this keeps the model's choice
constexpr int kTraceRounds = 5;

struct TraceCandidate {
  std::string name;
  const Structure* structure = nullptr;
  double modelCost = 0;
};

struct TraceChoice {
  size_t chosen = 0;
  std::vector<std::optional<double>> measured;  // per candidate: median seconds per ray; none: not measured
  std::string line;                             // for mbrt stats; empty when nothing was measured
};

// The decision alone, given the model's choice and the measurements
// (deterministic: what the tests inject).
size_t chooseByMeasurement(size_t modelChoice, std::span<const std::optional<double>> measured);

// Which candidates the trace measures: those within kModelError of the
// model's choice; none when fewer than two are.
std::vector<bool> worthMeasuring(std::span<const TraceCandidate> candidates, size_t modelChoice);

// Seconds per ray of one pass of `rays` through a structure.
using TraceTimer = std::function<double(const Structure&, std::span<const RayQuery>)>;

// The thread CPU time of one pass (what a loaded machine takes least from:
// time the thread waits for a core is not counted).
double threadTimePerRay(const Structure& s, std::span<const RayQuery> rays);

// Confirms (or overturns) the model's choice by a trace of `rays` and their
// bounces; with options.autoConfirmByTrace false, or nothing within the
// model's error, the model's choice.
TraceChoice confirmByTrace(std::span<const TraceCandidate> candidates, size_t modelChoice,
                           const std::vector<RayQuery>& rays, const BuildOptions& options);

// Replaces the timer while it lives (tests: measurements injected, so that
// the choice is known). One at a time, on the building thread.
class ScopedTraceTimer {
 public:
  explicit ScopedTraceTimer(TraceTimer timer);
  ~ScopedTraceTimer();
  ScopedTraceTimer(const ScopedTraceTimer&) = delete;
  ScopedTraceTimer& operator=(const ScopedTraceTimer&) = delete;

 private:
  TraceTimer previous_;
};

}  // namespace mbrt::detail
