#pragma once
// Filling voids (nodata, NaN) in elevation grids.
//
// Method (documented in docs/format.md, "Voids"): pull-push interpolation. A pyramid is built
// by averaging the valid samples of each 2x2 block ("pull"); then, from the coarsest level
// down, every void sample starts from the bilinear interpolation of the level above and is
// relaxed towards the average of its four neighbours ("push" plus Jacobi relaxation of
// Laplace's equation). The result is a smooth membrane that meets the valid samples around
// each void; valid samples are never changed. O(samples) time, and memory for the pyramid (a
// third more than the grid) plus two rows; rows without voids are skipped when relaxing.

#include <cstdint>
#include <string>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/raster/heightfield.h"

namespace terralod {

/// Counts voids (NaN) in the grid.
uint64_t countVoids(const Heightfield& heights);

/// One flag per grid sample (grid order, south row first); 1 bit each.
class SampleMask {
 public:
  SampleMask() = default;
  SampleMask(int32_t columns, int32_t rows)
      : mColumns(columns), mRows(rows), mBits((size_t(columns) * size_t(rows) + 63) / 64, 0) {}
  int32_t columns() const { return mColumns; }
  int32_t rows() const { return mRows; }
  /// The flag at (x, y); outside the grid, the nearest edge sample's (as Heightfield::at).
  bool at(int32_t x, int32_t y) const {
    if (mBits.empty()) return false;
    x = x < 0 ? 0 : x >= mColumns ? mColumns - 1 : x;
    y = y < 0 ? 0 : y >= mRows ? mRows - 1 : y;
    const size_t i = size_t(y) * size_t(mColumns) + size_t(x);
    return (mBits[i >> 6] >> (i & 63)) & 1;
  }
  void set(int32_t x, int32_t y) {
    const size_t i = size_t(y) * size_t(mColumns) + size_t(x);
    mBits[i >> 6] |= uint64_t{1} << (i & 63);
  }
  uint64_t count() const;

 private:
  int32_t mColumns = 0, mRows = 0;
  std::vector<uint64_t> mBits;
};

/// Rim height at or below which a group of voids touching the raster's edge counts as sea.
constexpr double kSeaVoidRimHeight = 10.0;

/// The voids (NaN) that are sea, for the generated colour: every 4-connected group of voids
/// that touches the raster's edge and whose rim (the valid samples beside it, counted once per
/// void neighbour) lies at or below kSeaVoidRimHeight metres for at least a quarter of its
/// length. Seas left as nodata meet the coast at sea level along much of it (New Zealand's
/// 1 km grid: 30 % of the rim at or below 10 m); voids in mountains that reach the edge do not
/// (the Alps' SRTM voids: none). Call before fillVoids. Empty (no storage) when no void
/// touches the edge.
SampleMask seaVoids(const Heightfield& heights);

/// Fills every NaN sample; returns how many were filled. Fails when every sample is a void.
/// `subject` names the source in error messages.
Result<uint64_t> fillVoids(Heightfield& heights, const std::string& subject);

}  // namespace terralod
