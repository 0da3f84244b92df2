#pragma once
// Geometry of the chunk tree over a grid of samples: a forest of square root chunks of
// `rootCells` cells, each a quadtree `depth` levels deep down to leaves of `leafCells` cells.
// The data occupies grid points [0, cellsX] x [0, cellsY]; the roots cover at least that and
// chunks wholly outside it do not exist. Levels count from 0 (roots) to depth (leaves).

#include <cstdint>
#include <vector>

#include "terralod/core/result.h"

namespace terralod {

struct TreeLayout {
  int32_t cellsX = 0;     ///< data extent in cells: columns - 1
  int32_t cellsY = 0;     ///< rows - 1
  int32_t leafCells = 0;  ///< side of a leaf chunk in cells (power of two)
  int32_t depth = 0;      ///< leaf level; levels are 0..depth
  int32_t rootCells = 0;  ///< side of a root chunk in cells = leafCells << depth
  int32_t rootsX = 0;
  int32_t rootsY = 0;

  int32_t levelCount() const { return depth + 1; }
  int32_t gridX() const { return rootsX * rootCells; }  ///< padded grid extent in cells
  int32_t gridY() const { return rootsY * rootCells; }
  /// Smallest power of two covering the padded grid (for bintree vertex classification).
  int32_t gridSide() const;
  int32_t chunkCells(int32_t level) const { return rootCells >> level; }
  /// Number of chunk columns/rows at a level that touch the data.
  int32_t chunksX(int32_t level) const;
  int32_t chunksY(int32_t level) const;
  bool chunkExists(int32_t level, int32_t ix, int32_t iy) const {
    const int32_t s = chunkCells(level);
    return ix >= 0 && iy >= 0 && int64_t(ix) * s < cellsX && int64_t(iy) * s < cellsY;
  }
  /// The coarsest level at which the grid line x = coordinate (or y) is a chunk border;
  /// chunks across that line from a chunk at `level` can be no coarser than this.
  int32_t coarsestLevelOfBorder(int32_t coordinate, int32_t level) const;
};

/// Chooses the layout for a raster. leafCells = 0 picks the default: 64 cells, smaller for
/// small rasters so that they still get a few levels. Fails on an unusable leafCells.
Result<TreeLayout> makeTreeLayout(int32_t columns, int32_t rows, int32_t leafCells);

/// Geometric error per level: levelError[L] = leafError * 2^(depth - L) (paper eq. 1).
std::vector<double> levelErrors(const TreeLayout& layout, double leafError);

}  // namespace terralod
