#include "terralod/runtime/residency.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <thread>

namespace terralod {

Residency::Residency(const ChunkTree& tree, ChunkLoadFunction load, TaskRunner& runner,
                     ResidencyOptions options, std::function<void(const std::string&)> log)
    : mTree(tree),
      mLoad(std::move(load)),
      mRunner(runner),
      mOptions(options),
      mLog(std::move(log)),
      mNodes(tree.nodes().size()),
      mDrawable(tree.nodes().size(), 0),
      mDoneMutex(std::make_shared<std::mutex>()),
      mDone(std::make_shared<std::vector<Finished>>()),
      mRunning(std::make_shared<size_t>(0)) {}

Residency::~Residency() {
  // Tasks reference mLoad (and through it the tileset): wait for the running ones.
  for (;;) {
    {
      std::lock_guard lock(*mDoneMutex);
      if (*mRunning == 0) return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

Result<LoadedChunk> Residency::loadNow(uint32_t node) {
  return mLoad(node);
}

void Residency::adjustParent(uint32_t node, int delta) {
  const uint32_t parent = mTree.node(node).parent;
  if (parent != kNoNode)
    mNodes[parent].busyChildren = uint32_t(int(mNodes[parent].busyChildren) + delta);
}

void Residency::addBytes(int64_t delta) {
  mCounters.residentBytes = uint64_t(int64_t(mCounters.residentBytes) + delta);
  mCounters.residentBytesMax = std::max(mCounters.residentBytesMax, mCounters.residentBytes);
}

std::vector<ReadyChunk> Residency::collect() {
  std::vector<Finished> done;
  {
    std::lock_guard lock(*mDoneMutex);
    done.swap(*mDone);
  }
  for (Finished& f : done) {
    Node& n = mNodes[f.node];
    --mInFlight;
    if (f.result) {
      n.state = ChunkState::kReady;
      n.failures = 0;
      ++mCounters.loads;
      mCounters.bytesRead += f.result->bytesRead;
      addBytes(int64_t(f.result->bytes));
      mReady.push_back({f.node, std::move(f.result).value()});
    } else {
      if (n.failures == 0 && mLog) mLog(f.result.error().message);
      ++n.failures;
      ++mCounters.failures;
      n.state = ChunkState::kFailed;
      n.retryAt =
          mFrame + (uint64_t(mOptions.retryFrames) << std::min<uint32_t>(n.failures - 1, 6));
      adjustParent(f.node, -1);
    }
  }
  std::vector<ReadyChunk> ready;
  ready.swap(mReady);
  std::stable_sort(ready.begin(), ready.end(), [&](const ReadyChunk& a, const ReadyChunk& b) {
    return mNodes[a.node].priority < mNodes[b.node].priority;
  });
  return ready;
}

void Residency::returnReady(ReadyChunk chunk) {
  mReady.push_back(std::move(chunk));
}

void Residency::markResident(const ReadyChunk& chunk, uint64_t gpuBytes) {
  assert(mNodes[chunk.node].state == ChunkState::kReady);
  addBytes(-int64_t(chunk.chunk.bytes));
  Node& n = mNodes[chunk.node];
  n.state = ChunkState::kResident;
  n.gpuBytes = gpuBytes;
  n.lastUsed = mFrame;
  mDrawable[chunk.node] = 1;
  addBytes(int64_t(gpuBytes));
  mResident.push_back(chunk.node);
}

void Residency::markLoadedNow(uint32_t node, uint64_t gpuBytes) {
  Node& n = mNodes[node];
  assert(n.state == ChunkState::kAbsent);
  adjustParent(node, +1);
  n.state = ChunkState::kResident;
  n.gpuBytes = gpuBytes;
  n.lastUsed = mFrame;
  mDrawable[node] = 1;
  ++mCounters.loads;
  addBytes(int64_t(gpuBytes));
  mResident.push_back(node);
}

void Residency::touch(uint32_t node) {
  mNodes[node].lastUsed = mFrame;
}

void Residency::request(uint32_t node, float priority) {
  const uint32_t parent = mTree.node(node).parent;
  if (parent != kNoNode && mNodes[parent].state != ChunkState::kResident) return;
  Node& n = mNodes[node];
  if (n.requested != mFrame) n.priority = priority;
  n.priority = std::min(n.priority, priority);
  n.requested = mFrame;
  if (n.state == ChunkState::kAbsent || (n.state == ChunkState::kFailed && mFrame >= n.retryAt)) {
    n.state = ChunkState::kQueued;
    mQueue.push_back(node);
  }
}

std::vector<uint32_t> Residency::evict() {
  std::vector<uint32_t> evicted;
  // Over the budget, or exactly at it while loads wait (dispatch starts them only below it:
  // without room made here, a full budget would keep them waiting for good).
  const auto overBudget = [this] {
    return mCounters.residentBytes > mOptions.budgetBytes ||
           (mCounters.residentBytes == mOptions.budgetBytes && !mQueue.empty());
  };
  // Loaded chunks nobody asked for this frame go first.
  if (overBudget()) {
    std::vector<ReadyChunk> keep;
    for (ReadyChunk& r : mReady) {
      if (mNodes[r.node].requested == mFrame) {
        keep.push_back(std::move(r));
        continue;
      }
      mNodes[r.node].state = ChunkState::kAbsent;
      adjustParent(r.node, -1);
      addBytes(-int64_t(r.chunk.bytes));
      ++mCounters.discarded;
    }
    mReady.swap(keep);
  }
  while (overBudget()) {
    size_t best = mResident.size();
    for (size_t k = 0; k < mResident.size(); ++k) {
      const uint32_t i = mResident[k];
      const Node& n = mNodes[i];
      if (mTree.node(i).level == 0 || n.busyChildren != 0 || n.lastUsed >= mFrame) continue;
      if (best == mResident.size() || n.lastUsed < mNodes[mResident[best]].lastUsed) best = k;
    }
    if (best == mResident.size()) break;  // everything left is in use this frame
    const uint32_t i = mResident[best];
    mResident[best] = mResident.back();
    mResident.pop_back();
    Node& n = mNodes[i];
    n.state = ChunkState::kAbsent;
    mDrawable[i] = 0;
    addBytes(-int64_t(n.gpuBytes));
    n.gpuBytes = 0;
    adjustParent(i, -1);
    ++mCounters.evictions;
    evicted.push_back(i);
  }
  return evicted;
}

void Residency::dispatch() {
  // Requests not renewed this frame are cancelled; the rest start in order of priority.
  std::erase_if(mQueue, [&](uint32_t i) {
    if (mNodes[i].requested == mFrame) return false;
    mNodes[i].state = ChunkState::kAbsent;
    ++mCounters.cancelled;
    return true;
  });
  std::stable_sort(mQueue.begin(), mQueue.end(),
                   [&](uint32_t a, uint32_t b) { return mNodes[a].priority < mNodes[b].priority; });
  size_t started = 0;
  while (started < mQueue.size() && mInFlight < mOptions.maxInFlight &&
         mCounters.residentBytes < mOptions.budgetBytes) {
    const uint32_t node = mQueue[started++];
    mNodes[node].state = ChunkState::kLoading;
    adjustParent(node, +1);
    ++mInFlight;
    {
      std::lock_guard lock(*mDoneMutex);
      ++*mRunning;
    }
    mRunner.post([load = &mLoad, node, doneMutex = mDoneMutex, done = mDone, running = mRunning] {
      Result<LoadedChunk> result = (*load)(node);
      std::lock_guard lock(*doneMutex);
      done->push_back({node, std::move(result)});
      --*running;
    });
  }
  mQueue.erase(mQueue.begin(), mQueue.begin() + std::ptrdiff_t(started));
  ++mFrame;
}

}  // namespace terralod
