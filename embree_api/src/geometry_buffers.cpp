// The buffers of triangle and quad meshes: index (UINT3 or UINT4), one
// vertex buffer (FLOAT3) per time step, vertex attributes (FLOAT to
// FLOAT16) for rtcInterpolate; shared, owned or from an RTCBuffer. Errors
// and their codes are Embree's for the same mistakes.
#include <cstdint>
#include <string>

#include "device.h"
#include "errors.h"
#include "geometry.h"

using namespace mbrt::embree_api;

namespace {

size_t formatBytes(RTCFormat f) {
  switch (f) {
    case RTC_FORMAT_UINT3: return 12;
    case RTC_FORMAT_UINT4: return 16;
    case RTC_FORMAT_FLOAT3: return 12;
    default:
      if (f >= RTC_FORMAT_FLOAT && f <= RTC_FORMAT_FLOAT16) return 4 * size_t(f - RTC_FORMAT_FLOAT + 1);
      return 4;
  }
}

void checkLayout(const BufferView& v) {
  if (v.count > 0xFFFFFFFFu) fail(RTC_ERROR_INVALID_ARGUMENT, "buffer too large");
  if (v.stride % 4 != 0) fail(RTC_ERROR_INVALID_OPERATION, "data must be 4 bytes aligned (the byte stride too)");
  // Embree lets items overlap; mbrt's vertex buffers need 12 bytes each.
  if (v.format == RTC_FORMAT_FLOAT3 && v.count > 1 && v.stride < 12)
    fail(RTC_ERROR_INVALID_ARGUMENT, "byte stride " + std::to_string(v.stride) +
                                         " of a vertex buffer is smaller than a vertex (12 bytes)");
  if (v.count > 0 && reinterpret_cast<uintptr_t>(v.data()) % 4 != 0)
    fail(RTC_ERROR_INVALID_OPERATION, "data must be 4 bytes aligned");
}

// Where (type, slot) goes in g; fails as Embree does for a wrong type,
// slot or format.
BufferView& slotFor(Geometry& g, RTCBufferType type, unsigned slot, RTCFormat format, bool checkFormat) {
  if (!g.isMesh()) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  switch (type) {
    case RTC_BUFFER_TYPE_INDEX: {
      if (slot != 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer slot");
      const RTCFormat want = g.type() == RTC_GEOMETRY_TYPE_QUAD ? RTC_FORMAT_UINT4 : RTC_FORMAT_UINT3;
      if (checkFormat && format != want) fail(RTC_ERROR_INVALID_OPERATION, "invalid index buffer format");
      return g.index;
    }
    case RTC_BUFFER_TYPE_VERTEX:
      if (checkFormat && format != RTC_FORMAT_FLOAT3) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex buffer format");
      if (slot >= g.vertices.size()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid vertex buffer slot");
      return g.vertices[slot];
    case RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE:
      if (checkFormat && !(format >= RTC_FORMAT_FLOAT && format <= RTC_FORMAT_FLOAT16))
        fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute buffer format");
      if (slot >= g.attributes.size()) fail(RTC_ERROR_INVALID_OPERATION, "invalid vertex attribute buffer slot");
      return g.attributes[slot];
    default:
      fail(RTC_ERROR_INVALID_ARGUMENT, "unknown buffer type");
  }
}

void setBuffer(Geometry& g, RTCBufferType type, unsigned slot, BufferView view) {
  BufferView& target = slotFor(g, type, slot, view.format, true);
  checkLayout(view);
  target = std::move(view);
  if (type == RTC_BUFFER_TYPE_INDEX)
    g.changedTopology();
  else if (type == RTC_BUFFER_TYPE_VERTEX)
    g.changedVertices();
}

}  // namespace

RTC_API void rtcSetGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                  RTCBuffer buffer, size_t byteOffset, size_t byteStride, size_t itemCount) {
  guarded("rtcSetGeometryBuffer", geometry, [&] {
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    Buffer& b = require<Buffer>(buffer, "RTCBuffer");
    if (g.isPlaceholder()) return;
    if (b.device() != g.device()) fail(RTC_ERROR_INVALID_ARGUMENT, "inputs are from different devices");
    if (itemCount > 0 && byteOffset + (itemCount - 1) * byteStride + formatBytes(format) > b.size())
      fail(RTC_ERROR_INVALID_ARGUMENT, "buffer range out of bounds");
    setBuffer(g, type, slot, BufferView{&b, byteOffset, byteStride, itemCount, format});
  });
}

RTC_API void rtcSetSharedGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot,
                                        RTCFormat format, const void* ptr, size_t byteOffset, size_t byteStride,
                                        size_t itemCount) {
  guarded("rtcSetSharedGeometryBuffer", geometry, [&] {
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    if (!ptr && itemCount > 0) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null buffer memory");
    if (g.isPlaceholder()) return;
    slotFor(g, type, slot, format, true);  // the type, slot and format are checked before any allocation
    auto b = Ref<Buffer>::adopt(
        new Buffer(g.device(), static_cast<char*>(const_cast<void*>(ptr)) + byteOffset, itemCount * byteStride));
    setBuffer(g, type, slot, BufferView{b, 0, byteStride, itemCount, format});
  });
}

RTC_API void* rtcSetNewGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot, RTCFormat format,
                                      size_t byteStride, size_t itemCount) {
  return guarded("rtcSetNewGeometryBuffer", geometry, static_cast<void*>(nullptr), [&] {
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    if (itemCount > 0xFFFFFFFFu) fail(RTC_ERROR_INVALID_ARGUMENT, "buffer too large");
    if (g.isPlaceholder()) {  // scratch memory the program may fill
      g.scratch.push_back({type, slot, Ref<Buffer>::adopt(new Buffer(g.device(), itemCount * byteStride))});
      return static_cast<void*>(g.scratch.back().buffer->data());
    }
    slotFor(g, type, slot, format, true);
    auto b = Ref<Buffer>::adopt(new Buffer(g.device(), itemCount * byteStride));
    setBuffer(g, type, slot, BufferView{b, 0, byteStride, itemCount, format});
    return static_cast<void*>(b->data());
  });
}

RTC_API void* rtcGetGeometryBufferData(RTCGeometry geometry, RTCBufferType type, unsigned int slot) {
  return guarded("rtcGetGeometryBufferData", geometry, static_cast<void*>(nullptr), [&] {
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    if (g.isPlaceholder()) {  // the scratch memory given out for (type, slot), if any
      for (auto it = g.scratch.rbegin(); it != g.scratch.rend(); ++it)
        if (it->type == type && it->slot == slot) return static_cast<void*>(it->buffer->data());
      return static_cast<void*>(nullptr);
    }
    return static_cast<void*>(const_cast<char*>(slotFor(g, type, slot, RTC_FORMAT_UNDEFINED, false).data()));
  });
}

RTC_API void rtcUpdateGeometryBuffer(RTCGeometry geometry, RTCBufferType type, unsigned int slot) {
  guarded("rtcUpdateGeometryBuffer", geometry, [&] {
    Geometry& g = require<Geometry>(geometry, "RTCGeometry");
    if (g.isPlaceholder()) return;
    slotFor(g, type, slot, RTC_FORMAT_UNDEFINED, false);
    if (type == RTC_BUFFER_TYPE_INDEX)
      g.changedTopology();
    else if (type == RTC_BUFFER_TYPE_VERTEX)
      g.changedVertices();
  });
}
