// RTCDevice: the build options every scene of the device is built with
// (the mbrt kind, from the config string or MBRT_EMBREE_KIND), the task
// arena of `threads=N`, the error callback and the memory monitor.
#pragma once

#include <tbb/task_arena.h>

#include <memory>
#include <mutex>
#include <string>

#include "handles.h"
#include "mbrt/build_options.h"

namespace mbrt::embree_api {

// What rtcNewDevice's config string says. mbrt.kind=NAME picks the kind
// (else the environment variable MBRT_EMBREE_KIND, else auto); Embree's
// own tokens (threads=N, verbose=N, isa=..., set_affinity=..., ...) are
// accepted, threads=N is honoured for builds. Throws ApiError
// (RTC_ERROR_INVALID_ARGUMENT) for an unknown kind or mbrt.* key.
struct DeviceConfig {
  AccelKind kind = AccelKind::Auto;
  int threads = 0;  // 0: the caller's arena
  int verbose = 0;
};
DeviceConfig parseDeviceConfig(const char* config, const char* environmentKind);

class Device final : public Object {
 public:
  static constexpr Tag kTag = Tag::Device;
  explicit Device(const DeviceConfig& config);
  ~Device() override;

  const BuildOptions& buildOptions() const { return options_; }
  int verbose() const { return verbose_; }
  uint64_t serial() const { return serial_; }

  // Runs f in the device's arena (threads=N) or in the caller's.
  template <class F>
  void run(F&& f) {
    if (arena_)
      arena_->execute(f);
    else
      f();
  }

  void setErrorFunction(RTCErrorFunction f, void* userPtr);
  void callErrorFunction(RTCError code, const char* message);
  void setMemoryMonitor(RTCMemoryMonitorFunction f, void* userPtr);
  // Tells the memory monitor of `bytes` (negative: freed); false when it
  // refuses the allocation.
  bool monitorMemory(ssize_t bytes);

 private:
  BuildOptions options_;
  int verbose_ = 0;
  uint64_t serial_;
  std::unique_ptr<tbb::task_arena> arena_;
  std::mutex mutex_;
  RTCErrorFunction errorFunction_ = nullptr;
  void* errorUserPtr_ = nullptr;
  RTCMemoryMonitorFunction memoryMonitor_ = nullptr;
  void* memoryUserPtr_ = nullptr;
};

}  // namespace mbrt::embree_api
