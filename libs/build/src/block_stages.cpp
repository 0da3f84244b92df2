#include "block_stages.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace terralod {

Pass1Block pass1Block(const TreeLayout& layout, const ErrorBudget& budget, GridPoint origin,
                      int32_t block, const float* window, BlockScratch& scratch) {
  Pass1Block out;
  out.grid = ActivationGrid::window(origin.x, origin.y, block, block);
  const size_t n = size_t(block + 1) * (block + 1);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (size_t i = 0; i < n; ++i) {
    const float v = window[i];
    out.sawVoid |= std::isnan(v);
    lo = std::min(lo, double(v));
    hi = std::max(hi, double(v));
  }
  out.minHeight = lo;
  out.maxHeight = hi;
  if (origin.x >= layout.cellsX || origin.y >= layout.cellsY || out.sawVoid) return out;
  scratch.reset(block);
  std::copy(window, window + n, scratch.heights.begin());
  BlockGeometry geometry;
  geometry.side = block;
  geometry.origin = origin;
  geometry.realX = std::min(block, layout.cellsX - origin.x);
  geometry.realY = std::min(block, layout.cellsY - origin.y);
  BlockResult result;
  computeBlock(geometry, budget, scratch, out.grid, result, out.stats);
  // computeBlock wrote the interior; the border rows and columns are in scratch, one-sided.
  const size_t stride = size_t(block) + 1;
  for (int32_t y = 0; y <= block; ++y)
    out.grid.setRun(origin.x, origin.y + y, scratch.activation.data() + size_t(y) * stride,
                    block + 1);
  out.square = {result.squareErrors, true};
  return out;
}

std::vector<uint8_t> haloValues(const ActivationGrid& window, const HaloPattern& halo) {
  const uint32_t stride = uint32_t(halo.side) + 1;
  std::vector<uint8_t> values(halo.points.size());
  for (size_t i = 0; i < values.size(); ++i)
    values[i] = window.get(window.originX() + int32_t(halo.points[i] % stride),
                           window.originY() + int32_t(halo.points[i] / stride));
  return values;
}

void applyHalo(ActivationGrid& window, const HaloPattern& halo,
               const std::vector<uint8_t>& values) {
  const uint32_t stride = uint32_t(halo.side) + 1;
  for (size_t i = 0; i < values.size(); ++i)
    window.set(window.originX() + int32_t(halo.points[i] % stride),
               window.originY() + int32_t(halo.points[i] / stride), values[i]);
}

}  // namespace terralod
