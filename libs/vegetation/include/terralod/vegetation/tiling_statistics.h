#pragma once
// How random a tiling looks: statistics and pictures behind papers/tiling-layered-depth-images.md
// §2 (Figure 4: our 8 stochastic Wang tiles give a tiling that "looks similar to white noise",
// Robinson's 16 aperiodic tiles "a marked plaid-like structure with strong horizontal and
// vertical features") and §7 (local clumps of tiles from one prototile).
//
// Statistics look at prototile indices only, never at edges:
// - `neighbourStats`: how often adjacent tiles are the same prototile, against 1/count (what an
//   independent uniform choice gives), and how large same-prototile clumps grow (§7).
// - `autocorrelation`: for every lag (dx, dy) in [−L, L]², (P_same − 1/n)/(1 − 1/n), where
//   P_same is the fraction of tile pairs at that lag with one prototile and n the number of
//   prototiles: 1 at the origin (and everywhere for a constant tiling), about 0 for independent
//   tiles, −1 where a two-colour checkerboard always differs. The plaid signature is a large
//   mean |value| along the axes (dx = 0 or dy = 0) against the rest.
//
// Our tiling in these terms (wang_tiling.h): a tile is (west, south, north) = (n(x−1,y−1) ^
// n(x−1,y), n(x,y−1), n(x,y)) of independent fair bits n (its own choice and those of its
// south, west and south-west neighbours), so tiles two or more apart (Chebyshev) are
// independent, and for every lag one apart P_same is exactly 1/8 too: a tile and its neighbour
// share some bits, but the prototile pair is still the same with probability 1/8 (east: the
// neighbour's west colour is our east colour, which is as likely to match our own west colour
// as not; north: our north colour must equal our south colour and the neighbour's north colour;
// diagonals likewise). So the expected autocorrelation is 0 at every lag but the origin; what
// a finite tiling shows off the origin is sampling noise (on 256 × 256 tiles, seed 1: mean
// |value| 0.0015, the largest of the 1088 lags up to 16 apart 0.0055).
//
// Same-prototile repeats are as frequent as chance, but concentrated (§7's clumps): only the 4
// prototiles with west = east can repeat eastwards, each with probability 1/4 (the east
// neighbour's south and north colours must match too), and only the 4 with south = north
// northwards; prototiles 0 and 3 (each able to tile the plane alone) can do both. So fewer
// tiles have a neighbour of their own prototile than under independent choice (399/1024 =
// 0.390 against 1 − (7/8)^4 = 0.414) but clumps grow larger (on 10^4 × 10^4 tiles the mean
// clump a tile is in is 1.89 tiles against 1.75, the largest 39 against 20).
//
// The comparison tiling is *not* Robinson's tile set: `hierarchicalTiling` gives each tile a
// type from the 2-adic structure of its coordinates, the way Robinson tilings nest their
// squares (crosses where x+1 and y+1 have equally many trailing zero bits, arms along the lines
// between them). It has Robinson-style hierarchical structure and 16 tile types, but no edge
// colours and no matching rules; it stands in for Figure 4(c, d) in statistics and pictures.
// (The paper's "Robinson's set of 16" is probably the 16 Wang tiles usually credited to Ammann,
// whose tilings have Fibonacci-spaced rows and columns; Robinson's own 1971 set has 6 tiles up
// to rotation and reflection. Neither is implemented here.)

#include <cstdint>
#include <vector>

#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {

/// A tiling as prototile indices 0..prototileCount−1, one byte per tile, row-major from the
/// south row (like LaidTiling).
struct TileGrid {
  uint32_t width = 0, height = 0;
  int prototileCount = 0;  ///< 1..256; the chance level of the statistics is 1/prototileCount
  std::vector<uint8_t> prototiles;
  int at(uint32_t x, uint32_t y) const { return prototiles[size_t(y) * width + x]; }
};

/// A grid of `prototileAt(x, y)` for 0 ≤ x < width, 0 ≤ y < height.
template <typename PrototileAt>
TileGrid sampleGrid(uint32_t width, uint32_t height, int prototileCount,
                    PrototileAt&& prototileAt) {
  TileGrid grid{width, height, prototileCount, std::vector<uint8_t>(size_t(width) * height)};
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x)
      grid.prototiles[size_t(y) * width + x] = uint8_t(prototileAt(x, y));
  return grid;
}

TileGrid toGrid(const LaidTiling& tiling);  ///< kWangPrototiles prototiles
TileGrid toGrid(const WangTiling& tiling);  ///< every tile looked up with `at`

/// Independent uniform prototiles (not a valid Wang tiling): the reference "chance" tiling.
TileGrid independentTiling(uint32_t width, uint32_t height, int prototileCount, uint64_t seed);

inline constexpr int kHierarchicalTileTypes = 16;

/// The type of tile (i − 1, j − 1) of the Robinson-style hierarchical structure (see the top of
/// this file), from a = trailing zeros of i and b = trailing zeros of j (i, j ≥ 1):
/// - a = b: a cross of level a, facing the cross of level a+1 that its group of four surrounds
///   (east when bit a+1 of i is 0, north when bit a+1 of j is 0). Type 4·(a mod 2) + east +
///   2·north.
/// - a > b: an arm on the vertical line through the level-a crosses of column i, pointing away
///   from the nearer of them (north when bit a of j is 1); b > a: an arm on the horizontal line
///   of row j likewise (east when bit b of i is 1). Type 8 + 4·horizontal + 2·forwards + (line
///   level mod 2).
/// Levels count mod 2, so an arm has one type all along each half of its line: long
/// horizontal and vertical features; the crosses repeat with period 4 at level 0, 8 at level 1,
/// and so on.
int hierarchicalTileType(uint64_t i, uint64_t j);

/// Tiles (x, y) of the hierarchical structure shifted by an offset drawn from `seed` (seed 0:
/// no shift, tile (x, y) has type hierarchicalTileType(x + 1, y + 1)).
TileGrid hierarchicalTiling(uint32_t width, uint32_t height, uint64_t seed);

struct NeighbourStats {
  double sameEast = 0;            ///< fraction of (x, y), (x+1, y) pairs of one prototile
  double sameNorth = 0;           ///< fraction of (x, y), (x, y+1) pairs of one prototile
  double sameEitherExpected = 0;  ///< 1/prototileCount: what an independent uniform choice gives
  double withSameNeighbour = 0;   ///< fraction of tiles with a 4-neighbour of their prototile
  /// What independent uniform choice gives for `withSameNeighbour`: the mean over tiles of
  /// 1 − (1 − 1/n)^(number of neighbours).
  double withSameNeighbourExpected = 0;
  uint64_t largestClump = 0;  ///< tiles in the largest 4-connected region of one prototile
  double meanClump = 0;       ///< mean over tiles of the size of the region the tile is in
};

NeighbourStats neighbourStats(const TileGrid& grid);

struct Autocorrelation {
  int maxLag = 0;  ///< L
  /// (2L+1)² values, row dy = −L..L, column dx = −L..L: value(dx, dy) = values[(dy + L) ·
  /// (2L + 1) + dx + L]. Symmetric: value(−dx, −dy) = value(dx, dy).
  std::vector<double> values;
  double maxAbsOffOrigin = 0;  ///< max |value| over lags ≠ (0, 0)
  double meanAbsOnAxes = 0;    ///< mean |value| over dx = 0 or dy = 0, origin excluded
  double meanAbsOffAxes = 0;   ///< mean |value| over dx ≠ 0 and dy ≠ 0

  double at(int dx, int dy) const {
    return values[size_t(dy + maxLag) * (2 * maxLag + 1) + dx + maxLag];
  }
  /// max |value| over lags with max(|dx|, |dy|) ≥ lag.
  double maxAbsFromLag(int lag) const;
};

/// The normalised same-prototile autocorrelation (top of this file) for lags up to `maxLag`
/// (< width and < height) each way, over all tile pairs inside the grid at each lag.
Autocorrelation autocorrelation(const TileGrid& grid, int maxLag);

/// 8-bit RGB, row-major from the top row, 3 bytes a pixel.
struct RgbImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;
  const uint8_t* pixel(int x, int y) const { return &rgb[(size_t(y) * width + x) * 3]; }
};

/// One colour per prototile (16 distinguishable colours; prototileCount ≤ 16), each tile a
/// square of `pixelsPerTile` pixels, north up (the grid's last row at the top).
RgbImage renderTiling(const TileGrid& grid, int pixelsPerTile);

/// A diverging heat map of an autocorrelation, `pixelsPerLag` pixels a lag, dy > 0 up: blue
/// for −scale, white for 0, red for +scale (clamped beyond).
RgbImage renderAutocorrelation(const Autocorrelation& autocorrelation, int pixelsPerLag,
                               double scale);

struct TilingFigureOptions {
  uint64_t seed = 1;  ///< of our tiling (the comparison uses it for its offset)
  uint32_t smallTiles = 32, largeTiles = 256;
  int smallPixelsPerTile = 8, largePixelsPerTile = 1;
  int maxLag = 16;  ///< of the autocorrelations, measured on the large tilings
  int pixelsPerLag = 8;
  int gap = 8;
  double heatScale = 0;  ///< 0: the larger maxAbsOffOrigin of the two, one scale for both maps
};

struct TilingFigure {
  RgbImage image;
  Autocorrelation ours, comparison;  ///< of the large tilings
  double heatScale = 0;              ///< the scale both heat maps use
};

/// Figure 4 of the paper and our measurement of it. Top row, left to right with gaps: our
/// tiling small and large (Figure 4 a, b), the Robinson-style hierarchical comparison small and
/// large (in place of c, d). Below each pair, centred: the autocorrelation of its large tiling.
TilingFigure tilingFigure(const TilingFigureOptions& options = {});

}  // namespace terralod::veg
