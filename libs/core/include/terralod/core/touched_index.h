#pragma once
// A dense table of indices (one int32 per key, -1 until set) that one owner reuses for many
// small jobs: clear() resets only the keys set since the last clear, so a job costs what it
// touches, not a fill of the whole table. The chunk mesher numbers a chunk's vertices with
// one; the RTIN codec's walks keep one per thread.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace terralod {

class TouchedIndex {
 public:
  /// Room for keys 0 .. n - 1 (new ones unset). Grows only; call between jobs.
  void reserve(size_t n) {
    if (mSlots.size() < n) mSlots.resize(n, -1);
  }
  size_t size() const { return mSlots.size(); }
  int32_t find(size_t key) const { return mSlots[key]; }
  /// The index at `key`, set to `next` if it had none.
  int32_t findOrAdd(size_t key, int32_t next) {
    int32_t& slot = mSlots[key];
    if (slot < 0) {
      slot = next;
      mTouched.push_back(key);
    }
    return slot;
  }
  /// Every key unset again.
  void clear() {
    for (size_t key : mTouched) mSlots[key] = -1;
    mTouched.clear();
  }

 private:
  std::vector<int32_t> mSlots;
  std::vector<size_t> mTouched;
};

}  // namespace terralod
