#include "result_memory.h"

#include <mutex>
#include <new>

namespace mbrt::python {
namespace {

constexpr std::align_val_t kAlign{64};
// Larger blocks go back to the system: keeping one would hold memory a
// caller may never ask for again.
constexpr size_t kMaxKeptBytes = size_t(1) << 30;

struct Block {
  std::byte* data;
  size_t bytes;
};

std::mutex gMutex;
Block gKept{nullptr, 0};  // guarded by gMutex

void freeBlock(Block b) {
  if (b.data) ::operator delete(b.data, kAlign);
}

void recycle(Block b) {
  Block dropped{nullptr, 0};
  {
    std::lock_guard lock(gMutex);
    if (b.bytes <= kMaxKeptBytes) std::swap(gKept, b);
    dropped = b;  // the older kept block, or b itself when too large
  }
  freeBlock(dropped);
}

}  // namespace

ResultBlock acquireResultBlock(size_t bytes) {
  Block b{nullptr, 0};
  {
    std::lock_guard lock(gMutex);
    // Reused when it fits and wastes at most half of itself.
    if (gKept.data && gKept.bytes >= bytes && gKept.bytes / 2 <= bytes) std::swap(b, gKept);
  }
  if (!b.data) b = {static_cast<std::byte*>(::operator new(bytes == 0 ? 1 : bytes, kAlign)), bytes};
  auto* owned = new Block(b);
  pybind11::capsule owner(owned, [](void* p) {
    auto* block = static_cast<Block*>(p);
    recycle(*block);
    delete block;
  });
  return {b.data, std::move(owner)};
}

}  // namespace mbrt::python
