// ThreadSanitizer builds only: a stand-in for TBB's scalable allocator
// (libtbbmalloc.so.2) that forwards to malloc and free, which TSan sees.
//
// libtbb allocates its own thread data and task memory through
// libtbbmalloc, loaded at the first allocation; before loading it, TBB takes
// a library of that soname already in the process (dlopen with RTLD_NOLOAD).
// With the real allocator, memory that a finished thread's TBB data held
// comes back to another thread without a free and a malloc TSan can see, so
// TBB zeroing it is reported as a race inside libtbb.so (a memset with no
// frame of mbrt above it). mbrt_thread_tests links this library, whose
// soname is libtbbmalloc.so.2 (tests/threads.cmake), so TBB's memory is
// ordinary malloc memory and every reuse of it is ordered for TSan.
#include <cstddef>
#include <cstdlib>

extern "C" {

void* scalable_malloc(std::size_t size) { return std::malloc(size); }

void scalable_free(void* p) { std::free(p); }

void* scalable_aligned_malloc(std::size_t size, std::size_t alignment) {
  void* p = nullptr;
  return posix_memalign(&p, alignment < sizeof(void*) ? sizeof(void*) : alignment, size) == 0 ? p : nullptr;
}

void scalable_aligned_free(void* p) { std::free(p); }

}  // extern "C"
