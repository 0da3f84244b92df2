#pragma once
// Minimal fork-join parallelism for the offline tools (build, verify, synth). The runtime's
// loader pool has its own seam; this is only for "run these N independent tasks on T threads".

#include <cstddef>
#include <functional>

namespace terralod {

/// Number of hardware threads, at least 1.
unsigned hardwareThreads();

/// Runs fn(index, worker) for every index in [0, count) on up to `threads` threads (the
/// caller's thread is worker 0). Indices are handed out in increasing order as workers free
/// up, so earlier indices start first. Returns when all calls have returned.
void parallelFor(size_t count, unsigned threads,
                 const std::function<void(size_t index, unsigned worker)>& fn);

}  // namespace terralod
