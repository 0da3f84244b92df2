#pragma once
// Square tiles of float texels while a chunk's texture is built, and the two resampling steps
// of the texture quadtree. Placement is edge-aligned: texel i of n lies at i / (n - 1) of the
// side, so a tile's outermost rows and columns lie on the chunk's border.
//
// Resampling keeps borders shared: a border row (or column) of the result is computed from
// the source's border row alone. Two neighbouring chunks whose border texels agree therefore
// still agree after any resampling (mips, parents): no seams, at any level, at any mip.

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace terralod {

struct TexelTile {
  uint32_t size = 0;      ///< texels per side
  uint32_t channels = 0;  ///< interleaved
  std::vector<float> values;

  TexelTile() = default;
  TexelTile(uint32_t side, uint32_t channelCount)
      : size(side), channels(channelCount), values(size_t(side) * side * channelCount, 0.0f) {}
  float* at(uint32_t x, uint32_t y) { return values.data() + (size_t(y) * size + x) * channels; }
  const float* at(uint32_t x, uint32_t y) const {
    return values.data() + (size_t(y) * size + x) * channels;
  }
};

/// The unit normal of a surface of slopes dx, dy (height per metre along x and y):
/// (-dx, -dy, 1) normalised.
inline void normalFromSlopes(float dx, float dy, float* n) {
  const float inv = 1.0f / std::sqrt(dx * dx + dy * dy + 1.0f);
  n[0] = -dx * inv;
  n[1] = -dy * inv;
  n[2] = inv;
}

/// Unit normals (x, y, z) by central differences, one texel per grid point of the `cells`-cell
/// square whose south-west grid point is (x0, y0); `height(gx, gy)` gives the heights one
/// point beyond the square too (clamped at the data's edge). Static tilesets' normal layers
/// (BlockTexels) and VIPM tilesets' normal maps are made by it.
template <typename Height>
TexelTile centralDifferenceNormals(int32_t x0, int32_t y0, int32_t cells, double spacingX,
                                   double spacingY, Height&& height) {
  TexelTile tile(uint32_t(cells + 1), 3);
  const float ix = float(0.5 / spacingX), iy = float(0.5 / spacingY);
  for (int32_t j = 0; j <= cells; ++j)
    for (int32_t i = 0; i <= cells; ++i) {
      const int32_t gx = x0 + i, gy = y0 + j;
      const float dx = (height(gx + 1, gy) - height(gx - 1, gy)) * ix;
      const float dy = (height(gx, gy + 1) - height(gx, gy - 1)) * iy;
      normalFromSlopes(dx, dy, tile.at(uint32_t(i), uint32_t(j)));
    }
  return tile;
}

/// Where resampled texels go: edge-aligned (texel k at k / (size - 1) of the side: tiles,
/// parents), or where the GPU samples mip level texels (texel k at (k + 0.5) * from / size -
/// 0.5 source texels, the borders excepted, which stay on the border).
enum class Placement : uint8_t { kEdgeAligned, kMipLevel };

/// `source` resampled to `size` texels per side: a tent filter as wide as the step (so
/// downsampling averages, upsampling interpolates), tilted so that linear functions come out
/// exact; borders from borders only.
TexelTile resampleTile(const TexelTile& source, uint32_t size,
                       Placement placement = Placement::kEdgeAligned);
/// The same, reusing `source`'s storage when the size does not change.
TexelTile resampleTile(TexelTile&& source, uint32_t size);

/// The next mip level (`size` = the level above's size / 2, at least 2) of a tile whose level 0
/// is edge-aligned. The GPU samples mip level m of a tile of n texels at texel coordinate
/// (0.5 + f (n - 1)) n_m / n - 0.5 for the fraction f across the chunk: the interior texels
/// are put exactly there, so every level shows the same surface in the same place (a parent
/// and its children agree at every mip). Border texels stay on the border (border-only
/// filtering), so neighbours still agree at their shared border.
TexelTile mipTile(const TexelTile& above, uint32_t size);

/// The four children's tiles (SW, SE, NW, NE; nullptr where a child does not exist) side by
/// side as one tile of 2n - 1 texels (neighbours share their border texels). A missing
/// child's quadrant repeats the nearest existing texels. At least one child must exist, and
/// the existing ones must have the same size and channels.
TexelTile mosaicTiles(const std::array<const TexelTile*, 4>& children);

/// The four children's tiles side by side without sharing (2n texels per side): how the mip
/// levels of a parent (2^k texels, no border column of their own) are their children's.
/// Missing children repeat the nearest existing texels, as in mosaicTiles.
TexelTile concatTiles(const std::array<const TexelTile*, 4>& children);

}  // namespace terralod
