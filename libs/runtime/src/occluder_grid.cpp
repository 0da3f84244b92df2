#include "terralod/runtime/occluder_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terralod {
namespace {

constexpr double kNone = std::numeric_limits<double>::infinity();

// The grid cells [first, last] of `count` over [0, width] DEM cells that the closed interval
// [a, b] (DEM cells from the grid's start) touches, boundaries included; exact in integers.
std::pair<uint32_t, uint32_t> touched(int64_t a, int64_t b, int64_t width, int64_t count) {
  a = std::clamp<int64_t>(a, 0, width);
  b = std::clamp<int64_t>(b, 0, width);
  // Cell i spans [width i / count, width (i + 1) / count].
  const int64_t first = std::max<int64_t>((a * count + width - 1) / width - 1, 0);
  const int64_t last = std::min<int64_t>(b * count / width, count - 1);
  return {uint32_t(first), uint32_t(last)};
}

}  // namespace

OccluderGridBuilder::OccluderGridBuilder(std::array<uint32_t, 2> min, std::array<uint32_t, 2> max,
                                         uint32_t cells) {
  if (!(min[0] < max[0] && min[1] < max[1]) || cells == 0) return;
  mGrid.min = min;
  mGrid.max = max;
  mGrid.cellsX = std::min(cells, max[0] - min[0]);
  mGrid.cellsY = std::min(cells, max[1] - min[1]);
  mLowest.assign(size_t(mGrid.cellsX) * mGrid.cellsY, kNone);
}

void OccluderGridBuilder::addTriangle(const std::array<uint32_t, 3>& xs,
                                      const std::array<uint32_t, 3>& ys, double lowest) {
  if (mLowest.empty()) return;
  const auto [x0, x1] = std::minmax({xs[0], xs[1], xs[2]});
  const auto [y0, y1] = std::minmax({ys[0], ys[1], ys[2]});
  const auto [i0, i1] = touched(int64_t(x0) - mGrid.min[0], int64_t(x1) - mGrid.min[0],
                                int64_t(mGrid.max[0] - mGrid.min[0]), mGrid.cellsX);
  const auto [j0, j1] = touched(int64_t(y0) - mGrid.min[1], int64_t(y1) - mGrid.min[1],
                                int64_t(mGrid.max[1] - mGrid.min[1]), mGrid.cellsY);
  for (uint32_t j = j0; j <= j1; ++j)
    for (uint32_t i = i0; i <= i1; ++i) {
      double& cell = mLowest[size_t(j) * mGrid.cellsX + i];
      cell = std::min(cell, lowest);
    }
}

OccluderGrid OccluderGridBuilder::finish() && {
  mGrid.floors.resize(mLowest.size());
  for (size_t k = 0; k < mLowest.size(); ++k) {
    const double z = mLowest[k];
    float f = -std::numeric_limits<float>::infinity();
    if (z != kNone && std::isfinite(z)) {
      f = float(z);
      if (double(f) > z) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
    }
    mGrid.floors[k] = f;
  }
  return std::move(mGrid);
}

}  // namespace terralod
