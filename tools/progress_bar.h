// A one-line progress bar on stderr for long jobs: percentage, rays/s and
// the time left, redrawn at most five times a second, shown only after the
// first second (short jobs print nothing).
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace mbrt::tools {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}

  void update(double fraction, uint64_t rays, double seconds) {
    if (!enabled_ || seconds < 1.0 || seconds - lastDraw_ < 0.2) return;
    lastDraw_ = seconds;
    drawn_ = true;
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth + 0.5);
    std::string bar(size_t(filled), '#');
    bar.resize(kWidth, '.');
    const double left = fraction > 0.0 ? seconds * (1.0 - fraction) / fraction : 0.0;
    std::fprintf(stderr, "\r[%s] %5.1f%%  %7.2f Mrays/s  %s left   ", bar.c_str(), 100.0 * fraction,
                 double(rays) / seconds * 1e-6, formatSeconds(left).c_str());
    std::fflush(stderr);
  }

  // Ends the line when a bar was drawn.
  void finish() {
    if (drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
  }

  static std::string formatSeconds(double s) {
    char buf[32];
    if (s < 60.0) std::snprintf(buf, sizeof buf, "%.0f s", s);
    else if (s < 3600.0) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s / 60.0), int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s / 3600.0), int(s / 60.0) % 60);
    return buf;
  }

 private:
  bool enabled_;
  bool drawn_ = false;
  double lastDraw_ = 0.0;
};

}  // namespace mbrt::tools
