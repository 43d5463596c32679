// Error codes per thread and device, the error callback, and the mapping
// of exceptions to Embree's codes (errors.h).
#include "errors.h"

#include <cstdio>
#include <utility>
#include <vector>

#include "device.h"

namespace mbrt::embree_api {
namespace {

// The calling thread's pending code per device (by serial number, so that
// a new device at a freed one's address starts clean), and its own slot.
thread_local std::vector<std::pair<uint64_t, RTCError>> tDeviceErrors;
thread_local RTCError tThreadError = RTC_ERROR_NONE;

RTCError& slotOf(Device* device) {
  if (!device) return tThreadError;
  for (auto& e : tDeviceErrors)
    if (e.first == device->serial()) return e.second;
  tDeviceErrors.emplace_back(device->serial(), RTC_ERROR_NONE);
  return tDeviceErrors.back().second;
}

}  // namespace

void fail(RTCError code, std::string message) { throw ApiError{code, std::move(message)}; }

void report(Device* device, RTCError code, const std::string& message) {
  RTCError& slot = slotOf(device);
  if (slot == RTC_ERROR_NONE) slot = code;
  if (device) {
    if (device->verbose() > 0) std::fprintf(stderr, "mbrt embree api: error %d: %s\n", int(code), message.c_str());
    device->callErrorFunction(code, message.c_str());
  }
}

RTCError takeError(Device* device) { return std::exchange(slotOf(device), RTC_ERROR_NONE); }

namespace detail {

void reportCurrentException(const char* function, const void* handle) {
  Device* device = deviceOfHandle(handle);
  const std::string prefix = std::string(function) + ": ";
  try {
    throw;
  } catch (const ApiError& e) {
    report(device, e.code, prefix + e.message);
  } catch (const std::bad_alloc&) {
    report(device, RTC_ERROR_OUT_OF_MEMORY, prefix + "out of memory");
  } catch (const mbrt::Error& e) {
    // The kernel refused the scene or ran out of its memory budget.
    report(device, RTC_ERROR_INVALID_OPERATION, prefix + e.what());
  } catch (const std::exception& e) {
    report(device, RTC_ERROR_UNKNOWN, prefix + e.what());
  } catch (...) {
    report(device, RTC_ERROR_UNKNOWN, prefix + "unknown error");
  }
}

}  // namespace detail
}  // namespace mbrt::embree_api
