#pragma once
// Implicit quadtree tiling (3D Tiles 1.1) for a large chunk tree (issue 24): tileset.json holds
// one root tile with an `implicitTiling` object instead of every tile, and the tree's shape
// goes into subtree files, each covering `subtreeLevels` levels below its root tile as
// bitstreams (docs/format.md "3D Tiles export"). Chunked LOD fits implicit tiling exactly: a
// chunk's four children split its square in half along x and y, and δ(L) halves per level as
// geometricError must. Pure: bytes and JSON out.
//
// Coordinates are implicit ones: level 0 is the implicit root; x counts along the root box's
// first axis (east), y along its second (north), both from 0 at its south-west corner.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "terralod/core/result.h"

namespace terralod::tiles3d {

struct TileKey {
  uint32_t level = 0, x = 0, y = 0;
  friend bool operator==(const TileKey&, const TileKey&) = default;
};

/// Quadtree Morton index: the bits of x and y interleaved, x in the lower bit of each pair.
uint64_t mortonIndex(uint32_t x, uint32_t y);

struct SubtreeFile {
  TileKey root;                ///< the subtree's root tile (its level a multiple of subtreeLevels)
  std::string uri;             ///< "subtrees/{level}/{x}/{y}.subtree"
  std::vector<uint8_t> bytes;  ///< the binary subtree file
};

/// The subtree files of a quadtree whose tiles with content are `content` (each with every
/// ancestor available, without content unless listed). `availableLevels` is the tree's depth.
/// Fails when a tile lies outside its level's grid or below availableLevels, or is listed twice.
Result<std::vector<SubtreeFile>> subtreeFiles(std::span<const TileKey> content,
                                              uint32_t availableLevels, uint32_t subtreeLevels);

/// The implicit root tile: `box` (3D Tiles box: centre, then the x, y and z half-axes, in the
/// root frame), `rootError` its geometricError (halved per level), `rootFrame` its transform.
nlohmann::json implicitRootTile(const std::array<double, 12>& box, double rootError,
                                const glm::dmat4& rootFrame, uint32_t availableLevels,
                                uint32_t subtreeLevels);

/// A tile's box: the root box's x and y half-axes halved `level` times, its centre moved to
/// the tile's square; z as the root's.
std::array<double, 12> implicitTileBox(const std::array<double, 12>& rootBox, const TileKey& key);

}  // namespace terralod::tiles3d
