#pragma once
// The surface of one level of a tileset as one welded triangle mesh, for `terralod export`.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/core/progress.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::cli {

/// Every chunk of a level, unmorphed and without skirts, in world coordinates.
struct LevelSurface {
  /// World metres, x east, y north, z up, relative to the tileset's south-west sample (so
  /// float32 keeps a few centimetres over a few hundred kilometres).
  std::vector<std::array<float, 3>> positions;
  std::vector<uint32_t> indices;  ///< triangle list, counter-clockwise seen from above
  uint64_t chunks = 0;
  uint64_t weldedVertices = 0;     ///< chunk vertices merged with another at the same grid point
  uint64_t heightMismatches = 0;   ///< welded vertices whose heights differed (first one kept)
  double maxHeightDifference = 0;  ///< metres, over all welded vertices
};

/// Reads and decodes every chunk of `level` (which must be < levelCount) and welds vertices at
/// the same grid point into one. Fails on the first unreadable chunk, naming it.
Result<LevelSurface> gatherLevelSurface(const TilesetReader& tileset, uint32_t level,
                                        Progress& progress);

}  // namespace terralod::cli
