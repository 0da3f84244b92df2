#pragma once
// A parent's level 0 made from its children's as they come: resampleTile(mosaicTiles(...))
// without the mosaic. A resampled parent never holds its children together: each child is used
// once, as it is added: the parent texels whose filter reaches that child alone are finished at
// once, and the few rows and columns of sums across the seams between children are kept until the
// last child is in. The same products are added in the same order as resampleTile adds them, so
// the floats are the same. An unresampled parent (the mosaic itself) keeps the children it is
// given and joins their rows once, at the end.
//
// Children exist from the south-west (a missing child lies east or north of a present one:
// {SW}, {SW, SE}, {SW, NW} or all four), as in every tree TreeLayout makes.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/build/texel_tile.h"

namespace terralod {

class MosaicBuilder {
 public:
  /// Children of `childSize` texels and `channels` channels, those marked in `present`
  /// (quadrants SW, SE, NW, NE), making a tile of `size` texels.
  MosaicBuilder(uint32_t childSize, uint32_t channels, uint32_t size, std::array<bool, 4> present);

  /// Uses child `quadrant`'s tile. Children may be added in any order, and concurrently
  /// (each writes its own texels).
  void add(size_t quadrant, const TexelTile& child);
  /// The same, taking the tile: a parent that holds its children unresampled (size 2 childSize
  /// - 1) keeps them and joins their rows in finish(), never filling a mosaic with zeros first
  /// (those mosaics are most of a textured build's new memory). A copy, for the const overload.
  void add(size_t quadrant, TexelTile&& child);
  /// The parent's tile, once every present child has been added.
  TexelTile finish();

 private:
  enum : uint8_t { kSouthOrWest = 0, kNorthOrEast = 1, kMixed = 2 };
  uint8_t rowOwner(uint32_t r) const;  // which half's child holds mosaic row r
  uint8_t colOwner(uint32_t k) const;
  uint8_t ownerOfTaps(uint32_t first, size_t count, bool rows) const;

  TexelTile joinKept();  // the unresampled mosaic of mKept

  uint32_t mChild, mChannels, mSize, mSource;  // mSource: the mosaic's side
  std::array<bool, 4> mPresent;
  TexelTile mOut;                             // resampled parents: written as children come
  std::array<TexelTile, 4> mKept;             // unresampled parents: the children, until finish()
  std::vector<uint8_t> mRowClass, mColClass;  // per output row / column: its taps' owner
  uint32_t mBandRow0 = 0, mBandRows = 0;      // mosaic rows the mixed output rows reach
  std::vector<float> mBandRowValues;          // those rows, whole
  uint32_t mBandCol0 = 0, mBandCols = 0;      // columns of sums the mixed output columns reach
  std::vector<float> mBandColSums;            // per output row: those sums
};

}  // namespace terralod
