#include "terralod/vegetation/ldi_cache.h"

#include <chrono>

namespace terralod::veg {

LdiCache::LdiCache(const VegetationReader& file, uint64_t budgetBytes,
                   std::function<void(const std::string&)> log)
    : mFile(file), mBudget(budgetBytes), mLog(std::move(log)), mFailed(kLdiCount, false) {}

uint64_t LdiCache::bytesOf(const WarpLdi& w) {
  return sizeof(WarpLdi) + w.ldi.layerCounts.size() + w.ldi.pixels.size() * sizeof(DepthPixel) +
         w.rowStarts.size() * sizeof(uint64_t);
}

uint64_t LdiCache::depthPixels(int prototile, int resolution, int direction) const {
  return mFile.entry(prototile, resolution, direction).depthPixels;
}

const WarpLdi* LdiCache::ldi(int prototile, int resolution, int direction) {
  const int index = ldiIndex(prototile, resolution, direction);
  if (auto it = mEntries.find(index); it != mEntries.end()) {
    mLru.splice(mLru.begin(), mLru, it->second.lru);
    it->second.frame = mFrame;
    return it->second.ldi.get();
  }
  if (mFailed[size_t(index)]) return nullptr;
  const auto start = std::chrono::steady_clock::now();
  auto read = mFile.readLdi(prototile, resolution, direction);
  mStats.readMs +=
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (!read) {
    mFailed[size_t(index)] = true;
    ++mStats.failures;
    if (mLog) mLog(read.error().message);
    return nullptr;
  }
  ++mStats.reads;
  Entry e;
  e.ldi = std::make_unique<WarpLdi>(WarpLdi::of(std::move(read).value()));
  e.bytes = bytesOf(*e.ldi);
  // Make room, least recently used first (never the one being added).
  e.frame = mFrame;
  while (!mLru.empty() && mStats.residentBytes + e.bytes > mBudget) {
    const int victim = mLru.back();
    if (mEntries[victim].frame == mFrame) break;  // this frame's: the rest are too
    mLru.pop_back();
    mStats.residentBytes -= mEntries[victim].bytes;
    mEntries.erase(victim);
    ++mStats.evictions;
  }
  mLru.push_front(index);
  e.lru = mLru.begin();
  mStats.residentBytes += e.bytes;
  return mEntries.emplace(index, std::move(e)).first->second.ldi.get();
}

}  // namespace terralod::veg
