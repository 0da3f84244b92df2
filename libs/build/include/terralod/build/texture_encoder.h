#pragma once
// Turns a chunk's float tiles into stored texture layers: the mip chain (edge-aligned
// resampling, see texel_tile.h) and GPU block compression of every level (BC1 for colour, by
// stb_dxt; BC5 for normals' x and y and BC4 for one channel, by alpha_block.h's encoder, which
// gives stb_dxt's bytes faster).

#include <array>
#include <vector>

#include "terralod/build/texel_tile.h"
#include "terralod/format/texture_codec.h"

namespace terralod {

/// `tile` holds RGB in [0, 1] (3 channels). A non-empty `level0` is taken as the encoded mip 0
/// (see mosaicBlocks) instead of encoding it again.
TextureLayer encodeColorLayer(const TexelTile& tile, uint8_t flags,
                              std::vector<uint8_t> level0 = {});
/// `tile` holds normal vectors (3 channels, any length; normalised here).
TextureLayer encodeNormalLayer(const TexelTile& tile, uint8_t flags,
                               std::vector<uint8_t> level0 = {});

/// The mip level of `size` texels below `above` (mipTile; the 1x1 level is the mean).
TexelTile nextMip(const TexelTile& above, uint32_t size);
/// One level's blocks: BC1 of RGB in [0, 1], or BC5 of normals' x and y (normalised here).
std::vector<uint8_t> encodeLevel(const TexelTile& level, TextureEncoding encoding);

/// The encoded level of a parent that is its four children's levels of `childSize` texels
/// side by side (2 childSize, nothing shared): their blocks, when childSize is a multiple of
/// 4 and every child exists (empty otherwise).
std::vector<uint8_t> concatBlocks(const std::array<const std::vector<uint8_t>*, 4>& children,
                                  uint32_t childSize, TextureEncoding encoding);

/// The encoded mip 0 of a parent whose tile is exactly its four children's side by side
/// (a mosaic of 2n - 1 texels, not resampled), from the children's encoded mip 0: when
/// (n - 1) is a multiple of 4 every parent block is one of the children's blocks, so the
/// result equals encoding the mosaic. Empty when that does not hold or a child is missing.
std::vector<uint8_t> mosaicBlocks(const std::array<const std::vector<uint8_t>*, 4>& children,
                                  uint32_t childSize, TextureEncoding encoding);

}  // namespace terralod
