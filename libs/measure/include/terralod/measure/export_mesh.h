#pragma once
// The surface of one level of a tileset as one welded triangle mesh, for `terralod export`.

#include <array>
#include <cstdint>
#include <vector>

#include "terralod/core/progress.h"
#include "terralod/format/tileset_reader.h"

namespace terralod {

/// Every chunk of a level, unmorphed and without skirts, in world coordinates.
struct LevelSurface {
  /// World metres, x east, y north, z up, relative to the tileset's south-west sample (so
  /// float32 keeps a few centimetres over a few hundred kilometres).
  std::vector<std::array<float, 3>> positions;
  std::vector<uint32_t> indices;  ///< triangle list, counter-clockwise seen from above
  /// Unit vertex normals (same axes), each the angle-weighted mean of its triangles' normals.
  std::vector<std::array<float, 3>> normals;
  /// Texture coordinates: u = x / width, v = y / height of the data's extent (0..1, v north,
  /// as OBJ and PLY count it; glTF's v runs the other way, its writer flips it). The colour
  /// texture `terralod export` writes covers exactly that extent.
  std::vector<std::array<float, 2>> texcoords;
  std::array<double, 2> extent{};  ///< metres east and north from the south-west sample
  uint64_t chunks = 0;
  uint64_t weldedVertices = 0;     ///< chunk vertices merged with another at the same grid point
  uint64_t heightMismatches = 0;   ///< welded vertices whose heights differed (first one kept)
  double maxHeightDifference = 0;  ///< metres, over all welded vertices
};

/// Reads and decodes every chunk of `level` (which must be < levelCount) and welds vertices at
/// the same grid point into one, then computes normals and texture coordinates. Fails on the
/// first unreadable chunk, naming it.
Result<LevelSurface> gatherLevelSurface(const TilesetReader& tileset, uint32_t level,
                                        Progress& progress);

/// Fills `surface`'s normals, extent and texture coordinates from its positions and indices.
void finishSurface(const TilesetHeader& header, LevelSurface& surface);

/// A VIPM tileset's surface (docs/format.md "VIPM tilesets") with every leaf at the level the
/// VIPM kind draws for an allowed error `error` (metres) without geomorphing: its collapses of
/// error <= `error` applied (morphWindow). Vertices at the same grid point are welded (a leaf's
/// border may keep points its neighbour collapsed: T-junctions, as drawn). Fails on the first
/// unreadable chunk.
Result<LevelSurface> gatherVipmSurface(const TilesetReader& tileset, double error,
                                       Progress& progress);

/// Angle-weighted vertex normals of a triangle mesh whose triangles are counter-clockwise seen
/// from +z: every vertex gets the sum of its triangles' unit normals, each weighted by the
/// triangle's angle at that vertex, normalised (so the triangulation's shape, not its triangles'
/// sizes, decides). A vertex of degenerate triangles only gets (0, 0, 1).
std::vector<std::array<float, 3>> angleWeightedNormals(
    const std::vector<std::array<float, 3>>& positions, const std::vector<uint32_t>& indices);

}  // namespace terralod
