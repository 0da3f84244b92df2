#pragma once
// Where a chunk's vertices are in the world: the arithmetic of docs/format.md in one place, so
// every reader of chunks (verify, export, the runtime) places them identically.

#include <array>
#include <cstdint>

#include "terralod/format/chunk_codec.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

/// Grid cell of a chunk's south-west corner: (node.x, node.y) * chunkCells(node.level).
inline std::array<int64_t, 2> chunkCellOrigin(const TilesetHeader& header, const NodeRecord& node) {
  const int64_t side = header.chunkCells(node.level);
  return {int64_t(node.x) * side, int64_t(node.y) * side};
}

/// Height in metres of a chunk vertex at morph parameter t (0: its own surface, 1: the
/// parent's).
inline double chunkVertexHeight(const ChunkGeometry& geometry, const ChunkVertex& v,
                                double t = 0.0) {
  return geometry.zBase + (double(v.z) + t * v.morphDelta) * geometry.zStep;
}

/// World position in metres (x east, y north, z up; the origin is the tileset's south-west
/// sample) of a vertex of `node`'s chunk at morph parameter t.
inline std::array<double, 3> chunkWorldPosition(const TilesetHeader& header, const NodeRecord& node,
                                                const ChunkGeometry& geometry, const ChunkVertex& v,
                                                double t = 0.0) {
  const auto [x0, y0] = chunkCellOrigin(header, node);
  return {double(x0 + v.x) * header.spacingX, double(y0 + v.y) * header.spacingY,
          chunkVertexHeight(geometry, v, t)};
}

}  // namespace terralod
