#pragma once
// The tileset.json of a 3D Tiles 1.1 export (issue 24): the chunk tree as an explicit tree of
// tiles, one per chunk, each with its chunk's glTF as content, refinement REPLACE, and as
// geometricError the chunk's δ(L): Cesium's screen-space error δ·H / (2·D·tan(fovy/2)) is
// chunked LOD's ρ = δ·K/D with K from the height, so a viewer's maximumScreenSpaceError plays
// the part of τ. Content positions are in the root frame (z up, metres; the root tile's
// transform takes them to Earth-centred coordinates), and each tile's box is its content's
// axis-aligned bounds there. Tilesets with several roots get a tile above them without content.
// Pure: no files.

#include <array>
#include <cstdint>
#include <span>
#include <string>

#include <glm/mat4x4.hpp>
#include <nlohmann/json.hpp>

#include "terralod/core/result.h"

namespace terralod::tiles3d {

inline constexpr uint32_t kNoParent = 0xffffffffu;

/// One chunk as exported. Tiles are listed parents first.
struct ExportTile {
  uint32_t parent = kNoParent;         ///< index into the list, or kNoParent for a root
  double geometricError = 0;           ///< metres: the chunk's δ(L)
  std::array<double, 3> min{}, max{};  ///< its content's bounds in the root frame, metres
  std::string contentUri;              ///< relative to tileset.json; empty: no content
};

/// The whole tileset.json. `rootFrame` maps root-frame metres to ECEF (column-major, as 3D
/// Tiles' `transform`); `tilesetError` is the top-level geometricError (the error of drawing
/// nothing); `extras` goes into the tileset's "extras" (what made it). Fails when a parent is
/// listed after its child, a box is empty or inverted, or a child's error exceeds its parent's.
Result<nlohmann::json> tilesetJson(std::span<const ExportTile> tiles, const glm::dmat4& rootFrame,
                                   double tilesetError, const nlohmann::json& extras = {});

/// A 3D Tiles box (centre, then the three half-axes) for axis-aligned bounds.
std::array<double, 12> boxOf(const std::array<double, 3>& min, const std::array<double, 3>& max);

}  // namespace terralod::tiles3d
