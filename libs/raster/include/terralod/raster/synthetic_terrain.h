#pragma once
// A synthetic elevation model for benchmarks and tests: mountains, hills and flats in metres,
// defined on an unbounded grid so that any window can be generated on its own, exactly.
//
// Grid convention: this class works in raster order, like the GeoTIFF it feeds. Column c grows
// eastwards and row r southwards (row 0 is the northern edge); windows come back north row
// first. terralod's grid rows are the other way round (gy = rows - 1 - r), so a caller that
// wants grid order flips the rows. Sample (c, r) sits c * spacing metres east and r * spacing
// metres south of the north-west corner, so a larger raster extends a smaller one (same seed
// and spacing) to the east and south and they agree on every sample they share.
//
// The terrain, in world metres (so it looks the same at any raster size):
//  - a gentle domain warp (about 700 m at 6 km wavelength) bends every large-scale feature;
//  - a "continent" mask (fBm with a 14 km wavelength) chooses flats where it is low, rolling
//    hills in between and mountains where it is high; the plains' base level follows it;
//  - mountains are a ridged multifractal (Musgrave: each octave is (1 - |noise|)^2 weighted by
//    the previous one, so ridges are sharp and rough while valleys stay smooth), with ridges a
//    few km apart and up to ~1.2 km of relief, cut by V-shaped valleys along the zero lines of
//    a warped 8 km noise;
//  - hills are plain fBm from the same octaves; the octaves continue down to twice the cell
//    size, so a 1 m raster is rough where a real one would be.
//
// The height is a pure function of (column, row, seed, spacing). Everything with a wavelength
// of at least 128 cells (the mask, warp, valleys and the coarse octaves) is evaluated on a
// global lattice every 8 cells and interpolated with Catmull-Rom cubics; the finer octaves are
// evaluated per sample, in 256-column chunks anchored at multiples of 256. Both are part of the
// definition, and neither depends on the window, thread or order of evaluation. Only basic
// IEEE arithmetic is used (no libm), so with -ffp-contract=off every run gives the same bits.

#include <cstdint>
#include <vector>

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

  /// The height of one sample (a 1x1 window).
  float height(int64_t column, int64_t row) const;

 private:
  // An octave evaluated on the lattice, in double precision, after the warp and a rotation.
  struct CoarseOctave {
    double frequency;  // cycles per metre
    double cosine, sine;
    double offsetX, offsetY;
    double crease;  // how much |noise| is rounded, in noise units
    double mountainAmplitude, hillAmplitude;
    uint32_t hashSeed;
    bool ridged;
  };
  // An octave evaluated per sample, unwarped, so that along a row its lattice coordinates are
  // affine functions of the column: (u, v) = column * (columnU, columnV) + row * (rowU, rowV)
  // + offset, in noise lattice units.
  struct FineOctave {
    double columnU, rowU, columnV, rowV;
    double offsetX, offsetY;
    float crease;
    float mountainAmplitude, hillAmplitude;
    uint32_t hashSeed;
    bool ridged;
  };
  struct LatticeSample;
  struct Chunk;

  LatticeSample latticeSample(int64_t latticeRow, int64_t latticeColumn) const;
  void fillChunkRow(int64_t anchor, int64_t row, Chunk& chunk) const;
  template <bool kRidged>
  static void addFineOctave(const FineOctave& octave, int64_t anchor, int64_t row, Chunk& chunk);

  uint64_t mSeed;
  double mSpacing;
  uint32_t mWarpSeedX, mWarpSeedY, mMaskSeed, mValleySeed;
  std::vector<CoarseOctave> mCoarse;
  std::vector<FineOctave> mFine;
};

}  // namespace terralod
