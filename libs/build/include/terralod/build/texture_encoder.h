#pragma once
// Turns a chunk's float tiles into stored texture layers: the mip chain (edge-aligned
// resampling, see texel_tile.h) and GPU block compression of every level (stb_dxt: BC1 for
// colour, BC5 for normals' x and y).

#include "terralod/build/texel_tile.h"
#include "terralod/format/texture_codec.h"

namespace terralod {

/// `tile` holds RGB in [0, 1] (3 channels).
TextureLayer encodeColorLayer(const TexelTile& tile, uint8_t flags);
/// `tile` holds normal vectors (3 channels, any length; normalised here).
TextureLayer encodeNormalLayer(const TexelTile& tile, uint8_t flags);

}  // namespace terralod
