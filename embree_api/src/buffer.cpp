// RTCBuffer and its API functions.
#include "buffer.h"

#include <cstdint>
#include <cstring>

#include "device.h"
#include "errors.h"

namespace mbrt::embree_api {

Buffer::Buffer(Device* device, size_t bytes) : Object(Tag::Buffer, device), bytes_(bytes) {
  owned_.reset(new char[bytes + 32]);
  std::memset(owned_.get(), 0, bytes + 32);
  data_ = owned_.get() + (16 - reinterpret_cast<uintptr_t>(owned_.get()) % 16) % 16;
}

Buffer::Buffer(Device* device, void* shared, size_t bytes)
    : Object(Tag::Buffer, device), data_(static_cast<char*>(shared)), bytes_(bytes) {}

Buffer::~Buffer() = default;

}  // namespace mbrt::embree_api

using namespace mbrt::embree_api;

RTC_API RTCBuffer rtcNewBuffer(RTCDevice device, size_t byteSize) {
  return guarded("rtcNewBuffer", device, RTCBuffer(nullptr), [&] {
    return reinterpret_cast<RTCBuffer>(new Buffer(&require<Device>(device, "RTCDevice"), byteSize));
  });
}

RTC_API RTCBuffer rtcNewSharedBuffer(RTCDevice device, void* ptr, size_t byteSize) {
  return guarded("rtcNewSharedBuffer", device, RTCBuffer(nullptr), [&] {
    Device& d = require<Device>(device, "RTCDevice");
    if (!ptr && byteSize > 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null memory for a shared buffer");
    return reinterpret_cast<RTCBuffer>(new Buffer(&d, ptr, byteSize));
  });
}

RTC_API void* rtcGetBufferData(RTCBuffer buffer) {
  return guarded("rtcGetBufferData", buffer, static_cast<void*>(nullptr),
                 [&] { return static_cast<void*>(require<Buffer>(buffer, "RTCBuffer").data()); });
}

RTC_API void rtcRetainBuffer(RTCBuffer buffer) {
  guarded("rtcRetainBuffer", buffer, [&] { require<Buffer>(buffer, "RTCBuffer").retain(); });
}

RTC_API void rtcReleaseBuffer(RTCBuffer buffer) {
  guarded("rtcReleaseBuffer", buffer, [&] { require<Buffer>(buffer, "RTCBuffer").release(); });
}
