// Progress on stderr for long jobs, shown only after the first second (short
// jobs print nothing). Terminal control codes (carriage return, erase line)
// are written only when stderr is a terminal; elsewhere (a log file, a pipe)
// progress is plain lines.
#pragma once

#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

namespace mbrt::tools {

inline bool stderrIsTerminal() { return ::isatty(STDERR_FILENO) == 1; }

inline std::string formatSeconds(double s) {
  char buf[32];
  if (s < 60.0) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 3600.0) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s / 60.0), int(s) % 60);
  else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s / 3600.0), int(s / 60.0) % 60);
  return buf;
}

// A progress bar: percentage, rays/s and the time left. On a terminal one
// line redrawn at most five times a second; elsewhere one line per tenth of
// the job.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled), terminal_(stderrIsTerminal()) {}

  void update(double fraction, uint64_t rays, double seconds) {
    if (!enabled_ || seconds < 1.0) return;
    const double left = fraction > 0.0 ? seconds * (1.0 - fraction) / fraction : 0.0;
    const double mrays = double(rays) / seconds * 1e-6;
    if (!terminal_) {
      const int tenth = int(fraction * 10.0);
      if (tenth <= lastTenth_) return;
      lastTenth_ = tenth;
      std::fprintf(stderr, "mbrt: %5.1f%%  %7.2f Mrays/s  %s left\n", 100.0 * fraction, mrays,
                   formatSeconds(left).c_str());
      return;
    }
    if (seconds - lastDraw_ < 0.2) return;
    lastDraw_ = seconds;
    drawn_ = true;
    constexpr int kWidth = 30;
    const int filled = int(fraction * kWidth + 0.5);
    std::string bar(size_t(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r[%s] %5.1f%%  %7.2f Mrays/s  %s left   ", bar.c_str(), 100.0 * fraction, mrays,
                 formatSeconds(left).c_str());
    std::fflush(stderr);
  }

  // Ends the line when a bar was drawn.
  void finish() {
    if (drawn_) std::fprintf(stderr, "\n");
    drawn_ = false;
  }

 private:
  bool enabled_;
  bool terminal_;
  bool drawn_ = false;
  double lastDraw_ = 0.0;
  int lastTenth_ = 0;
};

// "building stbvh ... 12 s" with a turning bar on a terminal while a job
// without progress figures (a build) runs, from its second second on; the
// line is erased when the job ends. Does nothing unless enabled and stderr
// is a terminal.
class BuildSpinner {
 public:
  BuildSpinner(bool enabled, std::string label) : label_(std::move(label)) {
    if (enabled && stderrIsTerminal()) thread_ = std::thread([this] { spin(); });
  }
  ~BuildSpinner() { stop(); }
  BuildSpinner(const BuildSpinner&) = delete;
  BuildSpinner& operator=(const BuildSpinner&) = delete;

  void stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    wake_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

 private:
  void spin() {
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_);
    if (wake_.wait_for(lock, std::chrono::seconds(1), [this] { return done_; })) return;
    static const char kTurn[] = "|/-\\";
    for (int i = 0; !done_; ++i) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::fprintf(stderr, "\rmbrt: %s %c %s ", label_.c_str(), kTurn[i % 4], formatSeconds(s).c_str());
      std::fflush(stderr);
      wake_.wait_for(lock, std::chrono::milliseconds(250), [this] { return done_; });
    }
    std::fprintf(stderr, "\r\033[K");  // erase the line
    std::fflush(stderr);
  }

  std::string label_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool done_ = false;
  std::thread thread_;
};

}  // namespace mbrt::tools
