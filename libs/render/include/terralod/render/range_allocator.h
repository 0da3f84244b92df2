#pragma once
// First-fit allocation of ranges inside a fixed-size space (e.g. a GPU buffer): the book-keeping
// only, no memory. Adjacent free ranges merge on release. Not thread-safe.

#include <cstdint>
#include <map>
#include <optional>

namespace terralod {

class RangeAllocator {
 public:
  explicit RangeAllocator(uint64_t capacity);

  /// The offset of a free range of `size` units (> 0), or nothing when no free range is big
  /// enough.
  std::optional<uint64_t> allocate(uint64_t size);
  /// Returns a range that allocate() gave out, with the same size.
  void release(uint64_t offset, uint64_t size);
  /// Adds `extra` units at the end of the space (after the owner grew its buffer).
  void grow(uint64_t extra);

  uint64_t capacity() const { return mCapacity; }
  uint64_t used() const { return mUsed; }

 private:
  std::map<uint64_t, uint64_t> mFree;  // offset -> size
  uint64_t mCapacity = 0;
  uint64_t mUsed = 0;
};

}  // namespace terralod
