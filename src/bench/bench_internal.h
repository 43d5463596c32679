// Helpers the bench's files share: counter-based random numbers, clocks,
// medians and the progress line.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "mbrt/splitmix.h"

namespace mbrt::bench {

using Clock = std::chrono::steady_clock;

inline double seconds(Clock::time_point a) { return std::chrono::duration<double>(Clock::now() - a).count(); }

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

// Counter-based random numbers: the same rays whatever the thread count.
inline uint64_t mix(uint64_t x) { return mix64(x + kSplitMixGamma); }
inline float uniform(uint64_t seed, uint64_t index, uint64_t stream) {
  return toUnitFloat(mix(seed ^ mix(index * 4 + stream)));
}
inline uint64_t hashName(const std::string& s) {
  uint64_t h = 1469598103934665603ull;
  for (char c : s) h = (h ^ uint8_t(c)) * 1099511628211ull;
  return h;
}

// Progress on stderr. On a terminal every stage overwrites one line (control
// codes); elsewhere (a log) only the start of each structure gets a line.
struct Progress {
  std::FILE* out = nullptr;
  bool terminal = false;
  void stage(const std::string& s) const {
    if (!out || !terminal) return;
    std::fprintf(out, "\r\033[K%s", s.c_str());
    std::fflush(out);
  }
  void step(const std::string& s) const {
    if (!out) return;
    if (terminal) return stage(s);
    std::fprintf(out, "%s\n", s.c_str());
    std::fflush(out);
  }
  void done() const {
    if (out && terminal) std::fprintf(out, "\r\033[K");
  }
};

}  // namespace mbrt::bench
