#pragma once
// Stochastic Wang tilings (papers/tiling-layered-depth-images.md §2): 8 prototiles with two
// colours for north/south edges and two for east/west edges, two prototiles for every
// (west, south) pair, laid row by row from the south-west corner, each tile a random choice
// among those matching the tile to its west and the one to its south.
//
// Random access. Our 8 prototiles are those whose east colour is south XOR north (west and
// south free, north the choice): whichever of the two matching prototiles the scanline picks
// differs in its north colour only, so a tile's north colour *is* its random choice, and its
// south and west colours are its neighbours' north and east colours. Drawing each tile's
// choice from a hash of (seed, x, y) instead of one running random stream, any tile is a
// function of the hashes at (x, y), (x, y−1), (x−1, y) and (x−1, y−1): a tiling is stored as
// its seed and size (16 bytes), and `WangTiling::at` looks up any tile of a terrain-sized
// tiling in constant time without laying the tiles before it. `scanlineTiling` lays the tiles
// one by one exactly as the paper does (choosing among the compatible prototiles it finds)
// and must agree with `at` tile for tile; the tests check that it does.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/vegetation/tile_objects.h"

namespace terralod::veg {

inline constexpr int kWangPrototiles = 8;

/// Prototile k has west = bit 2, south = bit 1, north = bit 0 of k, and east = south ^ north.
TileEdges prototileEdges(int prototile);
const std::array<TileEdges, kWangPrototiles>& prototileSet();

class WangTiling {
 public:
  WangTiling(uint32_t width, uint32_t height, uint64_t seed)
      : mWidth(width), mHeight(height), mSeed(seed) {}

  uint32_t width() const { return mWidth; }
  uint32_t height() const { return mHeight; }
  uint64_t seed() const { return mSeed; }
  /// Prototile of the tile in column x (eastwards), row y (northwards); 0 ≤ x < width.
  int at(uint32_t x, uint32_t y) const;

 private:
  int northOf(uint32_t x, uint32_t y) const;
  int southOf(uint32_t x, uint32_t y) const;
  int eastOf(uint32_t x, uint32_t y) const;

  uint32_t mWidth, mHeight;
  uint64_t mSeed;
};

/// A tiling laid tile by tile (the paper's algorithm), one prototile index per byte, row-major
/// from the south row.
struct LaidTiling {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> prototiles;
  int at(uint32_t x, uint32_t y) const { return prototiles[size_t(y) * width + x]; }
};

/// The scanline algorithm: the first tile any of the 8, the south row matching west edges,
/// every later row matching south edges (and west edges after its first tile). The choice
/// among the matching prototiles (in index order) is the tile's hash modulo their number.
LaidTiling scanlineTiling(uint32_t width, uint32_t height, uint64_t seed);

/// Whether every shared edge of a laid tiling matches (the tiling is valid).
bool tilingIsValid(const LaidTiling& tiling);

/// A valid 3×3 tiling around `prototile` (deterministic for a seed): index k is column k % 3
/// (eastwards), row k / 3 (northwards).
std::array<int, 9> contextAround(int prototile, uint64_t seed);

}  // namespace terralod::veg
