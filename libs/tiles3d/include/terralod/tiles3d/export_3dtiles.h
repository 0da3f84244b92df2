#pragma once
// `terralod export TILESET --format 3dtiles -o DIR` (issue 24): a tileset as a 3D Tiles 1.1
// tileset, one glTF per chunk (chunk_glb.h; local_chunk.h: static chunks with their skirts and
// colour tile as JPEG, VIPM nodes at their finest with flanges and material colours), an
// explicit tree in DIR/tileset.json (tileset_json.h) or, for large trees, implicit quadtree
// tiling with subtree files (implicit_tiling.h), placed on Earth through the source's
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
#include "terralod/tiles3d/earth_camera.h"

namespace terralod::tiles3d {

/// How tileset.json describes the tree: every tile (explicit), or a root tile and subtree files
/// (implicit quadtree tiling); auto: implicit from kImplicitFromTiles tiles on, where the tree
/// allows it (δ halving per level; VIPM tilesets are not exported).
enum class Tiling : uint8_t { kAuto, kExplicit, kImplicit };

/// Auto tiling's threshold: an explicit tileset.json of this many tiles is about 2 MB, which a
/// client reads before it draws anything.
inline constexpr uint64_t kImplicitFromTiles = 4096;

struct Export3dTilesOptions {
  Tiling tiling = Tiling::kAuto;
};

struct ExportSummary {
  Tiling tiling = Tiling::kExplicit;  ///< what was written (never kAuto)
  uint64_t tiles = 0, bytes = 0;      ///< glTF files and their bytes (tileset.json excluded)
  uint64_t subtrees = 0;              ///< implicit tiling's subtree files
  /// Implicit tiling: how far any tile's content reaches outside the box implicit tiling gives
  /// it (metres; the projection's and the Earth's curvature over the tile: a metre or two).
  double implicitBoxExcess = 0;
  uint64_t uncompressedBytes = 0;   ///< the glTFs' vertex and index data before meshopt
  double maxQuantisationError = 0;  ///< metres, over every position
  bool placed = true;               ///< false: the default placement (no georeferencing)
};

/// `warn` gets one line when the tileset has no place on Earth. Fails, writing nothing, when
/// implicit tiling is asked for a tree that does not allow it.
Result<ExportSummary> export3dTiles(const TilesetReader& tileset, const std::string& dir,
                                    const Export3dTilesOptions& options, Progress& progress,
                                    const std::function<void(const std::string&)>& warn);

}  // namespace terralod::tiles3d
