// The terralod executable allocates through jemalloc (linked in place of the C library's
// malloc), configured here.
//
// A build touches a few hundred megabytes of fresh memory (the activation grid, the texture
// tiles of every block, the blobs held for writing) and frees and reallocates tiles of a few
// megabytes thousands of times, from two or more threads. With glibc's malloc most of that
// memory was faulted in 4 KiB at a time, and much of it again after being handed back to the
// kernel; on a virtual machine each fresh page costs the host's backing too. So:
// - thp:always, metadata_thp:always: back the heap with transparent huge pages (THP set to
//   `madvise`, Debian's default, honours the request): a fault covers 2 MiB.
// - narenas:1: one arena, so a tile freed by one thread is memory the next tile on another
//   thread reuses (the allocations that matter are few and large; threads keep their caches).
// - dirty_decay_ms:30000, muzzy_decay_ms:-1: freed memory goes back to the kernel over 30 s,
//   and then lazily (MADV_FREE, reclaimed only under memory pressure), not while a build
//   still needs it.
// - oversize_threshold:0: no arena of its own for requests of 8 MiB and more. jemalloc
//   serves those from an arena that hands freed memory back to the kernel at once, so every
//   parent texture tile (1025² texels of three floats: 12.6 MB) was fresh memory again: a
//   pass-1 job of a staged build faulted in 223 huge pages, 93 with this setting.
// Measured on the 8193² synths against glibc's malloc (docs/benchmarks.md, "Textured builds
// and the allocator", and "Session 64" under the cluster builds).
// MALLOC_CONF in the environment still overrides any of it.
extern "C" {
// Read by jemalloc when it initialises (the name is its documented hook).
const char* malloc_conf =  // NOLINT
    "thp:always,metadata_thp:always,narenas:1,dirty_decay_ms:30000,muzzy_decay_ms:-1,"
    "oversize_threshold:0";
}
