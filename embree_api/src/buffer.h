// RTCBuffer: memory owned by the library (rtcNewBuffer,
// rtcSetNewGeometryBuffer) or the caller's (rtcNewSharedBuffer,
// rtcSetSharedGeometryBuffer), and the view a geometry has of one: offset,
// stride, item count and format.
#pragma once

#include <cstddef>
#include <memory>

#include "handles.h"

namespace mbrt::embree_api {

class Buffer final : public Object {
 public:
  static constexpr Tag kTag = Tag::Buffer;
  // Owned, zeroed, 16-byte aligned, with 16 bytes more than asked for
  // (Embree's clients may read the last item with a 16-byte load).
  Buffer(Device* device, size_t bytes);
  // The caller's memory.
  Buffer(Device* device, void* shared, size_t bytes);
  ~Buffer() override;

  char* data() const { return data_; }
  size_t size() const { return bytes_; }
  // Bytes that may be read from data(): the size, and for owned memory the
  // 16 bytes more it was given.
  size_t readable() const { return bytes_ + (owned_ ? 16 : 0); }

 private:
  std::unique_ptr<char[]> owned_;
  char* data_ = nullptr;
  size_t bytes_ = 0;
};

struct BufferView {
  Ref<Buffer> buffer;
  size_t offset = 0;
  size_t stride = 0;
  size_t count = 0;
  RTCFormat format = RTC_FORMAT_UNDEFINED;

  bool isSet() const { return static_cast<bool>(buffer); }
  const char* data() const { return buffer ? buffer->data() + offset : nullptr; }
  const char* item(size_t i) const { return data() + i * stride; }
};

}  // namespace mbrt::embree_api
