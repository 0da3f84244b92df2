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
      mLevelLargest(size_t(std::max(tree.levelCount(), 1)), 0),
      mReservedBy(tree.nodes().size(), 0),
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

uint64_t Residency::reserve(uint32_t node) const {
  // The largest of its level seen so far, else of the nearest level above seen (a level's
  // chunks are about its parents' size), else of any.
  for (size_t level = std::min<size_t>(mTree.node(node).level, mLevelLargest.size() - 1);;
       --level) {
    if (mLevelLargest[level] > 0) return mLevelLargest[level];
    if (level == 0) return mLargest;
  }
}

void Residency::noteChunkBytes(uint32_t node, uint64_t bytes) {
  uint64_t& level =
      mLevelLargest[std::min<size_t>(mTree.node(node).level, mLevelLargest.size() - 1)];
  level = std::max(level, bytes);
  mLargest = std::max(mLargest, bytes);
}

bool Residency::fits(uint32_t node) const {
  return mCounters.residentBytes + mReserved + reserve(node) <= mOptions.budgetBytes;
}

void Residency::setSharedBytes(uint64_t bytes) {
  addBytes(int64_t(bytes) - int64_t(mCounters.sharedBytes));
  mCounters.sharedBytes = bytes;
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
    // A chunk now ready holds its decoded bytes, and still reserves what its upload may take
    // beyond them (a kind's shared memory growing with it).
    const uint64_t reserved = mReservedBy[f.node];
    unreserve(f.node);
    if (f.result) noteChunkBytes(f.node, f.result->bytes);
    if (f.result && !f.refresh && reserved > f.result->bytes) {
      mReservedBy[f.node] = reserved - f.result->bytes;
      mReserved += mReservedBy[f.node];
    }
    if (f.refresh) {
      // Kept only while the node is still resident (an evicted one reloads the new bytes);
      // it stays refreshing until uploaded (markRefreshed).
      if (f.result && n.state == ChunkState::kResident) {
        mCounters.bytesRead += f.result->bytesRead;
        addBytes(int64_t(f.result->bytes));
        mReady.push_back({f.node, std::move(f.result).value(), true});
        continue;
      }
      n.refreshing = false;
      if (!f.result) {
        if (mLog) mLog(f.result.error().message);
        ++mCounters.failures;
      }
      continue;
    }
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

void Residency::unreserve(uint32_t node) {
  mReserved -= mReservedBy[node];
  mReservedBy[node] = 0;
}

void Residency::markResident(const ReadyChunk& chunk, uint64_t gpuBytes, uint64_t sharedGrowth) {
  assert(mNodes[chunk.node].state == ChunkState::kReady);
  unreserve(chunk.node);
  addBytes(-int64_t(chunk.chunk.bytes));
  Node& n = mNodes[chunk.node];
  n.state = ChunkState::kResident;
  n.gpuBytes = gpuBytes;
  n.lastUsed = mFrame;
  mDrawable[chunk.node] = 1;
  addBytes(int64_t(gpuBytes + sharedGrowth));
  mCounters.sharedBytes += sharedGrowth;
  noteChunkBytes(chunk.node, gpuBytes + sharedGrowth);
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
  noteChunkBytes(node, gpuBytes);
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
  if (n.state == ChunkState::kResident) n.lastUsed = mFrame;  // wanted: in use
  if (n.state == ChunkState::kAbsent || (n.state == ChunkState::kFailed && mFrame >= n.retryAt)) {
    n.state = ChunkState::kQueued;
    mQueue.push_back(node);
  }
}

std::vector<uint32_t> Residency::evict() {
  std::vector<uint32_t> evicted;
  // Over the budget with the loads in flight, or without room for the most wanted load
  // waiting (dispatch starts it only when it fits: without room made here, a full budget
  // would keep it waiting for good) when it could start (not while the uploads are behind:
  // room made then would be taken back by what is evicted, wanted again, and so on).
  const auto next = std::min_element(mQueue.begin(), mQueue.end(), [&](uint32_t a, uint32_t b) {
    return mNodes[a].priority < mNodes[b].priority;
  });
  const auto overBudget = [&] {
    if (mCounters.residentBytes + mReserved > mOptions.budgetBytes) return true;
    return next != mQueue.end() && mNodes[*next].requested == mFrame && !uploadsBehind() &&
           !fits(*next);
  };
  // Loaded chunks nobody asked for this frame go first.
  if (overBudget()) {
    std::vector<ReadyChunk> keep;
    for (ReadyChunk& r : mReady) {
      if (mNodes[r.node].requested == mFrame) {
        keep.push_back(std::move(r));
        continue;
      }
      addBytes(-int64_t(r.chunk.bytes));
      unreserve(r.node);
      ++mCounters.discarded;
      if (r.refresh) {  // the node stays resident with its old payload: decode it again later
        mNodes[r.node].refreshing = false;
        invalidate(r.node);
        continue;
      }
      mNodes[r.node].state = ChunkState::kAbsent;
      adjustParent(r.node, -1);
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
    n.stale = false;  // it loads the new bytes when next wanted
    // A refresh of it waiting for its upload has nothing left to replace.
    std::erase_if(mReady, [&](const ReadyChunk& r) {
      if (r.node != i || !r.refresh) return false;
      addBytes(-int64_t(r.chunk.bytes));
      n.refreshing = false;
      return true;
    });
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
  while (started < mQueue.size() && mInFlight < mOptions.maxInFlight && !uploadsBehind() &&
         fits(mQueue[started])) {
    const uint32_t node = mQueue[started++];
    mNodes[node].state = ChunkState::kLoading;
    adjustParent(node, +1);
    mReservedBy[node] = reserve(node);
    mReserved += mReservedBy[node];
    post(node, false);
  }
  mQueue.erase(mQueue.begin(), mQueue.begin() + std::ptrdiff_t(started));
  startRefreshes();
  ++mFrame;
}

void Residency::post(uint32_t node, bool refresh) {
  ++mInFlight;
  {
    std::lock_guard lock(*mDoneMutex);
    ++*mRunning;
  }
  mRunner.post(
      [load = &mLoad, node, refresh, doneMutex = mDoneMutex, done = mDone, running = mRunning] {
        Result<LoadedChunk> result = (*load)(node);
        std::lock_guard lock(*doneMutex);
        done->push_back({node, std::move(result), refresh});
        --*running;
      });
}

void Residency::invalidate(uint32_t node) {
  Node& n = mNodes[node];
  if (!n.stale) mStale.push_back(node);
  n.stale = true;
}

bool Residency::stale(uint32_t node) const {
  const Node& n = mNodes[node];
  const bool held = n.state == ChunkState::kResident || n.state == ChunkState::kLoading ||
                    n.state == ChunkState::kReady;
  return held && (n.stale || n.refreshing);
}

size_t Residency::stale() const {
  return size_t(std::count_if(mStale.begin(), mStale.end(), [&](uint32_t i) { return stale(i); }));
}

void Residency::startRefreshes() {
  // Resident: decode again (beside the loads: an edit's chunks come back promptly). Loading
  // or ready: wait until resident. Otherwise the next load reads the new bytes.
  std::erase_if(mStale, [&](uint32_t i) {
    Node& n = mNodes[i];
    switch (n.state) {
      case ChunkState::kResident:
        if (n.stale && !n.refreshing) {
          n.stale = false;
          n.refreshing = true;
          post(i, true);
        }
        return !n.stale && !n.refreshing;
      case ChunkState::kLoading:
      case ChunkState::kReady:
        return false;
      default:
        n.stale = false;
        return !n.refreshing;
    }
  });
}

void Residency::markRefreshed(const ReadyChunk& chunk, uint64_t gpuBytes) {
  assert(chunk.refresh && mNodes[chunk.node].state == ChunkState::kResident);
  Node& n = mNodes[chunk.node];
  addBytes(-int64_t(chunk.chunk.bytes));
  addBytes(int64_t(gpuBytes) - int64_t(n.gpuBytes));
  n.gpuBytes = gpuBytes;
  n.refreshing = false;
}

}  // namespace terralod
