#include "terralod/build/sparse_heights.h"

#include <algorithm>
#include <cmath>

namespace terralod {

SparseHeights::SparseHeights(const TreeLayout& layout, int32_t blockCells)
    : mLayout(layout), mBlock(blockCells) {
  // One slot per block line inside the data, plus the data's last row / column.
  mRows.resize(size_t(layout.cellsY / blockCells) + 2);
  mColumns.resize(size_t(layout.cellsX / blockCells) + 2);
  for (auto& r : mRows) r.assign(size_t(layout.cellsX) + 1, std::nanf(""));
  for (auto& c : mColumns) c.assign(size_t(layout.cellsY) + 1, std::nanf(""));
}

void SparseHeights::recordLines(int32_t x0, int32_t y0, int32_t w, int32_t h, const float* values) {
  const int32_t xa = std::max(x0, 0), xb = std::min(x0 + w - 1, mLayout.cellsX);
  const int32_t ya = std::max(y0, 0), yb = std::min(y0 + h - 1, mLayout.cellsY);
  std::lock_guard lock(mMutex);
  for (int32_t y = ya; y <= yb; ++y) {
    std::vector<float>* rows[2] = {y % mBlock == 0 ? &mRows[size_t(y / mBlock)] : nullptr,
                                   y == mLayout.cellsY ? &mRows.back() : nullptr};
    for (std::vector<float>* row : rows)
      if (row)
        std::copy(values + size_t(y - y0) * w + (xa - x0),
                  values + size_t(y - y0) * w + (xb - x0) + 1, row->begin() + xa);
  }
  for (int32_t x = xa; x <= xb; ++x) {
    std::vector<float>* columns[2] = {x % mBlock == 0 ? &mColumns[size_t(x / mBlock)] : nullptr,
                                      x == mLayout.cellsX ? &mColumns.back() : nullptr};
    for (std::vector<float>* column : columns)
      if (column)
        for (int32_t y = ya; y <= yb; ++y)
          (*column)[size_t(y)] = values[size_t(y - y0) * w + (x - x0)];
  }
}

void SparseHeights::recordPoints(const std::vector<std::pair<uint64_t, float>>& points) {
  std::lock_guard lock(mMutex);
  for (const auto& [key, height] : points) mPoints.findOrAdd(key, height);
}

double SparseHeights::at(int32_t x, int32_t y) const {
  x = std::clamp(x, 0, mLayout.cellsX);
  y = std::clamp(y, 0, mLayout.cellsY);
  float v;
  if (y % mBlock == 0) {
    v = mRows[size_t(y / mBlock)][size_t(x)];
  } else if (y == mLayout.cellsY) {
    v = mRows.back()[size_t(x)];
  } else if (x % mBlock == 0) {
    v = mColumns[size_t(x / mBlock)][size_t(y)];
  } else if (x == mLayout.cellsX) {
    v = mColumns.back()[size_t(y)];
  } else {
    const float* height = mPoints.find(key(x, y));
    v = height ? *height : std::nanf("");
  }
  if (std::isnan(v)) mMisses.fetch_add(1, std::memory_order_relaxed);
  return v;
}

}  // namespace terralod
