#include "terralod/build/tree_layout.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace terralod {
namespace {
constexpr int32_t kMaxRootCells = 32768;  // chunk-local coordinates must fit 16 bits
int32_t nextPow2(int32_t v) {
  return static_cast<int32_t>(std::bit_ceil(static_cast<uint32_t>(std::max(v, 1))));
}
}  // namespace

int32_t TreeLayout::gridSide() const {
  return nextPow2(std::max(gridX(), gridY()));
}

int32_t TreeLayout::chunksX(int32_t level) const {
  const int32_t s = chunkCells(level);
  return (cellsX + s - 1) / s;
}

int32_t TreeLayout::chunksY(int32_t level) const {
  const int32_t s = chunkCells(level);
  return (cellsY + s - 1) / s;
}

int32_t TreeLayout::coarsestLevelOfBorder(int32_t coordinate, int32_t level) const {
  int32_t l = level;
  while (l > 0 && coordinate % chunkCells(l - 1) == 0) --l;
  return l;
}

Result<TreeLayout> makeTreeLayout(int32_t columns, int32_t rows, int32_t leafCells) {
  TreeLayout t;
  t.cellsX = columns - 1;
  t.cellsY = rows - 1;
  if (t.cellsX < 1 || t.cellsY < 1) return Error{"raster needs at least 2x2 samples"};
  const int32_t shortSide = nextPow2(std::min(t.cellsX, t.cellsY));
  if (leafCells == 0) {
    leafCells = std::clamp(shortSide / 4, 16, 64);
  } else if (leafCells < 4 || leafCells > 256 || !std::has_single_bit(uint32_t(leafCells))) {
    return Error{"--chunk-cells must be a power of two from 4 to 256, not " +
                 std::to_string(leafCells)};
  }
  t.leafCells = leafCells;
  t.rootCells = std::clamp(shortSide, leafCells, std::max(leafCells, kMaxRootCells));
  t.depth = std::countr_zero(uint32_t(t.rootCells / leafCells));
  t.rootsX = (t.cellsX + t.rootCells - 1) / t.rootCells;
  t.rootsY = (t.cellsY + t.rootCells - 1) / t.rootCells;
  return t;
}

std::vector<double> levelErrors(const TreeLayout& layout, double leafError) {
  std::vector<double> errors(layout.levelCount());
  for (int32_t l = 0; l <= layout.depth; ++l) errors[l] = std::ldexp(leafError, layout.depth - l);
  return errors;
}

}  // namespace terralod
