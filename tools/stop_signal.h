// SIGINT and SIGTERM during a render: the first stops the work after what is
// in progress (the render's cancel flag), a second ends the process at once.
// While nothing would be kept (a build before the first tile: builds cannot
// be cancelled), the first one ends the process at once, writing nothing.
#pragma once

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>

namespace mbrt::tools {

// The signal that stopped the work (SIGINT, SIGTERM), 0 while none.
inline std::atomic<int> gStopSignal{0};
inline std::atomic<bool> gStopRequested{false};
// Set while the work in progress would leave nothing to write when stopped.
inline std::atomic<bool> gNothingToKeep{false};

// What a stop with nothing to keep says (a static string: the handler
// writes it). It starts with a newline, to end a progress line.
inline const char* nothingWrittenNote(int sig) {
  return sig == SIGINT ? "\nmbrt: stopped by SIGINT before any tile was rendered: nothing written\n"
                       : "\nmbrt: stopped by SIGTERM before any tile was rendered: nothing written\n";
}

extern "C" inline void onStopSignal(int sig) {
  if (gNothingToKeep.load()) {  // async-signal-safe: write(2) and _exit(2) only
    const char* note = nothingWrittenNote(sig);
    [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, note, std::strlen(note));
    ::_exit(128 + sig);
  }
  gStopSignal.store(sig);
  gStopRequested.store(true);
  std::signal(sig, SIG_DFL);  // a second one ends the process at once
  static const char kNote[] = "\nmbrt: stopping after the work in progress (again: stop at once)\n";
  [[maybe_unused]] const ssize_t n = ::write(STDERR_FILENO, kNote, sizeof kNote - 1);  // async-signal-safe
}

inline const char* signalName(int sig) { return sig == SIGINT ? "SIGINT" : "SIGTERM"; }

// Installs the SIGINT and SIGTERM handlers for its lifetime.
class StopSignalGuard {
 public:
  StopSignalGuard() {
    gStopSignal.store(0);
    gStopRequested.store(false);
    gNothingToKeep.store(false);
    previousInt_ = std::signal(SIGINT, onStopSignal);
    previousTerm_ = std::signal(SIGTERM, onStopSignal);
  }
  ~StopSignalGuard() {
    gNothingToKeep.store(false);
    std::signal(SIGINT, previousInt_ == SIG_ERR ? SIG_DFL : previousInt_);
    std::signal(SIGTERM, previousTerm_ == SIG_ERR ? SIG_DFL : previousTerm_);
  }
  StopSignalGuard(const StopSignalGuard&) = delete;
  StopSignalGuard& operator=(const StopSignalGuard&) = delete;

 private:
  void (*previousInt_)(int) = SIG_DFL;
  void (*previousTerm_)(int) = SIG_DFL;
};

}  // namespace mbrt::tools
