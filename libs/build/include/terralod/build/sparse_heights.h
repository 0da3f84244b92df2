#pragma once
// The heights the coarse part of the build needs when the raster is streamed: every sample on
// the block grid lines (chunk corners and the sides of chunks of a block or larger) and on the
// data's last row and column (where clamped padding points land), plus the points recorded as
// vertices of coarse levels. Recording is thread-safe; reading starts after recording ended.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <vector>

#include "terralod/build/height_source.h"
#include "terralod/build/tree_layout.h"
#include "terralod/core/key_hash.h"

namespace terralod {

class SparseHeights final : public HeightSampler {
 public:
  SparseHeights(const TreeLayout& layout, int32_t blockCells);

  /// Records the parts of a window (grid order, w x h at x0, y0) that lie on kept lines.
  void recordLines(int32_t x0, int32_t y0, int32_t w, int32_t h, const float* values);
  /// Records single points (x, y, height).
  void recordPoints(const std::vector<std::pair<uint64_t, float>>& points);
  static uint64_t key(int32_t x, int32_t y) { return (uint64_t(uint32_t(y)) << 32) | uint32_t(x); }

  /// Height at a grid point (clamped to the data). Points never recorded count as misses and
  /// return NaN, which the callers' tests treat as a bug.
  double at(int32_t x, int32_t y) const override;
  uint64_t misses() const { return mMisses.load(); }
  size_t pointCount() const { return mPoints.size(); }

 private:
  const TreeLayout& mLayout;
  int32_t mBlock;
  std::vector<std::vector<float>> mRows;  // y = k * block, and y = cellsY last
  std::vector<std::vector<float>> mColumns;
  KeyMap<uint64_t, float, 75> mPoints;
  std::mutex mMutex;
  mutable std::atomic<uint64_t> mMisses{0};
};

}  // namespace terralod
