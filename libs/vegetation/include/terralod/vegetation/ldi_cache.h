#pragma once
// The LDIs a frame needs, read from a .tlv file (local or over HTTP) when first wanted and kept
// while they fit a byte budget; the least recently used go first. Render thread only.

#include <cstdint>
#include <functional>
#include <list>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "terralod/vegetation/frame_warp.h"
#include "terralod/vegetation/vegetation_file.h"

namespace terralod::veg {

struct LdiCacheStats {
  uint64_t reads = 0;     ///< LDIs read and decoded
  uint64_t failures = 0;  ///< reads that failed (each logged once)
  uint64_t evictions = 0;
  uint64_t residentBytes = 0;  ///< decoded LDIs held
  double readMs = 0;           ///< reading and decoding, all reads so far
};

class LdiCache final : public LdiSource {
 public:
  /// `log` gets one line per LDI that cannot be read (the tile is then left out).
  LdiCache(const VegetationReader& file, uint64_t budgetBytes,
           std::function<void(const std::string&)> log = {});

  /// LDIs handed out in a frame are not evicted before the next (the budget may be
  /// exceeded for a frame that needs more).
  void beginFrame() override { ++mFrame; }
  const WarpLdi* ldi(int prototile, int resolution, int direction) override;
  uint64_t depthPixels(int prototile, int resolution, int direction) const override;

  const LdiCacheStats& stats() const { return mStats; }
  /// Bytes a decoded LDI holds.
  static uint64_t bytesOf(const WarpLdi& ldi);

 private:
  struct Entry {
    std::unique_ptr<WarpLdi> ldi;
    uint64_t bytes = 0;
    std::list<int>::iterator lru;
    uint64_t frame = 0;  // last handed out in
  };
  const VegetationReader& mFile;
  uint64_t mBudget;
  std::function<void(const std::string&)> mLog;
  std::unordered_map<int, Entry> mEntries;
  std::list<int> mLru;  // most recent first
  std::vector<bool> mFailed;
  LdiCacheStats mStats;
  uint64_t mFrame = 0;
};

}  // namespace terralod::veg
