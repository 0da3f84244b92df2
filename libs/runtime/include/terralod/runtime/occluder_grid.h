#pragma once
// A chunk's occluders for horizon culling (horizon_culling.h), whatever its mesh kind: its
// footprint cut into a few cells per side, each with a height at or below every point of the
// surface the chunk draws over that cell, at any morph parameter. Under a chunk that is drawn,
// the solid {cell} x (-inf, floor] lies below drawn triangles, which is what makes it an
// occluder. A kind's decode (loader threads) makes the grid from its decoded surface; the
// frame driver keeps the grids of the resident chunks.

#include <array>
#include <cstdint>
#include <vector>

namespace terralod {

struct OccluderGrid {
  /// The footprint the grid covers, in grid (DEM) cells from the chunk's south-west corner:
  /// [min, max] along x and y. The chunk's surface covers all of it.
  std::array<uint32_t, 2> min{}, max{};
  uint32_t cellsX = 0, cellsY = 0;  ///< grid cells along x and y (0: no grid)
  /// cellsX * cellsY floors in metres, row by row from the south-west; -inf where nothing is
  /// known (no triangle touched the cell).
  std::vector<float> floors;

  bool empty() const { return floors.empty(); }
  /// Memory it holds.
  uint64_t bytes() const { return sizeof(OccluderGrid) + floors.capacity() * sizeof(float); }
  /// Where grid cell column i (0..cellsX) begins, in DEM cells from the chunk's corner.
  double columnX(uint32_t i) const {
    return double(min[0]) + double(max[0] - min[0]) * double(i) / double(cellsX);
  }
  double rowY(uint32_t j) const {
    return double(min[1]) + double(max[1] - min[1]) * double(j) / double(cellsY);
  }
};

/// Makes a grid from a chunk's surface triangles.
class OccluderGridBuilder {
 public:
  /// Cells per side of the grids kinds make (16 x 16 floats: 1 KB a chunk).
  static constexpr uint32_t kCells = 16;

  /// The footprint in DEM cells from the chunk's corner (min < max on both axes, else the
  /// grid is empty); at most `cells` grid cells per side, and no grid cell smaller than a
  /// DEM cell.
  OccluderGridBuilder(std::array<uint32_t, 2> min, std::array<uint32_t, 2> max,
                      uint32_t cells = kCells);

  /// A surface triangle with these corners (DEM cells from the chunk's corner) that is never
  /// drawn below `lowest` metres (e.g. the least of its corners' heights at morph 0 and 1):
  /// lowers every grid cell its bounding box touches (boundaries included) to `lowest`.
  void addTriangle(const std::array<uint32_t, 3>& xs, const std::array<uint32_t, 3>& ys,
                   double lowest);

  /// The grid; floors rounded down to float, -inf in cells no triangle touched.
  OccluderGrid finish() &&;

 private:
  OccluderGrid mGrid;
  std::vector<double> mLowest;
};

}  // namespace terralod
