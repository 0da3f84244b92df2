#pragma once
// For every grid point, how many levels (counted up from the leaves) include it as a mesh
// vertex: the "activation" of the RTIN vertex, 4 bits per point. A point with activation a is
// a vertex of every chunk at level L >= depth + 1 - a that contains it. Activations are
// saturated: a point's value is at least that of every point that depends on it, which makes
// each level's mesh conforming and each finer level's mesh a refinement of the coarser one.
//
// A grid covers the whole tree, or one block's closed square (a window with an origin: what a
// cluster build's block job holds), or only the points at or above some activation (sparse:
// what the coarse levels need; every other point reads as 0, which no coarse level can tell
// from its true value).

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "terralod/core/key_hash.h"
#include "terralod/core/large_buffer.h"

namespace terralod {

class ActivationGrid {
 public:
  /// Whole-tree grids are tens of megabytes, filled once: huge pages where the system has them.
  using Nibbles = std::vector<uint8_t, LargeBufferAllocator<uint8_t>>;

  ActivationGrid() = default;
  /// Points (0..cellsX) x (0..cellsY), all zero.
  ActivationGrid(int32_t cellsX, int32_t cellsY)
      : mCellsX(cellsX),
        mCellsY(cellsY),
        mRowBytes((int64_t(cellsX) + 2) / 2),
        mNibbles(size_t(mRowBytes) * (int64_t(cellsY) + 1)) {}  // zero, untouched

  /// Points (x0..x0+cellsX) x (y0..y0+cellsY) of a larger grid, all zero; x0 even.
  static ActivationGrid window(int32_t x0, int32_t y0, int32_t cellsX, int32_t cellsY) {
    ActivationGrid g(cellsX, cellsY);
    g.mX0 = x0;
    g.mY0 = y0;
    return g;
  }
  using SparsePoints = KeyMap<uint64_t, uint8_t, 75>;  ///< key(x, y) -> activation (first kept)
  static ActivationGrid sparse(std::shared_ptr<const SparsePoints> points) {
    ActivationGrid g;
    g.mSparse = std::move(points);
    return g;
  }
  static uint64_t key(int32_t x, int32_t y) { return (uint64_t(uint32_t(y)) << 32) | uint32_t(x); }

  int32_t originX() const { return mX0; }
  int32_t originY() const { return mY0; }
  int32_t cellsX() const { return mCellsX; }
  int32_t cellsY() const { return mCellsY; }
  size_t bytes() const { return mNibbles.size(); }
  /// The packed points (two to a byte, rows padded to whole bytes), for saving a window.
  Nibbles& nibbles() { return mNibbles; }
  const Nibbles& nibbles() const { return mNibbles; }

  uint8_t get(int32_t x, int32_t y) const {
    if (mSparse) [[unlikely]] {
      const uint8_t* value = mSparse->find(key(x, y));
      return value ? *value : 0;
    }
    x -= mX0;
    y -= mY0;
    const uint8_t byte = mNibbles[size_t(y) * mRowBytes + (x >> 1)];
    return (x & 1) ? byte >> 4 : byte & 0x0F;
  }
  /// Not safe against a concurrent set() of the other point sharing the byte: rows start on a
  /// byte boundary and points (2k, 2k+1) share one, which callers partition around. Dense
  /// grids only.
  void set(int32_t x, int32_t y, uint8_t value) {
    x -= mX0;
    y -= mY0;
    uint8_t& byte = mNibbles[size_t(y) * mRowBytes + (x >> 1)];
    byte = (x & 1) ? uint8_t((byte & 0x0F) | (value << 4)) : uint8_t((byte & 0xF0) | value);
  }

  /// Sets `count` consecutive points of row y from x on. Only the bytes holding those points
  /// are touched (the neighbours sharing the first and last byte are preserved).
  void setRun(int32_t x, int32_t y, const uint8_t* values, int32_t count) {
    int32_t i = 0;
    if (count > 0 && ((x - mX0) & 1)) set(x, y, values[i++]);
    uint8_t* row = mNibbles.data() + size_t(y - mY0) * mRowBytes;
    for (; i + 1 < count; i += 2)
      row[(x - mX0 + i) >> 1] = uint8_t(values[i] | (values[i + 1] << 4));
    if (i < count) set(x + i, y, values[i]);
  }

 private:
  int32_t mX0 = 0, mY0 = 0;
  int32_t mCellsX = 0;
  int32_t mCellsY = 0;
  int64_t mRowBytes = 0;
  Nibbles mNibbles;
  std::shared_ptr<const SparsePoints> mSparse;
};

}  // namespace terralod
