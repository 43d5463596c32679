// Memory accounting of a build: the bytes in use, their peak, and an
// optional budget that stops the build with a clear error before it is
// exceeded.
#pragma once

#include <atomic>
#include <cstddef>
#include <string>

#include "mbrt/error.h"

namespace mbrt::detail {

class BuildBudget {
 public:
  explicit BuildBudget(size_t limit = 0) : limit_(limit) {}

  // Reserve `bytes` for `what`; throws Error if that would exceed the limit.
  void charge(size_t bytes, const char* what) {
    const size_t now = used_.fetch_add(bytes) + bytes;
    if (limit_ != 0 && now > limit_) {
      used_.fetch_sub(bytes);
      throw Error(std::string("memory budget of ") + std::to_string(limit_) + " bytes exceeded by " + what +
                  " (needs " + std::to_string(now) + " bytes)");
    }
    size_t peak = peak_.load();
    while (now > peak && !peak_.compare_exchange_weak(peak, now)) {
    }
  }
  void release(size_t bytes) { used_.fetch_sub(bytes); }
  size_t peak() const { return peak_.load(); }
  size_t used() const { return used_.load(); }
  size_t limit() const { return limit_; }  // 0: unlimited

 private:
  size_t limit_;
  std::atomic<size_t> used_{0};
  std::atomic<size_t> peak_{0};
};

// Charges on construction, releases on destruction (scratch memory).
class ScopedCharge {
 public:
  ScopedCharge(BuildBudget& budget, size_t bytes, const char* what) : budget_(budget), bytes_(bytes) {
    budget_.charge(bytes, what);
  }
  ~ScopedCharge() { budget_.release(bytes_); }
  ScopedCharge(const ScopedCharge&) = delete;
  ScopedCharge& operator=(const ScopedCharge&) = delete;

 private:
  BuildBudget& budget_;
  size_t bytes_;
};

}  // namespace mbrt::detail
