// Errors as Embree reports them: each API function catches what went
// wrong, keeps the first error code per thread and device until
// rtcGetDeviceError reads it (the code of a call without a usable device
// goes to the thread's own slot, rtcGetDeviceError(NULL)), and calls the
// device's error callback with a message that starts with the function's
// name. Embree 3 has no RTC_ERROR_UNSUPPORTED: what mbrt does not
// implement is reported as Embree reports features compiled out of it
// (docs/embree-api.md lists which code goes with which case).
#pragma once

#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <type_traits>

#include "handles.h"
#include "mbrt/error.h"

namespace mbrt::embree_api {

struct ApiError {
  RTCError code;
  std::string message;
};

[[noreturn]] void fail(RTCError code, std::string message);

// Stores the code (the first one stays until it is read) and calls the
// device's callback; a null device stores it in the thread's slot.
void report(Device* device, RTCError code, const std::string& message);
// rtcGetDeviceError: returns and clears the calling thread's code.
RTCError takeError(Device* device);

// The value a caller passed for an enum parameter, read as its bytes: a C
// caller may pass any int (embree_verify does), and reading a value outside
// the enum's range as the enum is undefined in C++, so arguments are checked
// on this value before they are used as the enum.
template <class E>
std::underlying_type_t<E> passedValue(const E& e) {
  std::underlying_type_t<E> v;
  std::memcpy(&v, &e, sizeof v);
  return v;
}

// The object a handle names, or fails with RTC_ERROR_INVALID_ARGUMENT.
template <class T>
T& require(const void* handle, const char* what) {
  T* o = objectOf<T>(handle);
  if (!o) fail(RTC_ERROR_INVALID_ARGUMENT, std::string("invalid argument: ") + what + " is null, released or not a " + what);
  return *o;
}

namespace detail {
void reportCurrentException(const char* function, const void* handle);
}

// Runs an API function's body; on an exception, reports it on the device
// of `handle` (see report) as `function: message` and returns onError.
// An exception the error callback throws reaches the caller, as with
// Embree (embree_verify's callback throws).
template <class R, class Body>
R guarded(const char* function, const void* handle, R onError, Body&& body) {
  try {
    return body();
  } catch (...) {
    detail::reportCurrentException(function, handle);
  }
  return onError;
}

template <class Body>
void guarded(const char* function, const void* handle, Body&& body) {
  try {
    body();
  } catch (...) {
    detail::reportCurrentException(function, handle);
  }
}

}  // namespace mbrt::embree_api
