#pragma once
// The colour texels a chunk draws, decoded on the CPU for tools that need pixels (`terralod
// export`'s texture, 3D Tiles' JPEGs): its own colour tile, or for a chunk that inherits its
// texture (kNodeInheritsTexture) its square of the nearest textured ancestor's tile.

#include <cstdint>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {

struct NodeColour {
  std::vector<uint8_t> rgb;  ///< RGB8, size x size, row 0 the southern one; empty: no colour
  uint32_t size = 0;         ///< texels a side (edge-aligned over the chunk's square)
};

/// Level 0 of the colour a node draws. An untextured tileset gives an empty NodeColour; a
/// colour layer that is not BC1 or does not decode is an error naming the chunk that holds it.
Result<NodeColour> readNodeColour(const TilesetReader& tileset, uint32_t node);

}  // namespace terralod
