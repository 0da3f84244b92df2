#pragma once
// A synthetic elevation model for benchmarks and tests: mountains, hills and flats in metres,
// defined on an unbounded grid so that any window can be generated on its own, exactly.
//
// Grid convention: this class works in raster order, like the GeoTIFF it feeds. Column c grows
// eastwards and row r southwards (row 0 is the northern edge); windows come back north row
// first. terralod's grid rows run the other way (gy = rows - 1 - r), so a caller that wants
// grid order flips the rows. Sample (c, r) sits c * spacing metres east and r * spacing metres
// south of the north-west corner, so a larger raster extends a smaller one (same seed and
// spacing) to the east and south, and the two agree on every sample they share.
//
// The terrain, in world metres so that it looks the same at any raster size:
//  - a gentle domain warp (about 500 m at a 6 km wavelength) bends every large-scale feature;
//  - a "continent" mask (fBm, 14 km wavelength) makes flats where it is low, rolling hills in
//    between and mountains where it is high; the base level of the land rises with it;
//  - mountains are a ridged multifractal (Musgrave: each octave is (1 - |noise|)^2 weighted by
//    the octave before, so crests are sharp and rough and valleys smooth) with ridges a few km
//    apart and up to ~1.2 km of relief, cut by V-shaped valleys along the zero lines of a
//    warped 8 km noise; octaves shorter than 1 km add plain noise scaled by the same weight;
//  - hills are fBm of the same octaves; octaves continue down to twice the cell size, so a
//    1 m raster is rough where real terrain would be.
// Heights stay within about 50..1700 m.
//
// The height is a pure function of (column, row, seed, spacing). Everything whose wavelength
// is at least 128 cells (mask, warp, valleys, coarse octaves) is evaluated on a global lattice
// every 8 cells and interpolated with Catmull-Rom cubics; the finer octaves are evaluated per
// sample in 256-column chunks anchored at multiples of 256. Both are part of the definition,
// and neither depends on the window, the thread or the order of evaluation. The arithmetic is
// plain IEEE (+, -, *, /, sqrt, floor, conversions; no transcendental functions), so with
// -ffp-contract=off every run, vectorised or not, gives the same bits.

#include <cstdint>
#include <memory>

namespace terralod {

class SyntheticTerrain {
 public:
  /// Windows must lie inside columns and rows [0, kMaxIndex].
  static constexpr int64_t kMaxIndex = (int64_t{1} << 24) - 1;

  /// `spacing` is the distance between samples in metres (positive and finite).
  SyntheticTerrain(uint64_t seed, double spacing);

  uint64_t seed() const { return mSeed; }
  double spacing() const { return mSpacing; }

  /// Heights in metres of columns [column0, column0 + columns) and rows [row0, row0 + rows),
  /// written to `out` row by row, north row first, `columns` values per row. Thread-safe.
  void fillWindow(int64_t column0, int64_t row0, int32_t columns, int32_t rows, float* out) const;

  /// The height of one sample (a 1x1 window; slow, for tests and spot checks).
  float height(int64_t column, int64_t row) const;

 private:
  struct Octaves;

  uint64_t mSeed;
  double mSpacing;
  std::shared_ptr<const Octaves> mOctaves;  // immutable, so copies may share it
};

}  // namespace terralod
