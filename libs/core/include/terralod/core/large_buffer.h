#pragma once
// An allocator for large buffers sized once and filled (whole-grid arrays: activations,
// rasters). Two things make it cheaper than the default for them:
// - Its memory is always zero when handed out (fresh pages for large blocks, calloc for small
//   ones), so value-initialised elements cost nothing: `Vector v(n)` writes no byte, and the
//   pages are first touched by whoever fills them (in parallel, where the build is).
// - On Linux, blocks of 2 MiB or more are mapped aligned to 2 MiB and advised as transparent
//   huge pages: one page fault per 2 MiB instead of one per 4 KiB. Page faults are dear in
//   virtual machines: zero-filling 32 MiB took 90-125 ms in 4 KiB pages on our 2-core VM and
//   13-49 ms in huge pages (docs/benchmarks.md). Where the kernel gives none (THP "never"),
//   the advice is ignored.
// Because value-initialisation leaves the allocation's bytes as they are, a vector using it
// must not be shrunk and grown again (the regrown elements would keep old values); and only
// arithmetic elements, whose zero is all-zero bytes, are allowed.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <type_traits>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace terralod {

template <class T>
struct LargeBufferAllocator {
  static_assert(std::is_arithmetic_v<T>, "zero bytes must be the value-initialised element");
  using value_type = T;
  static constexpr size_t kHugePage = size_t{2} << 20;

  LargeBufferAllocator() = default;
  template <class U>
  LargeBufferAllocator(const LargeBufferAllocator<U>&) noexcept {}

  T* allocate(size_t n) {
    if (n > std::numeric_limits<size_t>::max() / sizeof(T) - kHugePage)
      throw std::bad_array_new_length();
    const size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= kHugePage) {
      // Map one huge page more than needed and unmap the slack on both sides of the aligned
      // range: anonymous mappings are zero.
      const size_t rounded = roundedUp(bytes);
      void* mapped = mmap(nullptr, rounded + kHugePage, PROT_READ | PROT_WRITE,
                          MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
      if (mapped == MAP_FAILED) throw std::bad_alloc();
      const uintptr_t start = reinterpret_cast<uintptr_t>(mapped);
      const uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
      if (aligned > start) munmap(mapped, aligned - start);
      if (const size_t tail = start + rounded + kHugePage - (aligned + rounded); tail > 0)
        munmap(reinterpret_cast<void*>(aligned + rounded), tail);
      madvise(reinterpret_cast<void*>(aligned), rounded, MADV_HUGEPAGE);  // advice only
      return reinterpret_cast<T*>(aligned);
    }
#endif
    void* p = std::calloc(n == 0 ? 1 : n, sizeof(T));
    if (!p) throw std::bad_alloc();
    return static_cast<T*>(p);
  }

  void deallocate(T* p, size_t n) noexcept {
#if defined(__linux__)
    if (n * sizeof(T) >= kHugePage) {
      munmap(p, roundedUp(n * sizeof(T)));
      return;
    }
#endif
    std::free(p);
  }

  /// Value-initialisation: the allocation is already zero.
  template <class U>
  void construct(U*) noexcept {}
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <class U>
  bool operator==(const LargeBufferAllocator<U>&) const noexcept {
    return true;
  }

 private:
  static size_t roundedUp(size_t bytes) {
    return (bytes + kHugePage - 1) / kHugePage * kHugePage;
  }
};

}  // namespace terralod
