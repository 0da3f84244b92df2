#pragma once
// How a batch command (a build, a stage task) asks the C library's allocator to keep the memory
// it frees. glibc returns freed memory at the top of its heap to the system once more than a
// few MB are free there, and serves each block above its mmap threshold with fresh pages that
// the kernel zero-fills on first touch. The texture pass allocates and frees tiles of a few MB
// for every chunk, so with the defaults a pass-2 task spent half its time in page faults
// (docs/benchmarks.md, "Builds on a cluster").

namespace terralod {

/// Keeps up to 1 GiB freed at the top of the heap for reuse and serves blocks up to 64 MiB from
/// the heap. Peak RSS can rise by what is kept (a staged reduce at 65537²: 452 → 602 MB, while
/// the textured builds' peaks fell); a no-op where the allocator is not glibc's. Not for
/// long-lived interactive processes, whose resident size should shrink again.
void keepFreedMemoryForReuse();

}  // namespace terralod
