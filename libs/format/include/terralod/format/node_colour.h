#pragma once
// The colour texels a chunk draws, decoded on the CPU for tools that need pixels (`terralod
// export`'s texture, 3D Tiles' JPEGs): its own colour tile, or for a chunk that inherits its
// texture (kNodeInheritsTexture) its square of the nearest textured ancestor's tile.

#include <cstdint>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {

struct NodeColour {
  std::vector<uint8_t> rgb;  ///< RGB8, size x size, row 0 the southern one; empty: no colour
  uint32_t size = 0;         ///< texels a side (edge-aligned over the chunk's square)
};

/// Reads the colour chunks draw, keeping the last few owners' decoded tiles: the chunks that
/// share one ancestor's texture come one after another in node order, and decoding a 2049²
/// tile for each of them would cost more than the rest of an export. Thread-safe.
class NodeColours {
 public:
  explicit NodeColours(const TilesetReader& tileset) : mTileset(tileset) {}

  /// Level 0 of the colour `node` draws. An untextured tileset gives an empty NodeColour; a
  /// colour layer that is not BC1 or does not decode is an error naming the chunk holding it.
  Result<NodeColour> read(uint32_t node);

 private:
  Result<std::shared_ptr<const NodeColour>> owned(uint32_t owner);

  static constexpr size_t kKept = 4;  ///< decoded owner tiles kept (a 2049² one is 12 MB)
  const TilesetReader& mTileset;
  std::mutex mMutex;
  std::vector<std::pair<uint32_t, std::shared_ptr<const NodeColour>>> mKept;  // newest last
};

/// NodeColours(tileset).read(node), for one chunk.
Result<NodeColour> readNodeColour(const TilesetReader& tileset, uint32_t node);

/// The texels a side of the colour `node` draws (NodeColour::size) without decoding it; 0 when
/// it has none.
Result<uint32_t> nodeColourSize(const TilesetReader& tileset, uint32_t node);

}  // namespace terralod
