// Large build arrays on transparent huge pages. Where Linux gives huge pages
// only on request (THP mode "madvise", a common default), every 4 KiB page of
// a fresh array costs a page fault when first written; a build writes
// hundreds of MB into fresh arrays, and on virtual machines those faults
// were a fifth to a third of a build's time (docs/performance.md, "Build
// arrays on huge pages"). Advising an array before it is written lets the
// kernel back it with 2 MiB pages: one fault where there were 512.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace mbrt::detail {

inline constexpr size_t kHugePageBytes = size_t(2) << 20;

// Asks for huge pages over the whole 2 MiB pages inside [p, p + bytes).
// Arrays under two huge pages are left alone; without THP, or off Linux, it
// does nothing. Memory already written keeps its pages; the contents never
// change.
inline void adviseHugePages(const void* p, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (p == nullptr || bytes < 2 * kHugePageBytes) return;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(p) + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(p) + bytes) & ~(kHugePageBytes - 1);
  if (end > begin) (void)::madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

// v.reserve(n), then the new storage advised before anything is written to
// it (a reserve that reallocates copies the old elements first: call this
// while `v` is empty for the whole array to be advised).
template <class T, class A>
void reserveOnHugePages(std::vector<T, A>& v, size_t n) {
  if (n <= v.capacity()) return;
  v.reserve(n);
  adviseHugePages(v.data(), v.capacity() * sizeof(T));
}

// v.resize(n) into storage advised before it is written (v empty or small).
template <class T, class A>
void resizeOnHugePages(std::vector<T, A>& v, size_t n) {
  reserveOnHugePages(v, n);
  v.resize(n);
}

// std::allocator whose large blocks are advised as they are allocated: for
// containers that allocate as they grow (tbb::concurrent_vector's segments).
template <class T>
struct HugePageAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = HugePageAllocator<U>;
  };
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(size_t n) {
    T* p = std::allocator<T>::allocate(n);
    adviseHugePages(p, n * sizeof(T));
    return p;
  }
  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }
};

}  // namespace mbrt::detail
