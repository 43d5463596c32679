// Reference counting and handle checks of every object (handles.h).
#include "device.h"
#include "handles.h"

namespace mbrt::embree_api {

Object::Object(Tag tag, Device* device) : tag_(tag), device_(device) {
  if (device_ && tag != Tag::Device) device_->retain();
}

Object::~Object() {
  tag_.store(Tag::Released, std::memory_order_relaxed);
  if (device_ && device_ != this) device_->release();
}

void Object::release() {
  if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
}

Device* deviceOfHandle(const void* handle) {
  if (!handle) return nullptr;
  const auto* o = static_cast<const Object*>(handle);
  switch (o->tag()) {
    case Tag::Device:
    case Tag::Scene:
    case Tag::Geometry:
    case Tag::Buffer:
      return o->device();
    default:
      return nullptr;
  }
}

}  // namespace mbrt::embree_api
