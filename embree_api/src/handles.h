// The objects behind Embree's handles (RTCDevice, RTCScene, RTCGeometry,
// RTCBuffer): reference counted (rtcRetain*/rtcRelease*), each with a tag
// saying what it is, so that a null handle, a handle of the wrong type or
// a released one is refused with RTC_ERROR_INVALID_ARGUMENT instead of
// being used.
#pragma once

#include <atomic>
#include <cstdint>
#include <utility>

#include "api.h"

namespace mbrt::embree_api {

class Device;

enum class Tag : uint32_t {
  Device = 0x44455643u,
  Scene = 0x5343454eu,
  Geometry = 0x47454f4du,
  Buffer = 0x42554646u,
  Released = 0xdeadbeefu,
};

class Object {
 public:
  // Every object but a device holds a reference to its device.
  Object(Tag tag, Device* device);
  Object(const Object&) = delete;
  Object& operator=(const Object&) = delete;
  virtual ~Object();

  Tag tag() const { return tag_.load(std::memory_order_relaxed); }
  Device* device() const { return device_; }
  void retain() { refs_.fetch_add(1, std::memory_order_relaxed); }
  // Deletes the object when the last reference goes.
  void release();

 private:
  std::atomic<Tag> tag_;
  std::atomic<int64_t> refs_{1};
  Device* device_;
};

// An owning reference (retains on copy, releases on destruction).
template <class T>
class Ref {
 public:
  Ref() = default;
  Ref(T* p) : p_(p) {  // NOLINT: implicit, as a pointer
    if (p_) p_->retain();
  }
  Ref(const Ref& o) : Ref(o.p_) {}
  Ref(Ref&& o) noexcept : p_(std::exchange(o.p_, nullptr)) {}
  Ref& operator=(Ref o) noexcept {
    std::swap(p_, o.p_);
    return *this;
  }
  ~Ref() {
    if (p_) p_->release();
  }
  // Takes over the reference a new object starts with.
  static Ref adopt(T* p) {
    Ref r;
    r.p_ = p;
    return r;
  }
  T* get() const { return p_; }
  T* operator->() const { return p_; }
  T& operator*() const { return *p_; }
  explicit operator bool() const { return p_ != nullptr; }

 private:
  T* p_ = nullptr;
};

// The object a handle names when it is live and of type T's tag; else null.
template <class T>
T* objectOf(const void* handle) {
  if (!handle) return nullptr;
  auto* o = static_cast<Object*>(const_cast<void*>(handle));
  return o->tag() == T::kTag ? static_cast<T*>(o) : nullptr;
}

// The device of any live handle (for error reporting), else null.
Device* deviceOfHandle(const void* handle);

}  // namespace mbrt::embree_api
