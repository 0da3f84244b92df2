#pragma once
// Integer keys to values, for a set of keys known roughly in advance and far smaller than the
// key space: open addressing with linear probing, sized for the expected count and doubled
// when more than `kMaxLoadPercent` of the slots would be used (half by default: lookups of
// absent keys stay short). No erase. The RTIN codec numbers a large chunk square's
// vertices with one (KeyHash), where a dense table over the square would be mostly empty; the
// coarse levels of a staged build keep their sparse activations and heights in others, where
// std::unordered_map spent a fifth of the coarse job in finding keys (a node per key, and a
// division per lookup).

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace terralod {

template <typename Key, typename Value, unsigned kMaxLoadPercent = 50>
class KeyMap {
 public:
  /// The one key that cannot be stored.
  static constexpr Key kNoKey = ~Key{0};

  /// Room for `expected` keys before it grows; at most 2^16 up front (an untrusted count
  /// reserves no more).
  explicit KeyMap(size_t expected = 0) {
    rehash(std::bit_ceil(slotsFor(std::clamp<size_t>(expected, 8, size_t{1} << 16))));
  }
  size_t size() const { return mCount; }
  /// The value at `key`, or null.
  const Value* find(Key key) const {
    for (size_t i = slotOf(key);; i = (i + 1) & mMask) {
      if (mKeys[i] == key) return &mValues[i];
      if (mKeys[i] == kNoKey) return nullptr;
    }
  }
  /// The value at `key`, set to `value` if it had none.
  Value findOrAdd(Key key, Value value) {
    if (slotsFor(mCount + 1) > mKeys.size()) rehash(2 * mKeys.size());
    for (size_t i = slotOf(key);; i = (i + 1) & mMask) {
      if (mKeys[i] == key) return mValues[i];
      if (mKeys[i] == kNoKey) {
        mKeys[i] = key;
        mValues[i] = value;
        ++mCount;
        return value;
      }
    }
  }

 private:
  static size_t slotsFor(size_t keys) {
    return (keys * 100 + kMaxLoadPercent - 1) / kMaxLoadPercent;
  }
  // Fibonacci hashing: the top bits of the key times 2^64 / phi.
  size_t slotOf(Key key) const { return size_t((uint64_t(key) * 0x9E3779B97F4A7C15ull) >> mShift); }
  void rehash(size_t capacity) {
    std::vector<Key> oldKeys = std::exchange(mKeys, std::vector<Key>(capacity, kNoKey));
    std::vector<Value> oldValues = std::exchange(mValues, std::vector<Value>(capacity));
    mMask = capacity - 1;
    mShift = 64 - std::countr_zero(capacity);
    mCount = 0;
    for (size_t i = 0; i < oldKeys.size(); ++i)
      if (oldKeys[i] != kNoKey) findOrAdd(oldKeys[i], oldValues[i]);
  }
  // Keys and values apart: a uint64_t key beside a uint8_t value would take 16 bytes a slot.
  std::vector<Key> mKeys;
  std::vector<Value> mValues;
  size_t mMask = 0, mCount = 0;
  int mShift = 64;
};

/// 32-bit keys to int32 values, -1 for a key that is not there.
class KeyHash : public KeyMap<uint32_t, int32_t> {
 public:
  using KeyMap::KeyMap;
  /// The value at `key`, or -1.
  int32_t find(uint32_t key) const {
    const int32_t* value = KeyMap::find(key);
    return value ? *value : -1;
  }
};

}  // namespace terralod
