// The data a core keeps close: its second-level cache, 1 MB on the
// machines mbrt is measured on. Structures whose hot data exceeds it wait on
// memory, and pay for what hides that wait (prefetching the children of a
// node, reading a leaf's indices beside its references); those within it
// only pay the extra instructions (docs/performance.md, "The cost of a
// visit").
#pragma once

#include <cstddef>

namespace mbrt::detail {

inline constexpr size_t kCoreCacheBytes = size_t(1) << 20;

}  // namespace mbrt::detail
