#pragma once
// 32-bit keys to int32 values, for a set of keys known roughly in advance and far smaller than
// the key space: open addressing with linear probing, sized for the expected count at half
// load and doubled when that is passed. No erase. The RTIN codec numbers a large chunk
// square's vertices with one, where a dense table over the square would be mostly empty.

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace terralod {

class KeyHash {
 public:
  /// The one key that cannot be stored.
  static constexpr uint32_t kNoKey = ~uint32_t{0};

  /// Room for `expected` keys before it grows; at most 2^16 up front (an untrusted count
  /// reserves no more).
  explicit KeyHash(size_t expected) {
    rehash(std::bit_ceil(2 * std::clamp<size_t>(expected, 8, size_t{1} << 16)));
  }
  size_t size() const { return mCount; }
  /// The value at `key`, or -1.
  int32_t find(uint32_t key) const {
    for (size_t i = slotOf(key);; i = (i + 1) & mMask) {
      if (mEntries[i].key == key) return mEntries[i].value;
      if (mEntries[i].key == kNoKey) return -1;
    }
  }
  /// The value at `key`, set to `value` if it had none.
  int32_t findOrAdd(uint32_t key, int32_t value) {
    if (2 * (mCount + 1) > mEntries.size()) rehash(2 * mEntries.size());
    for (size_t i = slotOf(key);; i = (i + 1) & mMask) {
      Entry& e = mEntries[i];
      if (e.key == key) return e.value;
      if (e.key == kNoKey) {
        e = {key, value};
        ++mCount;
        return value;
      }
    }
  }

 private:
  struct Entry {
    uint32_t key;
    int32_t value;
  };
  // Fibonacci hashing: the top bits of the key times 2^64 / phi.
  size_t slotOf(uint32_t key) const {
    return size_t((uint64_t(key) * 0x9E3779B97F4A7C15ull) >> mShift);
  }
  void rehash(size_t capacity) {
    std::vector<Entry> old = std::exchange(mEntries, std::vector<Entry>(capacity, {kNoKey, -1}));
    mMask = capacity - 1;
    mShift = 64 - std::countr_zero(capacity);
    mCount = 0;
    for (const Entry& e : old)
      if (e.key != kNoKey) findOrAdd(e.key, e.value);
  }
  std::vector<Entry> mEntries;
  size_t mMask = 0, mCount = 0;
  int mShift = 64;
};

}  // namespace terralod
