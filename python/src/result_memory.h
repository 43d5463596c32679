// Memory for the result arrays of Accel.intersect, recycled between calls.
//
// A fresh numpy array of a million rays' hits (36 MB) is untouched memory:
// the first write to each page faults, which on a virtual machine costs as
// much as tracing a tenth of the rays (docs/python.md). The seven arrays of
// one call are views into one block; when the caller drops the last of them
// the block is kept (one block, the most recent) and the next call of at
// most its size writes into pages that are already mapped.
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>

namespace mbrt::python {

// A block of at least `bytes` bytes, 64-byte aligned, and the capsule that
// owns it: the numpy arrays viewing it take the capsule as their base, and
// the block returns to the recycler when the capsule is freed.
struct ResultBlock {
  std::byte* data = nullptr;
  pybind11::capsule owner;
};
ResultBlock acquireResultBlock(size_t bytes);

}  // namespace mbrt::python
