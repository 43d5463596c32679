// A primitive of one level of a scene: what every builder, node and leaf
// refers to.
#pragma once

#include <cstdint>

namespace mbrt::detail {

// Geometry id and primitive id in it (instances have primID 0).
struct PrimRef {
  uint32_t geomID;
  uint32_t primID;
};

}  // namespace mbrt::detail
