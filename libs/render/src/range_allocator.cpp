#include "terralod/render/range_allocator.h"

#include <cassert>
#include <iterator>

namespace terralod {

RangeAllocator::RangeAllocator(uint64_t capacity) : mCapacity(capacity) {
  if (capacity > 0) mFree.emplace(0, capacity);
}

std::optional<uint64_t> RangeAllocator::allocate(uint64_t size) {
  assert(size > 0);
  for (auto it = mFree.begin(); it != mFree.end(); ++it) {
    if (it->second < size) continue;
    const uint64_t offset = it->first, left = it->second - size;
    mFree.erase(it);
    if (left > 0) mFree.emplace(offset + size, left);
    mUsed += size;
    return offset;
  }
  return std::nullopt;
}

void RangeAllocator::release(uint64_t offset, uint64_t size) {
  assert(size > 0 && offset + size <= mCapacity && mUsed >= size);
  mUsed -= size;
  auto next = mFree.lower_bound(offset);
  // Merge with the free range after it, then with the one before it.
  if (next != mFree.end() && offset + size == next->first) {
    size += next->second;
    next = mFree.erase(next);
  }
  if (next != mFree.begin()) {
    auto previous = std::prev(next);
    if (previous->first + previous->second == offset) {
      previous->second += size;
      return;
    }
  }
  mFree.emplace(offset, size);
}

void RangeAllocator::grow(uint64_t extra) {
  if (extra == 0) return;
  const uint64_t offset = mCapacity;
  mCapacity += extra;
  mUsed += extra;  // release() takes it back out and merges it with a free tail
  release(offset, extra);
}

}  // namespace terralod
