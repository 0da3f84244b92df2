#pragma once
// `terralod export TILESET --format 3dtiles -o DIR` (issue 24): a static tileset as a 3D Tiles
// 1.1 tileset, one glTF per chunk (chunk_glb.h, skirts included, its colour tile as JPEG), an
// explicit tree in DIR/tileset.json (tileset_json.h), placed on Earth through the source's
// georeferencing (earth_placement.h): every vertex goes through PROJ to Earth-centred
// coordinates, then into the root frame (the frame at the data's centre), so the content is
// exact to its quantisation wherever the tileset lies. One chunk is held at a time.
//
// Written into DIR.partial and renamed to DIR when complete: a killed export leaves no DIR
// (and no tileset.json). DIR must not exist, or be an empty directory.

#include <functional>
#include <string>

#include "terralod/core/progress.h"
#include "terralod/core/result.h"
#include "terralod/format/tileset_reader.h"

namespace terralod::tiles3d {

/// Where tilesets without a place are put (a tangent plane; documented in README): longitude
/// and latitude in degrees.
inline constexpr double kDefaultLongitude = 0.0, kDefaultLatitude = 0.0;

struct ExportSummary {
  uint64_t tiles = 0, bytes = 0;    ///< glTF files and their bytes (tileset.json excluded)
  uint64_t uncompressedBytes = 0;   ///< the glTFs' vertex and index data before meshopt
  double maxQuantisationError = 0;  ///< metres, over every position
  bool placed = true;               ///< false: the default placement (no georeferencing)
};

/// `warn` gets one line when the tileset has no place on Earth.
Result<ExportSummary> export3dTiles(const TilesetReader& tileset, const std::string& dir,
                                    Progress& progress,
                                    const std::function<void(const std::string&)>& warn);

}  // namespace terralod::tiles3d
