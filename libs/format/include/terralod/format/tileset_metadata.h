#pragma once
// The tileset's metadata JSON (docs/format.md, "Metadata"), parsed and validated once when a
// tileset is opened, as the typed values readers use: how the source was read (for verify),
// and each level's texture tile sizes (for the renderer's mip placement and for export).
// What nobody reads stays in the JSON (`terralod info` prints it whole).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terralod/core/result.h"
#include "terralod/core/source_grid.h"
#include "terralod/core/terrain_edit.h"
#include "terralod/format/tileset_format.h"

namespace terralod {

/// One level's texture tiles (texels a side, 2^k + 1).
struct TextureLevelSizes {
  uint32_t color = 0;
  uint32_t normal = 0;
  friend bool operator==(const TextureLevelSizes&, const TextureLevelSizes&) = default;
};

/// A material of a VIPM tileset ("materials"; its position in the list is the material index
/// the chunk blobs store per vertex).
struct TilesetMaterial {
  uint8_t id = 0;                  ///< the class value as the user knows it
  std::string name;                ///< e.g. "rock"
  std::array<uint8_t, 3> color{};  ///< average colour, sRGB ("#rrggbb" in the JSON)
  friend bool operator==(const TilesetMaterial&, const TilesetMaterial&) = default;
};

/// Materials a VIPM tileset may name (one splatting pass each; blobs store indices < 8).
inline constexpr size_t kMaxTilesetMaterials = 8;

struct TilesetMetadata {
  /// "source": "encoding" as written ("none", "terrain-rgb", "terrarium").
  std::string sourceEncoding = "none";
  /// "source": "file", the source raster's file name (no directory); empty when not recorded.
  std::string sourceFile;
  /// "source": "band", recorded only for multi-band sources.
  std::optional<int> sourceBand;
  /// "source": "crs_wkt", the source's CRS (empty when it had none).
  std::string sourceCrsWkt;
  /// "source": "geotransform", GDAL's six coefficients for the source raster (absent when it
  /// had no georeferencing): where grid point (x, y) of the tileset lies in sourceCrsWkt.
  std::optional<std::array<double, 6>> sourceGeoTransform;
  /// "build": "vertical_scale".
  double verticalScale = 1.0;
  /// "texture": "levels", root level first: one per level, or empty when the tileset is
  /// untextured or was written before the sizes were recorded.
  std::vector<TextureLevelSizes> textureLevels;
  /// "texture": "color": "generated" (colour made from the heights), or the file name of the
  /// image draped over the terrain; empty when untextured or not recorded.
  std::string textureColor;
  /// "texture": "snow_line" (version 6, the shade layer's generated colour): the snow line in
  /// metres at evenly spaced grid rows from row 0 to row snowLineLastRow (generated_colour.h);
  /// empty when not recorded.
  std::vector<float> snowLine;
  uint32_t snowLineLastRow = 0;
  /// "materials": required, 1..8 of them, in VIPM tilesets (header meshKind 2); empty otherwise.
  std::vector<TilesetMaterial> materials;
  /// VIPM: "build": "materials": "classification" or the categorical raster's file name.
  std::string materialsSource;
  /// "build": "morph_gap": how far a chunk's fully morphed surface may lie from its parent's,
  /// as a fraction of the parent level's error (absent: 0, the chunks refine their parents;
  /// `build --mesher greedy` lets parent edges flip within this gap).
  double morphGap = 0.0;
  /// VIPM: "build": "material_rules" (absent: true).
  bool materialRules = true;
  /// VIPM: "edits", the brush strokes applied to the source before it was built (docs/format.md
  /// "Edits"), in order; empty when there were none.
  std::vector<TerrainEdit> edits;
};

/// The tileset's source grid: its size and spacing from the header, its georeferencing from
/// the metadata.
SourceGrid sourceGridOf(const TilesetHeader& header, const TilesetMetadata& metadata);

/// "#rrggbb" for a colour (what "materials" stores).
std::string colorHex(const std::array<uint8_t, 3>& color);

/// Parses and validates `json` for a tileset with `header`; `subject` names the file in
/// errors. Refuses what is not a JSON object, and fields of the wrong type or out of range
/// (a texture size that is not 2^k + 1 in [2, 4097], a level list not one per level).
Result<TilesetMetadata> parseTilesetMetadata(std::string_view json, const TilesetHeader& header,
                                             const std::string& subject);

}  // namespace terralod
