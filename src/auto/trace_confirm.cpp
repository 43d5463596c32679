#include "auto/trace_confirm.h"

#include <time.h>

#include <algorithm>
#include <cstdio>

#include "auto/ray_cost.h"

namespace mbrt::detail {
namespace {

TraceTimer& installedTimer() {
  static TraceTimer timer;  // empty: threadTimePerRay
  return timer;
}

double threadSeconds() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string nanoseconds(double seconds) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f ns", seconds * 1e9);
  return buf;
}

}  // namespace

size_t chooseByMeasurement(size_t modelChoice, std::span<const std::optional<double>> measured) {
  if (modelChoice >= measured.size() || !measured[modelChoice]) return modelChoice;
  size_t best = modelChoice;
  for (size_t i = 0; i < measured.size(); ++i)
    if (measured[i] && *measured[i] < *measured[best]) best = i;
  return *measured[best] < *measured[modelChoice] * (1.0 - kMeasuredMargin) ? best : modelChoice;
}

std::vector<bool> worthMeasuring(std::span<const TraceCandidate> candidates, size_t modelChoice) {
  std::vector<bool> measure(candidates.size(), false);
  if (modelChoice >= candidates.size()) return measure;
  const double limit = candidates[modelChoice].modelCost * (1.0 + kModelError);
  size_t count = 0;
  for (size_t i = 0; i < candidates.size(); ++i)
    if (candidates[i].structure && candidates[i].modelCost <= limit) {
      measure[i] = true;
      ++count;
    }
  if (count < 2) measure.assign(candidates.size(), false);
  return measure;
}

double threadTimePerRay(const Structure& s, std::span<const RayQuery> rays) {
  if (rays.empty()) return 0.0;
  const double start = threadSeconds();
  for (const RayQuery& r : rays) {
    RayQuery q = r;
    Hit hit;
    s.intersect(q, hit);
  }
  return (threadSeconds() - start) / double(rays.size());
}

TraceChoice confirmByTrace(std::span<const TraceCandidate> candidates, size_t modelChoice,
                           const std::vector<RayQuery>& rays, const BuildOptions& options) {
  TraceChoice choice;
  choice.chosen = modelChoice;
  choice.measured.assign(candidates.size(), std::nullopt);
  const std::vector<bool> measure = worthMeasuring(candidates, modelChoice);
  if (!options.autoConfirmByTrace || rays.empty() || std::find(measure.begin(), measure.end(), true) == measure.end())
    return choice;
  // The sample and its bounces off the model's choice's hits (every correct
  // candidate finds the same ones).
  std::vector<Hit> hits(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    RayQuery q = rays[i];
    candidates[modelChoice].structure->intersect(q, hits[i]);
  }
  std::vector<RayQuery> traced = rays;
  const std::vector<RayQuery> bounces = bounceRays(rays, hits);
  traced.insert(traced.end(), bounces.begin(), bounces.end());
  const TraceTimer& timer = installedTimer();
  std::vector<std::vector<double>> rounds(candidates.size());
  for (int r = 0; r < kTraceRounds; ++r)
    for (size_t i = 0; i < candidates.size(); ++i) {
      if (!measure[i]) continue;
      const Structure& s = *candidates[i].structure;
      if (timer) {
        rounds[i].push_back(timer(s, traced));
      } else {
        threadTimePerRay(s, traced);  // warms the caches
        rounds[i].push_back(threadTimePerRay(s, traced));
      }
    }
  for (size_t i = 0; i < candidates.size(); ++i)
    if (measure[i]) choice.measured[i] = median(rounds[i]);
  choice.chosen = chooseByMeasurement(modelChoice, choice.measured);
  std::string figures;
  for (size_t i = 0; i < candidates.size(); ++i)
    if (choice.measured[i])
      figures += (figures.empty() ? "" : ", ") + candidates[i].name + " " + nanoseconds(*choice.measured[i]);
  choice.line = "; within the model's error, measured by a trace of " + std::to_string(traced.size()) +
                " sampled rays (thread time per ray, median of " + std::to_string(kTraceRounds) +
                " interleaved rounds): " + figures + ": " +
                (choice.chosen == modelChoice ? "the model's choice, " + candidates[modelChoice].name + ", stands"
                                              : candidates[choice.chosen].name + " kept instead of the model's " +
                                                    candidates[modelChoice].name);
  return choice;
}

ScopedTraceTimer::ScopedTraceTimer(TraceTimer timer) : previous_(std::move(installedTimer())) {
  installedTimer() = std::move(timer);
}
ScopedTraceTimer::~ScopedTraceTimer() { installedTimer() = std::move(previous_); }

}  // namespace mbrt::detail
