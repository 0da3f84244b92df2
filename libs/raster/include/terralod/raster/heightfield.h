#pragma once
// An in-memory grid of heights in grid order (south row first), used when the input fits the
// memory budget and by tests.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "terralod/core/large_buffer.h"

namespace terralod {

class Heightfield {
 public:
  /// Rasters are hundreds of megabytes, filled once: huge pages where the system has them.
  using Values = std::vector<float, LargeBufferAllocator<float>>;

  Heightfield() = default;
  /// All `fill`; zeros cost nothing until the samples are written (LargeBufferAllocator).
  Heightfield(int32_t columns, int32_t rows, float fill = 0.0f)
      : mColumns(columns), mRows(rows), mValues(size_t(columns) * rows) {
    if (fill != 0.0f || std::signbit(fill)) std::fill(mValues.begin(), mValues.end(), fill);
  }

  int32_t columns() const { return mColumns; }
  int32_t rows() const { return mRows; }
  bool empty() const { return mValues.empty(); }

  /// Height at grid point (x, y); outside the grid the nearest edge sample (replication).
  float at(int32_t x, int32_t y) const {
    x = std::clamp(x, 0, mColumns - 1);
    y = std::clamp(y, 0, mRows - 1);
    return mValues[size_t(y) * mColumns + x];
  }
  float& operator()(int32_t x, int32_t y) { return mValues[size_t(y) * mColumns + x]; }
  float operator()(int32_t x, int32_t y) const { return mValues[size_t(y) * mColumns + x]; }
  const float* row(int32_t y) const { return mValues.data() + size_t(y) * mColumns; }
  float* row(int32_t y) { return mValues.data() + size_t(y) * mColumns; }
  Values& values() { return mValues; }
  const Values& values() const { return mValues; }

 private:
  int32_t mColumns = 0;
  int32_t mRows = 0;
  Values mValues;
};

}  // namespace terralod
