#pragma once
// An allocator for large buffers filled once and kept (whole-grid arrays). On Linux, blocks of
// 2 MiB or more are aligned to 2 MiB and advised as transparent huge pages, so first touching
// them costs one page fault per 2 MiB instead of one per 4 KiB. Page faults are dear in virtual
// machines: zero-filling 32 MiB took 90-125 ms in 4 KiB pages on our 2-core VM and 13-49 ms in
// huge pages (docs/benchmarks.md, "Build time: page faults"). Where the kernel gives no huge
// pages (THP "never"), the advice is ignored and nothing else changes. Smaller blocks, and
// other systems, use operator new.

#include <cstddef>
#include <cstdlib>
#include <limits>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace terralod {

template <class T>
struct LargeBufferAllocator {
  using value_type = T;
  static constexpr size_t kHugePage = size_t{2} << 20;

  LargeBufferAllocator() = default;
  template <class U>
  LargeBufferAllocator(const LargeBufferAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    if (n > std::numeric_limits<size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= kHugePage) {
      const size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
      void* p = std::aligned_alloc(kHugePage, rounded);
      if (!p) throw std::bad_alloc();
      madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves 4 KiB pages
      return static_cast<T*>(p);
    }
#endif
    return static_cast<T*>(::operator new(bytes));
  }

  void deallocate(T* p, size_t n) noexcept {
#if defined(__linux__)
    if (n * sizeof(T) >= kHugePage) {
      std::free(p);
      return;
    }
#endif
    ::operator delete(p);
  }

  template <class U>
  bool operator==(const LargeBufferAllocator<U>&) const noexcept {
    return true;
  }
};

}  // namespace terralod
