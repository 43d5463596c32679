// rtcInterpolate and rtcInterpolateN for triangle and quad meshes: a
// vertex or vertex-attribute buffer at a hit's (primID, u, v), with first
// derivatives (second ones are zero). Triangles: (1-u-v) p0 + u p1 + v p2.
// Quads, as Embree's two triangles: (1-u-v) p0 + u p1 + v p3 where
// u + v <= 1, else (u+v-1) p2 + (1-u) p3 + (1-v) p1.
#include <cstring>

#include "errors.h"
#include "geometry.h"

using namespace mbrt::embree_api;

namespace {

struct Outputs {
  float *P, *dPdu, *dPdv, *ddPdudu, *ddPdvdv, *ddPdudv;
  size_t stride;  // between values: 1 (rtcInterpolate) or N
};

void interpolateOne(const Geometry& g, unsigned prim, float u, float v, RTCBufferType type, unsigned slot,
                    unsigned valueCount, const Outputs& out, size_t lane) {
  if (!g.isMesh()) fail(RTC_ERROR_INVALID_OPERATION, "operation not supported for this geometry");
  const BufferView* b = nullptr;
  if (type == RTC_BUFFER_TYPE_VERTEX && slot < g.vertices.size()) b = &g.vertices[slot];
  if (type == RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE && slot < g.attributes.size()) b = &g.attributes[slot];
  if (!b || !b->isSet()) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid buffer type or slot, or no buffer there");
  if (size_t(valueCount) * sizeof(float) > (b->count > 1 ? b->stride : b->buffer->size() - b->offset))
    fail(RTC_ERROR_INVALID_ARGUMENT, "valueCount is larger than an item of the buffer");
  if (!g.index.isSet() || prim >= g.index.count) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid primID");
  uint32_t idx[4];
  std::memcpy(idx, g.index.item(prim), g.corners() * sizeof(uint32_t));
  for (unsigned c = 0; c < g.corners(); ++c)
    if (idx[c] >= b->count) fail(RTC_ERROR_INVALID_ARGUMENT, "a vertex index of the primitive is out of range");
  auto value = [&](unsigned corner, unsigned k) {
    float f;
    std::memcpy(&f, b->item(idx[corner]) + k * sizeof(float), sizeof(float));
    return f;
  };
  for (unsigned k = 0; k < valueCount; ++k) {
    float p, du, dv;
    if (g.corners() == 3) {
      const float p0 = value(0, k), p1 = value(1, k), p2 = value(2, k);
      p = (1.0f - u - v) * p0 + u * p1 + v * p2;
      du = p1 - p0;
      dv = p2 - p0;
    } else if (u + v <= 1.0f) {
      const float p0 = value(0, k), p1 = value(1, k), p3 = value(3, k);
      p = (1.0f - u - v) * p0 + u * p1 + v * p3;
      du = p1 - p0;
      dv = p3 - p0;
    } else {
      const float p1 = value(1, k), p2 = value(2, k), p3 = value(3, k);
      p = (u + v - 1.0f) * p2 + (1.0f - u) * p3 + (1.0f - v) * p1;
      du = p2 - p3;
      dv = p2 - p1;
    }
    const size_t at = k * out.stride + lane;
    if (out.P) out.P[at] = p;
    if (out.dPdu) out.dPdu[at] = du;
    if (out.dPdv) out.dPdv[at] = dv;
    if (out.ddPdudu) out.ddPdudu[at] = 0.0f;
    if (out.ddPdvdv) out.ddPdvdv[at] = 0.0f;
    if (out.ddPdudv) out.ddPdudv[at] = 0.0f;
  }
}

}  // namespace

RTC_API void rtcInterpolate(const RTCInterpolateArguments* args) {
  guarded("rtcInterpolate", args ? args->geometry : nullptr, [&] {
    if (!args) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null arguments");
    const Geometry& g = require<Geometry>(args->geometry, "RTCGeometry");
    const Outputs out{args->P, args->dPdu, args->dPdv, args->ddPdudu, args->ddPdvdv, args->ddPdudv, 1};
    interpolateOne(g, args->primID, args->u, args->v, args->bufferType, args->bufferSlot, args->valueCount, out, 0);
  });
}

RTC_API void rtcInterpolateN(const RTCInterpolateNArguments* args) {
  guarded("rtcInterpolateN", args ? args->geometry : nullptr, [&] {
    if (!args) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null arguments");
    const Geometry& g = require<Geometry>(args->geometry, "RTCGeometry");
    const Outputs out{args->P, args->dPdu, args->dPdv, args->ddPdudu, args->ddPdvdv, args->ddPdudv, args->N};
    const int* valid = static_cast<const int*>(args->valid);
    for (unsigned i = 0; i < args->N; ++i)
      if (!valid || valid[i])
        interpolateOne(g, args->primIDs[i], args->u[i], args->v[i], args->bufferType, args->bufferSlot,
                       args->valueCount, out, i);
  });
}
