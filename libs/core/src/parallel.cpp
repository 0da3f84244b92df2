#include "terralod/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace terralod {

unsigned hardwareThreads() {
  return std::max(1u, std::thread::hardware_concurrency());
}

void parallelFor(size_t count, unsigned threads,
                 const std::function<void(size_t index, unsigned worker)>& fn) {
  if (count == 0) return;
  const unsigned workers = static_cast<unsigned>(std::clamp<size_t>(threads, 1, count));
  std::atomic<size_t> next{0};
  auto work = [&](unsigned worker) {
    for (size_t i = next.fetch_add(1); i < count; i = next.fetch_add(1)) fn(i, worker);
  };
  std::vector<std::jthread> pool;
  pool.reserve(workers - 1);
  for (unsigned w = 1; w < workers; ++w) pool.emplace_back(work, w);
  work(0);
}

}  // namespace terralod
